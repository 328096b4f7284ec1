#pragma once
// The contact-law components cgdem compiles, as type lists, and the one rule that says which of their
// combinations make physical sense. The registry of compiled laws (drivers/physics_registry.cpp) is
// generated from these lists, and the scene parser refuses a combination with the same rule's reason, so
// every combination a scene can name either runs or is refused with why.
#include <string>
#include <string_view>
#include <type_traits>
#include "models/capillary_bridge.hpp"
#include "models/dmt.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/jkr_full.hpp"
#include "models/linear_eepa.hpp"
#include "models/linear_spring_dashpot.hpp"
#include "models/material_parameters.hpp"
#include "models/mindlin_tangential.hpp"
#include "models/rolling_resistance.hpp"

namespace cgdem::models {

template <class... T>
struct TypeList {};

template <class T>
struct TypeTag {
  using type = T;
};

template <class... T>
constexpr int list_size(TypeList<T...>) {
  return static_cast<int>(sizeof...(T));
}

// The I-th type of a list.
template <int I, class List>
struct TypeAtImpl;
template <int I, class T, class... Rest>
struct TypeAtImpl<I, TypeList<T, Rest...>> {
  using type = typename TypeAtImpl<I - 1, TypeList<Rest...>>::type;
};
template <class T, class... Rest>
struct TypeAtImpl<0, TypeList<T, Rest...>> {
  using type = T;
};
template <int I, class List>
using TypeAt = typename TypeAtImpl<I, List>::type;

// Calls f(TypeTag<T>{}) for every T of the list, in order.
template <class... T, class F>
void for_each_type(TypeList<T...>, F&& f) {
  (f(TypeTag<T>{}), ...);
}

using NormalLaws = TypeList<HertzTsuji, LinearSpringDashpot, JkrFull, LinearEepa>;
using AdhesionLaws = TypeList<NoAdhesion, Dmt, CapillaryBridge>;
using TangentialLaws = TypeList<MindlinTangential, NoFriction>;
using RollingLaws = TypeList<NoRolling, RollingConstantTorque, RollingSpringDashpot>;

// Calls f(TypeTag<C>{}) for every component of every list (each once: a component is in one list).
template <class F>
void for_each_component(F&& f) {
  for_each_type(NormalLaws{}, f);
  for_each_type(AdhesionLaws{}, f);
  for_each_type(TangentialLaws{}, f);
  for_each_type(RollingLaws{}, f);
}

// Calls f(TypeTag<C>{}, kind) for each component the contact spec names, kind being its key ("normal",
// "adhesion", "tangential", "rolling").
template <class F>
void for_each_chosen_component(const ContactSpec& c, F&& f) {
  const auto pick = [&](auto list, const std::string& chosen, const char* kind) {
    for_each_type(list, [&](auto tag) {
      if (chosen == decltype(tag)::type::name) f(tag, kind);
    });
  };
  pick(NormalLaws{}, c.normal, "normal");
  pick(AdhesionLaws{}, c.adhesion, "adhesion");
  pick(TangentialLaws{}, c.tangential, "tangential");
  pick(RollingLaws{}, c.rolling, "rolling");
}

// Whether the normal law of that name is spring-like (models/material_parameters.hpp): the linear
// oscillator's damping and contact time, no Rayleigh limit.
inline bool is_spring_like(const std::string& normal) {
  bool spring = false;
  for_each_type(NormalLaws{}, [&](auto tag) {
    using C = typename decltype(tag)::type;
    if (normal == C::name) spring = IsSpringLike<C>::value;
  });
  return spring;
}

// Why the components named (their YAML names, `name` of each type) make no physical sense together, or
// "" when they do.
constexpr std::string_view combination_problem(std::string_view normal, std::string_view adhesion,
                                               std::string_view tangential, std::string_view rolling) {
  if (adhesion == "dmt" && normal != "hertz")
    return normal == "jkr" || normal == "eepa"
               ? "the normal law has its own adhesion; DMT is the attraction on a Hertzian contact"
               : "DMT is the attraction on a Hertzian contact (docs/physics.md 3.4)";
  if (rolling != "none" && tangential == "none")
    return "rolling resistance needs a tangential law: without friction a particle slides instead of "
           "rolling";
  return "";
}

// The YAML name of a compiled law: normal[+adhesion][+tangential][+rolling], "none" parts left out.
inline std::string law_name(std::string_view normal, std::string_view adhesion, std::string_view tangential,
                            std::string_view rolling) {
  std::string name(normal);
  for (std::string_view part : {adhesion, tangential, rolling})
    if (part != "none") name.append("+").append(part);
  return name;
}

// Calls f(TypeTag<ContactLaw<Normal, A, T, R>>{}, name) for every combination with Normal that makes sense.
template <class Normal, class F>
void for_each_sensible_law(F&& f) {
  for_each_type(AdhesionLaws{}, [&](auto a) {
    for_each_type(TangentialLaws{}, [&](auto t) {
      for_each_type(RollingLaws{}, [&](auto r) {
        using A = typename std::decay_t<decltype(a)>::type;
        using T = typename std::decay_t<decltype(t)>::type;
        using R = typename std::decay_t<decltype(r)>::type;
        if constexpr (combination_problem(Normal::name, A::name, T::name, R::name).empty())
          f(TypeTag<ContactLaw<Normal, A, T, R>>{}, law_name(Normal::name, A::name, T::name, R::name));
      });
    });
  });
}

} // namespace cgdem::models
