#pragma once
// The host side of a contact-law component: the material parameters it reads, declared next to its
// device functor. One declaration says everything the setup needs about a parameter: its YAML key (a
// block of keys per component under materials.<name>, e.g. eepa: {k1, k2, k_adh, f0}), its valid range
// and units, how two materials' values mix into the pair's, which factor of a parameter-scaling law
// multiplies it, whether it is attractive (zeroed where adhesion is off), and which PairParameters field
// it fills. The scene parser, the pair mixing (setup/materials.cpp), the parameter scaling
// (setup/scaling.cpp) and the time-step estimate read these tables, so a new component with new
// parameters is written in its own header, the component lists, and PairParameters.
//
// A component declares, all optional:
//   static constexpr MaterialParameter material_parameters[] = {...};
//   static constexpr const char* material_block = "eepa";         // the YAML block of those keys
//   static constexpr const char* material_example = "eepa: {k1: <N/m>, ...}";
//   static const char* material_missing(const MaterialSpec&);     // what the law lacks, or nullptr
//   static MaterialProblem material_problem(const MaterialSpec&);  // a problem between two keys
//   static void finish_pair(PairParameters&);                      // defaults between keys, after mixing
// and, a normal law: `spring_like` (force linear in the overlap with stiffness `spring_stiffness(p)`: the
// linear oscillator's damping and contact time, no Rayleigh limit) or Hertz-like (E*, G*; Hertz contact
// time and damping). docs/adding_a_law.md shows a whole declaration.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include "core/scene.hpp"
#include "models/pair_parameters.hpp"

namespace cgdem::models {

// A problem between a component's keys: the key to point at, what is wrong, the fix ("" key: none).
struct MaterialProblem {
  std::string key, problem, fix;
};

// A value as messages print it (6 significant digits).
inline std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

// How the two materials' values of a parameter give the pair's.
enum class Mix {
  mean,           // (a + b) / 2: like pairs keep their own value
  geometric_mean, // sqrt(|a b|), negative when either is (pull-off forces <= 0); 0 when either is 0
  harmonic_mean,  // 2 a b / (a + b), 0 when either is 0: two half-contacts in series (EEPA stiffnesses)
  series,         // a b / (a + b) when both are given, else the given one: two springs in series
  max,
};

// Which factor of a parameter-scaling law multiplies the parameter (setup/scaling.hpp ParameterScaling).
enum class Scales { no, stiffness, pull_off };

struct MaterialParameter {
  const char* key;            // YAML key inside the component's block
  Real PairParameters::*pair; // the field of the pair it fills
  Mix mix;
  Scales scales;
  bool attractive;      // zero for pairs without adhesion (walls under contact.wall_adhesion: false)
  double default_value; // when the material does not give it
  double lowest, highest;
  bool lowest_included, highest_included;
  bool degrees;     // given in degrees in YAML, held in radians
  const char* help; // the fix for an out-of-range value: "give the loading stiffness k1 in N/m"
};

// No bound on that side of a parameter's range.
inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// The pair's value from the two materials' values.
inline double mix_values(Mix mix, double a, double b) {
  switch (mix) {
  case Mix::mean:
    return 0.5 * (a + b);
  case Mix::geometric_mean:
    return (a < 0 || b < 0 ? -1.0 : 1.0) * std::sqrt(std::fabs(a * b));
  case Mix::harmonic_mean:
    return a > 0 && b > 0 ? 2 * a * b / (a + b) : 0.0;
  case Mix::series:
    return a > 0 && b > 0 ? a * b / (a + b) : (a > b ? a : b);
  case Mix::max:
    return a > b ? a : b;
  }
  return 0;
}

// The full key of a parameter in MaterialSpec::law_parameters: "<block>.<key>".
inline std::string parameter_path(const char* block, const MaterialParameter& p) {
  return std::string(block) + "." + p.key;
}

// Detection of the optional declarations.
template <class C, class = void>
struct HasMaterialParameters : std::false_type {};
template <class C>
struct HasMaterialParameters<C, std::void_t<decltype(C::material_parameters), decltype(C::material_block)>>
    : std::true_type {};

template <class C, class = void>
struct HasMaterialMissing : std::false_type {};
template <class C>
struct HasMaterialMissing<C, std::void_t<decltype(C::material_missing(std::declval<const MaterialSpec&>()))>>
    : std::true_type {};

template <class C, class = void>
struct HasMaterialProblem : std::false_type {};
template <class C>
struct HasMaterialProblem<C, std::void_t<decltype(C::material_problem(std::declval<const MaterialSpec&>()))>>
    : std::true_type {};

template <class C, class = void>
struct HasFinishPair : std::false_type {};
template <class C>
struct HasFinishPair<C, std::void_t<decltype(C::finish_pair(std::declval<PairParameters&>()))>>
    : std::true_type {};

template <class C, class = void>
struct IsSpringLike : std::false_type {};
template <class C>
struct IsSpringLike<C, std::enable_if_t<C::spring_like>> : std::true_type {};

// Calls f(block, parameter) for each parameter component C declares.
template <class C, class F>
void for_each_material_parameter(F&& f) {
  if constexpr (HasMaterialParameters<C>::value)
    for (const MaterialParameter& p : C::material_parameters)
      f(C::material_block, p);
}

// The value of a declared parameter for material m: given, or the declaration's default.
inline double material_value(const MaterialSpec& m, const char* block, const MaterialParameter& p) {
  return m.law_parameter(parameter_path(block, p), p.default_value);
}

} // namespace cgdem::models
