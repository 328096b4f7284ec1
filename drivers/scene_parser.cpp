// Scene files: YAML -> Scene. See drivers/scene_parser.hpp and docs/scene_format.md.
#include "drivers/scene_parser.hpp"
#include "models/component_lists.hpp"

#include <yaml-cpp/yaml.h>
#include "setup/mesh_loader.hpp"
#include "setup/scaling.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace cgdem {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t subst = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, subst});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string scene_error_message(const std::string& location, const std::string& key_path,
                                const std::string& what, const std::string& fix) {
  std::string msg = location + ": ";
  if (!key_path.empty()) msg += key_path + ": ";
  msg += what;
  if (!fix.empty()) msg += "; " + fix;
  for (char& c : msg)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  return msg;
}

namespace {

// The contact-law choices are the names of the compiled components (models/component_lists.hpp).
template <class List>
std::vector<std::string> component_names(List list) {
  std::vector<std::string> out;
  models::for_each_type(list, [&](auto t) { out.emplace_back(std::decay_t<decltype(t)>::type::name); });
  return out;
}
const std::vector<std::string> kNormalLaws = component_names(models::NormalLaws{});
const std::vector<std::string> kAdhesionLaws = component_names(models::AdhesionLaws{});
const std::vector<std::string> kTangentialLaws = component_names(models::TangentialLaws{});
const std::vector<std::string> kRollingLaws = component_names(models::RollingLaws{});
const std::vector<std::string> kCoarseLaws = {
    "none",       "chen_elliott", "bond",       "cohesion", "thakur", "thakur_f0_linear", "thakur_f0_cubic",
    "hu_method1", "hu_method2",   "hu_method3", "sakai"};
const std::vector<std::string> kDistributions = {"mono", "uniform", "normal", "lognormal"};
const std::vector<std::string> kPlacements = {"lattice", "random_box", "random_cylinder", "file", "inlet"};
const std::vector<std::string> kOutletTypes = {"plane", "box"};
const std::vector<std::string> kWallTypes = {"plane", "cylinder", "cone", "mesh"};
const std::vector<std::string> kOutputFields = {"position", "velocity", "angular_velocity", "radius", "mass",
                                                "group",    "id"};

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i)
    out += (i ? sep : "") + v[i];
  return out;
}

std::string num_str(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

std::vector<std::string> split_path(const std::string& p) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : p) {
    if (c == '.') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

// The closest candidate, when it is close enough to be a plausible typo.
std::string closest(const std::string& bad, const std::vector<std::string>& valid) {
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const auto& v : valid) {
    const std::size_t d = edit_distance(bad, v);
    if (d < best_d) best_d = d, best = v;
  }
  const std::size_t limit = std::max<std::size_t>(2, std::max(bad.size(), best.size()) / 3);
  return best_d <= limit ? best : std::string();
}

std::string suggestion(const std::string& bad, const std::vector<std::string>& valid,
                       const std::string& noun) {
  const std::string c = closest(bad, valid);
  if (!c.empty()) return "did you mean '" + c + "'?";
  if (valid.empty()) return "there are no " + noun + " here";
  return "valid " + noun + ": " + join(valid);
}

std::string describe(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "nothing";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  return "a map";
}

struct Override {
  std::vector<std::string> path;
  std::string text;
};

class Ctx {
public:
  std::string source;
  std::vector<Override> overrides;

  std::string location(const std::string& key_path, const YAML::Mark& mark) const {
    const auto comps = split_path(key_path);
    for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {
      if (it->path.size() <= comps.size() && std::equal(it->path.begin(), it->path.end(), comps.begin()))
        return source + ":--set '" + it->text + "'";
    }
    if (mark.line >= 0) return source + ":" + std::to_string(mark.line + 1);
    return source;
  }
  [[noreturn]] void fail(const std::string& key_path, const YAML::Mark& mark, const std::string& what,
                         const std::string& fix) const {
    throw SceneError(scene_error_message(location(key_path, mark), key_path, what, fix));
  }
};

// A value in the tree with its key path and the best line we know for it.
struct Field {
  YAML::Node node;
  std::string path;
  YAML::Mark mark;
};

YAML::Mark mark_of(const YAML::Node& n, const YAML::Mark& fallback) {
  if (n.IsDefined()) {
    const YAML::Mark m = n.Mark();
    if (m.line >= 0) return m;
  }
  return fallback;
}

// A YAML map whose keys are checked against the keys allowed at this place.
class MapView {
public:
  MapView(const Ctx& ctx, const Field& f, const std::vector<std::string>& allowed,
          const std::string& fix_example = "")
      : ctx_(ctx), f_(f) {
    if (f.node.IsNull()) return; // "key:" with nothing: an empty map
    if (!f.node.IsMap())
      ctx.fail(f.path, f.mark, "expected a map of keys, got " + describe(f.node),
               fix_example.empty() ? "write it as 'key: value' lines indented under it" : fix_example);
    std::set<std::string> seen;
    for (auto it = f.node.begin(); it != f.node.end(); ++it) {
      const YAML::Mark km = mark_of(it->first, f.mark);
      if (!it->first.IsScalar()) ctx.fail(f.path, km, "a key is not a plain name", "use plain names as keys");
      const std::string key = it->first.Scalar();
      const std::string kp = sub(key);
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
        ctx.fail(kp, km, "unknown key '" + key + "'", suggestion(key, allowed, "keys here"));
      if (!seen.insert(key).second)
        ctx.fail(kp, km, "key '" + key + "' is given twice", "keep only one '" + key + "'");
      keys_.push_back(key);
    }
  }
  std::string sub(const std::string& key) const { return f_.path.empty() ? key : f_.path + "." + key; }
  bool has(const std::string& key) const { return std::find(keys_.begin(), keys_.end(), key) != keys_.end(); }
  Field get(const std::string& key) const {
    const YAML::Node& n = f_.node;
    YAML::Node child = has(key) ? YAML::Node(n[key]) : YAML::Node();
    Field out{child, sub(key), f_.mark};
    if (has(key)) {
      // The line of the key itself (for a block map or list below it, its first entry is on a later line).
      for (auto it = n.begin(); it != n.end(); ++it)
        if (it->first.Scalar() == key) out.mark = mark_of(it->first, mark_of(it->second, f_.mark));
    }
    return out;
  }
  Field require(const std::string& key, const std::string& fix) const {
    if (!has(key)) ctx_.fail(sub(key), f_.mark, "missing required key '" + key + "'", fix);
    Field out = get(key);
    if (out.node.IsNull()) ctx_.fail(out.path, out.mark, "'" + key + "' has no value", fix);
    return out;
  }
  const std::vector<std::string>& keys() const { return keys_; }

private:
  const Ctx& ctx_;
  Field f_;
  std::vector<std::string> keys_;
};

double as_num(const Ctx& ctx, const Field& f) {
  double v = 0;
  if (!f.node.IsScalar() || !YAML::convert<double>::decode(f.node, v))
    ctx.fail(f.path, f.mark, "expected a number, got " + describe(f.node),
             "write a plain number in SI units such as 0.001 or 1e7");
  if (!std::isfinite(v)) ctx.fail(f.path, f.mark, "must be a finite number", "write a finite number");
  return v;
}

long as_int(const Ctx& ctx, const Field& f) {
  long v = 0;
  if (f.node.IsScalar() && YAML::convert<long>::decode(f.node, v)) return v;
  double d = 0;
  if (f.node.IsScalar() && YAML::convert<double>::decode(f.node, d) && std::isfinite(d) &&
      d == std::floor(d) && std::fabs(d) < 9e15)
    return static_cast<long>(d);
  ctx.fail(f.path, f.mark, "expected a whole number, got " + describe(f.node),
           "write an integer such as 1000");
}

bool as_bool(const Ctx& ctx, const Field& f) {
  bool v = false;
  if (!f.node.IsScalar() || !YAML::convert<bool>::decode(f.node, v))
    ctx.fail(f.path, f.mark, "expected true or false, got " + describe(f.node), "write true or false");
  return v;
}

std::string as_str(const Ctx& ctx, const Field& f) {
  if (!f.node.IsScalar() || f.node.Scalar().empty())
    ctx.fail(f.path, f.mark, "expected a name or text, got " + describe(f.node), "write a plain word");
  return f.node.Scalar();
}

Field item(const Field& list, std::size_t i) {
  const YAML::Node& n = list.node;
  YAML::Node c = n[i];
  return Field{c, list.path + "." + std::to_string(i), mark_of(c, list.mark)};
}

Vec3d as_vec3(const Ctx& ctx, const Field& f) {
  if (!f.node.IsSequence() || f.node.size() != 3)
    ctx.fail(f.path, f.mark, "expected a list of three numbers, got " + describe(f.node),
             "write [x, y, z], e.g. [0, 0, -9.81]");
  Vec3d v{};
  for (std::size_t i = 0; i < 3; ++i)
    v[i] = as_num(ctx, item(f, i));
  return v;
}

std::string as_choice(const Ctx& ctx, const Field& f, const std::vector<std::string>& valid,
                      const std::string& what) {
  if (!f.node.IsScalar())
    ctx.fail(f.path, f.mark, "expected a " + what + " name, got " + describe(f.node),
             "use one of " + join(valid));
  const std::string s = f.node.Scalar();
  if (std::find(valid.begin(), valid.end(), s) == valid.end()) {
    const std::string c = closest(s, valid);
    ctx.fail(f.path, f.mark, "unknown " + what + " '" + s + "'",
             "use one of " + join(valid) + (c.empty() ? "" : " (did you mean '" + c + "'?)"));
  }
  return s;
}

void check(const Ctx& ctx, bool ok, const Field& f, const std::string& what, const std::string& fix) {
  if (!ok) ctx.fail(f.path, f.mark, what, fix);
}

// Optional readers: keep the default when the key is absent.
void opt_num(const Ctx& ctx, const MapView& m, const std::string& key, double& out) {
  if (m.has(key)) out = as_num(ctx, m.get(key));
}
void opt_bool(const Ctx& ctx, const MapView& m, const std::string& key, bool& out) {
  if (m.has(key)) out = as_bool(ctx, m.get(key));
}
void opt_vec3(const Ctx& ctx, const MapView& m, const std::string& key, Vec3d& out) {
  if (m.has(key)) out = as_vec3(ctx, m.get(key));
}

// Range checks on an optional number already read.
void positive(const Ctx& ctx, const MapView& m, const std::string& key, double v,
              const std::string& unit_fix) {
  if (m.has(key)) check(ctx, v > 0, m.get(key), key + " must be > 0 (got " + num_str(v) + ")", unit_fix);
}
void non_negative(const Ctx& ctx, const MapView& m, const std::string& key, double v,
                  const std::string& fix) {
  if (m.has(key)) check(ctx, v >= 0, m.get(key), key + " must be >= 0 (got " + num_str(v) + ")", fix);
}

// A component parameter's declared range (models/material_parameters.hpp).
bool within_range(const models::MaterialParameter& d, double v) {
  const bool above = d.lowest_included ? v >= d.lowest : v > d.lowest;
  const bool below = d.highest_included ? v <= d.highest : v < d.highest;
  return above && below;
}
std::string out_of_range(const models::MaterialParameter& d, double v) {
  const std::string key = d.key, got = " (got " + num_str(v) + ")";
  if (std::isinf(d.highest))
    return key + " must be " + (d.lowest_included ? ">= " : "> ") + num_str(d.lowest) + got;
  if (std::isinf(d.lowest))
    return key + " must be " + (d.highest_included ? "<= " : "< ") + num_str(d.highest) + got;
  return key + " " + num_str(v) + " is outside " + (d.lowest_included ? "[" : "(") + num_str(d.lowest) +
         ", " + num_str(d.highest) + (d.highest_included ? "]" : ")");
}

double norm(const Vec3d& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

const char* kAxis[3] = {"x", "y", "z"};
constexpr double kPi = 3.14159265358979323846;

struct Parser {
  Ctx ctx;
  std::filesystem::path base_dir;
  Scene scene;
  std::map<std::string, Field> material_fields; // for cross-checks
  YAML::Mark coarse_law_mark; // group 0's coarse_grain.law, for errors about the scene's law

  std::vector<std::string> material_names() const {
    std::vector<std::string> out;
    for (const auto& m : scene.materials)
      out.push_back(m.name);
    return out;
  }

  std::string material_ref(const Field& f) {
    const std::string name = as_str(ctx, f);
    if (scene.material_index(name) < 0)
      ctx.fail(f.path, f.mark, "material '" + name + "' is not defined under materials",
               scene.materials.empty()
                   ? "define it under materials"
                   : suggestion(name, material_names(), "materials") + " (or define it under materials)");
    return name;
  }

  void parse_domain(const Field& f) {
    MapView m(ctx, f, {"lo", "hi", "periodic"});
    DomainSpec& d = scene.domain;
    d.lo = as_vec3(ctx, m.require("lo", "give the lower corner, e.g. lo: [0, 0, 0] (m)"));
    const Field hi = m.require("hi", "give the upper corner, e.g. hi: [0.02, 0.02, 0.04] (m)");
    d.hi = as_vec3(ctx, hi);
    for (int a = 0; a < 3; ++a)
      check(ctx, d.hi[a] > d.lo[a], hi,
            std::string("domain hi ") + kAxis[a] + " = " + num_str(d.hi[a]) + " is not above lo " + kAxis[a] +
                " = " + num_str(d.lo[a]),
            "make every component of hi larger than lo");
    if (m.has("periodic")) {
      const Field p = m.get("periodic");
      if (!p.node.IsSequence() || p.node.size() != 3)
        ctx.fail(p.path, p.mark, "expected a list of three booleans, got " + describe(p.node),
                 "write e.g. periodic: [true, true, false] (x, y, z)");
      for (std::size_t a = 0; a < 3; ++a)
        d.periodic[a] = as_bool(ctx, item(p, a));
    }
  }

  void parse_material(const std::string& name, const Field& f) {
    std::vector<std::string> keys{"density",  "youngs_modulus",   "poisson_ratio", "restitution",
                                  "friction", "rolling_friction", "surface_energy"};
    models::for_each_component([&](auto component) {
      using C = typename decltype(component)::type;
      if constexpr (models::HasMaterialParameters<C>::value) keys.push_back(C::material_block);
    });
    MapView m(ctx, f, keys);
    MaterialSpec s;
    s.name = name;
    opt_num(ctx, m, "density", s.density);
    positive(ctx, m, "density", s.density, "give the particle density in kg/m^3, e.g. 2500");
    opt_num(ctx, m, "youngs_modulus", s.youngs_modulus);
    positive(ctx, m, "youngs_modulus", s.youngs_modulus, "give Young's modulus in Pa, e.g. 5e6");
    opt_num(ctx, m, "poisson_ratio", s.poisson_ratio);
    if (m.has("poisson_ratio"))
      check(ctx, s.poisson_ratio > -1 && s.poisson_ratio < 0.5, m.get("poisson_ratio"),
            "Poisson ratio " + num_str(s.poisson_ratio) + " is outside (-1, 0.5)",
            "use a value between -1 and 0.5 (exclusive), typically 0.2-0.35");
    opt_num(ctx, m, "restitution", s.restitution);
    if (m.has("restitution"))
      check(ctx, s.restitution > 0 && s.restitution <= 1, m.get("restitution"),
            "restitution " + num_str(s.restitution) + " is outside (0, 1]",
            "use a coefficient of restitution above 0 and at most 1 (1 = elastic)");
    opt_num(ctx, m, "friction", s.friction);
    non_negative(ctx, m, "friction", s.friction, "use a sliding friction coefficient >= 0, e.g. 0.5");
    opt_num(ctx, m, "rolling_friction", s.rolling_friction);
    non_negative(ctx, m, "rolling_friction", s.rolling_friction, "use a rolling friction coefficient >= 0");
    opt_num(ctx, m, "surface_energy", s.surface_energy);
    non_negative(ctx, m, "surface_energy", s.surface_energy, "use a surface energy >= 0 in J/m^2");
    // Each component's block of keys, as the component declares them (models/material_parameters.hpp).
    models::for_each_component([&](auto component) {
      using C = typename decltype(component)::type;
      if constexpr (models::HasMaterialParameters<C>::value) {
        if (!m.has(C::material_block)) return;
        std::vector<std::string> block_keys;
        for (const models::MaterialParameter& d : C::material_parameters)
          block_keys.push_back(d.key);
        MapView block(ctx, m.get(C::material_block), block_keys);
        for (const models::MaterialParameter& d : C::material_parameters)
          if (block.has(d.key)) {
            const double v = as_num(ctx, block.get(d.key));
            check(ctx, within_range(d, v), block.get(d.key), out_of_range(d, v), d.help);
            s.law_parameters[models::parameter_path(C::material_block, d)] = d.degrees ? v * kPi / 180.0 : v;
          }
        if constexpr (models::HasMaterialProblem<C>::value) {
          const models::MaterialProblem problem = C::material_problem(s);
          check(ctx, problem.key.empty(), block.get(problem.key), problem.problem, problem.fix);
        }
      }
    });
    scene.materials.push_back(s);
    material_fields[name] = f;
  }

  void parse_materials(const Field& f) {
    if (!f.node.IsMap() || f.node.size() == 0)
      ctx.fail(f.path, f.mark, "expected a map of named materials, got " + describe(f.node),
               "write materials: {glass: {density: 2500, youngs_modulus: 5e6}}");
    for (auto it = f.node.begin(); it != f.node.end(); ++it) {
      const std::string name = it->first.Scalar();
      const Field mf{it->second, "materials." + name, mark_of(it->first, mark_of(it->second, f.mark))};
      if (scene.material_index(name) >= 0)
        ctx.fail(mf.path, mark_of(it->first, f.mark), "material '" + name + "' is defined twice",
                 "rename or remove one");
      parse_material(name, mf);
    }
  }

  void parse_contact(const Field& f) {
    MapView m(ctx, f,
              {"normal", "adhesion", "tangential", "rolling", "wall_adhesion", "jkr_separation", "lever_arm",
               "damping", "restitution_speed_ratio"});
    ContactSpec& c = scene.contact;
    if (m.has("normal")) c.normal = as_choice(ctx, m.get("normal"), kNormalLaws, "normal law");
    if (m.has("adhesion") && m.get("adhesion").node.IsScalar() &&
        m.get("adhesion").node.Scalar() == "jkr_simplified")
      ctx.fail(
          m.sub("adhesion"), m.get("adhesion").mark,
          "adhesion 'jkr_simplified' is Hu's JKR, which is the full JKR curve while the surfaces overlap",
          "use normal: jkr with jkr_separation: contact_loss (and adhesion: none)");
    if (m.has("adhesion")) c.adhesion = as_choice(ctx, m.get("adhesion"), kAdhesionLaws, "adhesion law");
    if (m.has("tangential"))
      c.tangential = as_choice(ctx, m.get("tangential"), kTangentialLaws, "tangential law");
    if (m.has("rolling")) c.rolling = as_choice(ctx, m.get("rolling"), kRollingLaws, "rolling law");
    opt_bool(ctx, m, "wall_adhesion", c.wall_adhesion);
    if (m.has("jkr_separation"))
      c.jkr_separation = as_choice(ctx, m.get("jkr_separation"), {"delta_s", "pull_off", "contact_loss"},
                                   "JKR separation rule");
    if (m.has("lever_arm"))
      c.lever_arm = as_choice(ctx, m.get("lever_arm"), {"auto", "contact_point", "radius"}, "lever arm");
    if (m.has("damping"))
      c.damping = as_choice(ctx, m.get("damping"), {"restitution", "beta_formula"}, "damping rule");
    opt_num(ctx, m, "restitution_speed_ratio", c.restitution_speed_ratio);
    if (m.has("restitution_speed_ratio"))
      check(ctx, c.restitution_speed_ratio > 1 && c.restitution_speed_ratio < 1e6,
            m.get("restitution_speed_ratio"),
            "restitution_speed_ratio must be > 1 and < 1e6 (got " + num_str(c.restitution_speed_ratio) +
                "): below the sticking velocity an adhesive pair does not rebound",
            "give the impact speed in sticking velocities at which JKR/DMT pairs rebound with e, e.g. 20");
    const std::string_view problem =
        models::combination_problem(c.normal, c.adhesion, c.tangential, c.rolling);
    if (!problem.empty() && c.adhesion == "dmt")
      ctx.fail(m.sub("adhesion"), m.get("adhesion").mark,
               "adhesion 'dmt' cannot be combined with normal law '" + c.normal +
                   "': " + std::string(problem),
               "use adhesion: none (or capillary) with normal: " + c.normal + ", or normal: hertz with dmt");
    if (!problem.empty())
      ctx.fail(m.sub("rolling"), m.get("rolling").mark,
               "rolling '" + c.rolling + "' cannot be combined with tangential '" + c.tangential +
                   "': " + std::string(problem),
               "add tangential: mindlin, or set rolling: none");
  }

  void parse_pairs(const Field& f) {
    if (!f.node.IsSequence())
      ctx.fail(f.path, f.mark, "expected a list of material pairs, got " + describe(f.node),
               "write pairs: [{materials: [glass, steel], friction: 0.3}]");
    std::set<std::pair<std::string, std::string>> seen;
    for (std::size_t i = 0; i < f.node.size(); ++i) {
      const Field pf = item(f, i);
      MapView m(ctx, pf, {"materials", "restitution", "friction", "rolling_friction", "surface_energy"});
      PairOverrideSpec p;
      const Field mats = m.require("materials", "name the two materials, e.g. materials: [glass, steel]");
      if (!mats.node.IsSequence() || mats.node.size() != 2)
        ctx.fail(mats.path, mats.mark, "expected a list of two material names, got " + describe(mats.node),
                 "write materials: [a, b]");
      p.material_a = material_ref(item(mats, 0));
      p.material_b = material_ref(item(mats, 1));
      auto key = std::minmax(p.material_a, p.material_b);
      if (!seen.insert({key.first, key.second}).second)
        ctx.fail(mats.path, mats.mark, "pair " + p.material_a + "-" + p.material_b + " is given twice",
                 "merge the two entries");
      opt_num(ctx, m, "restitution", p.restitution);
      if (m.has("restitution"))
        check(ctx, p.restitution > 0 && p.restitution <= 1, m.get("restitution"),
              "restitution " + num_str(p.restitution) + " is outside (0, 1]",
              "use a value above 0 and at most 1");
      opt_num(ctx, m, "friction", p.friction);
      non_negative(ctx, m, "friction", p.friction, "use a sliding friction coefficient >= 0");
      opt_num(ctx, m, "rolling_friction", p.rolling_friction);
      non_negative(ctx, m, "rolling_friction", p.rolling_friction, "use a rolling friction coefficient >= 0");
      opt_num(ctx, m, "surface_energy", p.surface_energy);
      non_negative(ctx, m, "surface_energy", p.surface_energy, "use a surface energy >= 0 in J/m^2");
      scene.pair_overrides.push_back(p);
    }
  }

  void parse_size(const Field& f, SizeSpec& s) {
    MapView m(ctx, f, {"radius", "distribution", "min", "max", "mean", "std"},
              "write size: {radius: 0.0005} or size: {distribution: uniform, min: 0.0004, max: 0.0006}");
    if (m.has("distribution"))
      s.distribution = as_choice(ctx, m.get("distribution"), kDistributions, "size distribution");
    else if (m.has("radius"))
      s.distribution = "mono";
    else
      ctx.fail(m.sub("radius"), f.mark, "missing required key 'radius' (or 'distribution')",
               "give radius: <m> for equal spheres, or distribution: uniform|normal|lognormal with its "
               "parameters");
    std::vector<std::string> allowed;
    if (s.distribution == "mono") allowed = {"distribution", "radius"};
    if (s.distribution == "uniform") allowed = {"distribution", "min", "max"};
    if (s.distribution == "normal" || s.distribution == "lognormal")
      allowed = {"distribution", "mean", "std", "min", "max"};
    for (const auto& k : m.keys())
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
        ctx.fail(m.sub(k), m.get(k).mark,
                 "key '" + k + "' does not apply to a " + s.distribution + " distribution",
                 "remove it (keys for " + s.distribution + ": " + join(allowed) + ")");
    auto radius_like = [&](const std::string& key, double& out, bool required) {
      if (required)
        m.require(key, "give " + key + " (radius in m) for a " + s.distribution + " distribution");
      if (!m.has(key)) return;
      out = as_num(ctx, m.get(key));
      check(ctx, out > 0, m.get(key), key + " must be > 0 (got " + num_str(out) + ")",
            "give a positive radius in metres, e.g. 0.0005");
    };
    if (s.distribution == "mono") radius_like("radius", s.radius, true);
    if (s.distribution == "uniform") {
      radius_like("min", s.min_radius, true);
      radius_like("max", s.max_radius, true);
      check(ctx, s.max_radius > s.min_radius, m.get("max"),
            "max " + num_str(s.max_radius) + " is not above min " + num_str(s.min_radius),
            "make max > min (for equal sizes use radius: instead)");
    }
    if (s.distribution == "normal" || s.distribution == "lognormal") {
      radius_like("mean", s.mean_radius, true);
      m.require("std", "give the standard deviation of the radius in m");
      s.std_radius = as_num(ctx, m.get("std"));
      check(ctx, s.std_radius >= 0, m.get("std"), "std must be >= 0 (got " + num_str(s.std_radius) + ")",
            "give the standard deviation of the radius in m");
      radius_like("min", s.min_radius, false);
      radius_like("max", s.max_radius, false);
      if (m.has("min") && m.has("max"))
        check(ctx, s.max_radius > s.min_radius, m.get("max"),
              "max " + num_str(s.max_radius) + " is not above min " + num_str(s.min_radius),
              "make max > min");
    }
  }

  void check_box_in_domain(const Field& f, const Vec3d& lo, const Vec3d& hi, const std::string& what) {
    const DomainSpec& d = scene.domain;
    const double tol = 1e-12;
    for (int a = 0; a < 3; ++a) {
      const double L = d.hi[a] - d.lo[a];
      if (lo[a] < d.lo[a] - tol * L || hi[a] > d.hi[a] + tol * L)
        ctx.fail(f.path, f.mark,
                 what + " reaches outside the domain in " + kAxis[a] + " ([" + num_str(lo[a]) + ", " +
                     num_str(hi[a]) + "] vs domain [" + num_str(d.lo[a]) + ", " + num_str(d.hi[a]) + "])",
                 "shrink the region or enlarge domain.lo/hi");
    }
  }

  void parse_placement(const Field& f, GroupSpec& g, std::size_t index) {
    MapView m(ctx, f,
              {"type", "lo", "hi", "center", "axis", "radius", "height", "spacing", "seed", "file", "rate",
               "mass_rate", "start", "every"},
              "write placement: {type: random_box, lo: [..], hi: [..]}");
    PlacementSpec& p = g.placement;
    p.kind = as_choice(ctx, m.require("type", "give type: " + join(kPlacements, " | ")), kPlacements,
                       "placement type");
    std::vector<std::string> allowed;
    if (p.kind == "lattice") allowed = {"type", "lo", "hi", "spacing", "seed"};
    if (p.kind == "random_box") allowed = {"type", "lo", "hi", "seed"};
    if (p.kind == "random_cylinder") allowed = {"type", "center", "axis", "radius", "height", "seed"};
    if (p.kind == "file") allowed = {"type", "file", "seed"};
    if (p.kind == "inlet") allowed = {"type", "lo", "hi", "seed", "rate", "mass_rate", "start", "every"};
    for (const auto& k : m.keys())
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
        ctx.fail(m.sub(k), m.get(k).mark, "key '" + k + "' does not apply to placement type " + p.kind,
                 "remove it (keys for " + p.kind + ": " + join(allowed) + ")");
    p.seed = index + 1;
    if (m.has("seed")) {
      const long s = as_int(ctx, m.get("seed"));
      check(ctx, s >= 0, m.get("seed"), "seed must be >= 0", "give a non-negative integer seed");
      p.seed = static_cast<std::uint64_t>(s);
    }
    if (p.kind == "lattice" || p.kind == "random_box" || p.kind == "inlet") {
      p.lo = scene.domain.lo;
      p.hi = scene.domain.hi;
      opt_vec3(ctx, m, "lo", p.lo);
      opt_vec3(ctx, m, "hi", p.hi);
      const Field hf = m.has("hi") ? m.get("hi") : f;
      for (int a = 0; a < 3; ++a)
        check(ctx, p.hi[a] > p.lo[a], hf,
              std::string("placement hi ") + kAxis[a] + " = " + num_str(p.hi[a]) + " is not above lo " +
                  kAxis[a] + " = " + num_str(p.lo[a]),
              "make every component of hi larger than lo");
      check_box_in_domain(hf, p.lo, p.hi, "the placement box");
      if (m.has("spacing")) {
        p.spacing = as_num(ctx, m.get("spacing"));
        check(ctx, p.spacing > 0, m.get("spacing"), "spacing must be > 0 (got " + num_str(p.spacing) + ")",
              "give the lattice spacing in m, or leave it out (1.05 x the largest diameter)");
      }
    }
    if (p.kind == "random_cylinder") {
      p.center =
          as_vec3(ctx, m.require("center", "give the centre of the cylinder's base, e.g. [0, 0, 0.001]"));
      const Field rf = m.require("radius", "give the cylinder radius in m");
      p.cylinder_radius = as_num(ctx, rf);
      check(ctx, p.cylinder_radius > 0, rf, "radius must be > 0 (got " + num_str(p.cylinder_radius) + ")",
            "give the cylinder radius in m");
      const Field hf = m.require("height", "give the cylinder height in m (along its axis)");
      p.cylinder_height = as_num(ctx, hf);
      check(ctx, p.cylinder_height > 0, hf, "height must be > 0 (got " + num_str(p.cylinder_height) + ")",
            "give the cylinder height in m");
      if (m.has("axis")) {
        p.axis = as_vec3(ctx, m.get("axis"));
        const double n = norm(p.axis);
        check(ctx, n > 0, m.get("axis"), "axis is the zero vector", "give a direction, e.g. [0, 1, 0]");
        for (double& c : p.axis)
          c /= n;
      }
      // Bounding box: the two end disks, each reaching R sqrt(1 - a_i^2) from its centre along axis i.
      Vec3d lo{}, hi{};
      for (int i = 0; i < 3; ++i) {
        const double top = p.center[i] + p.cylinder_height * p.axis[i];
        const double reach = p.cylinder_radius * std::sqrt(std::max(0.0, 1 - p.axis[i] * p.axis[i]));
        lo[i] = std::min(p.center[i], top) - reach;
        hi[i] = std::max(p.center[i], top) + reach;
      }
      check_box_in_domain(rf, lo, hi, "the placement cylinder");
    }
    if (p.kind == "inlet") {
      if (m.has("rate") == m.has("mass_rate"))
        ctx.fail(f.path, f.mark,
                 m.has("rate") ? "both rate and mass_rate are given" : "the inlet has no rate",
                 "give rate (particles/s) or mass_rate (kg/s), one of them");
      const char* key = m.has("rate") ? "rate" : "mass_rate";
      double& v = m.has("rate") ? p.rate : p.mass_rate;
      v = as_num(ctx, m.get(key));
      check(ctx, v > 0, m.get(key), std::string(key) + " must be > 0 (got " + num_str(v) + ")",
            m.has("rate") ? "give particles per second" : "give kg per second");
      opt_num(ctx, m, "start", p.start);
      non_negative(ctx, m, "start", p.start, "give the time the inlet opens in s, >= 0");
      opt_num(ctx, m, "every", p.every);
      positive(ctx, m, "every", p.every, "give the time between insertions in s");
    }
    if (p.kind == "file") {
      const Field ff =
          m.require("file", "give the particle file (CSV id,x,y,z,radius[,density] or cgdem HDF5)");
      std::filesystem::path path(as_str(ctx, ff));
      if (path.is_relative() && !base_dir.empty()) path = (base_dir / path).lexically_normal();
      p.file = path.string();
      std::ifstream in(p.file);
      if (!in)
        ctx.fail(ff.path, ff.mark, "cannot read particle file '" + p.file + "'",
                 "check the path (a relative path is taken from the scene file's directory)");
    }
  }

  void parse_group(const Field& f, std::size_t index) {
    MapView m(
        ctx, f,
        {"name", "material", "count", "size", "placement", "velocity", "velocity_random", "coarse_grain"});
    GroupSpec g;
    g.source_location = ctx.location(f.path, f.mark);
    g.name = m.has("name") ? as_str(ctx, m.get("name")) : "group" + std::to_string(index);
    for (const auto& other : scene.groups)
      if (other.name == g.name)
        ctx.fail(m.sub("name"), m.get("name").mark, "group name '" + g.name + "' is used twice",
                 "give every group its own name");
    g.material =
        material_ref(m.require("material", "name the group's material, one of: " + join(material_names())));
    parse_placement(
        m.require("placement", "give placement: {type: lattice|random_box|random_cylinder|file|inlet, ...}"),
        g, index);
    const bool from_file = g.placement.kind == "file";
    if (from_file) {
      if (m.has("size"))
        ctx.fail(m.sub("size"), m.get("size").mark, "size does not apply to file placement",
                 "remove size (the radii come from the file)");
      if (m.has("count")) {
        g.count = as_int(ctx, m.get("count"));
        check(ctx, g.count >= 0, m.get("count"), "count must be >= 0 (got " + std::to_string(g.count) + ")",
              "give 0 (or leave it out) for all particles of the file, or how many to take");
      }
    } else {
      const Field cf = m.require("count", "give the number of particles, e.g. count: 1000");
      g.count = as_int(ctx, cf);
      check(ctx, g.count > 0, cf, "count must be > 0 (got " + std::to_string(g.count) + ")",
            "give the number of particles to place");
      parse_size(m.require("size", "give size: {radius: <m>} or a distribution"), g.size);
    }
    opt_vec3(ctx, m, "velocity", g.velocity);
    opt_num(ctx, m, "velocity_random", g.velocity_random);
    non_negative(ctx, m, "velocity_random", g.velocity_random, "give a speed >= 0 in m/s");
    if (m.has("coarse_grain")) {
      MapView c(ctx, m.get("coarse_grain"), {"law", "factor", "torque_power", "surface_energy_power"});
      const Field lf = c.require("law", "give law: " + join(kCoarseLaws, " | "));
      g.coarse_grain.law = as_choice(ctx, lf, kCoarseLaws, "coarse_grain law");
      if (index == 0) coarse_law_mark = lf.mark;
      if (c.has("factor")) {
        g.coarse_grain.factor = as_num(ctx, c.get("factor"));
        check(ctx, g.coarse_grain.factor >= 1, c.get("factor"),
              "coarse_grain factor " + num_str(g.coarse_grain.factor) + " is below 1",
              "give the ratio coarse/original diameter, >= 1");
        if (g.coarse_grain.law == "none" && g.coarse_grain.factor != 1)
          ctx.fail(c.sub("factor"), c.get("factor").mark,
                   "coarse_grain factor " + num_str(g.coarse_grain.factor) + " has no effect with law none",
                   "choose a law (" + join(kCoarseLaws) + ") or remove factor");
      } else if (g.coarse_grain.law != "none") {
        c.require("factor", "give factor: <coarse diameter / original diameter>, >= 1");
      }
      if (c.has("torque_power")) {
        if (g.coarse_grain.law != "hu_method1")
          ctx.fail(c.sub("torque_power"), c.get("torque_power").mark,
                   "torque_power applies to hu_method1 only (law is " + g.coarse_grain.law + ")",
                   "remove torque_power");
        g.coarse_grain.torque_power = as_int(ctx, c.get("torque_power"));
        check(ctx, g.coarse_grain.torque_power == 2 || g.coarse_grain.torque_power == 3,
              c.get("torque_power"),
              "torque_power " + std::to_string(g.coarse_grain.torque_power) + " is not 2 or 3",
              "use 2 (Hu eq 30, M_S = l^2 M_O) or 3 (rotational similarity, M_S = l^3 M_O)");
      }
      if (c.has("surface_energy_power")) {
        const std::string& law = g.coarse_grain.law;
        if (!scales_surface_energy(scaling_law(law)))
          ctx.fail(c.sub("surface_energy_power"), c.get("surface_energy_power").mark,
                   "surface_energy_power applies to the laws that scale the surface energy (chen_elliott, "
                   "bond, cohesion), not to " +
                       law,
                   "remove surface_energy_power");
        g.coarse_grain.surface_energy_power = as_num(ctx, c.get("surface_energy_power"));
        check(ctx, g.coarse_grain.surface_energy_power >= 0 && g.coarse_grain.surface_energy_power <= 3,
              c.get("surface_energy_power"),
              "surface_energy_power " + num_str(g.coarse_grain.surface_energy_power) + " is outside 0-3",
              "give the exponent p of gamma ~ k^p, e.g. 1 to keep the pull-off force per cross-section");
      }
    }
    if (!from_file && g.placement.kind == "lattice" && g.placement.spacing > 0) {
      const double rmax = g.size.distribution == "mono" ? g.size.radius : g.size.max_radius;
      const double factor = g.coarse_grain.law == "none" ? 1.0 : g.coarse_grain.factor;
      if (rmax > 0 && g.placement.spacing < 2 * rmax * factor)
        ctx.fail(m.sub("placement.spacing"), m.get("placement").mark,
                 "lattice spacing " + num_str(g.placement.spacing) + " is below the largest diameter " +
                     num_str(2 * rmax * factor),
                 "use a spacing of at least the largest particle diameter, or leave it out");
    }
    scene.groups.push_back(g);
  }

  void parse_groups(const Field& f) {
    if (!f.node.IsSequence() || f.node.size() == 0)
      ctx.fail(f.path, f.mark, "expected a list of particle groups, got " + describe(f.node),
               "write groups: as a list of '- name: ...' entries");
    for (std::size_t i = 0; i < f.node.size(); ++i)
      parse_group(item(f, i), i);
    const std::string& law = scene.groups[0].coarse_grain.law;
    for (std::size_t i = 1; i < scene.groups.size(); ++i)
      if (scene.groups[i].coarse_grain.law != law)
        ctx.fail("groups." + std::to_string(i) + ".coarse_grain.law", item(f, i).mark,
                 "coarse_grain law '" + scene.groups[i].coarse_grain.law + "' differs from group 0's '" +
                     law + "'",
                 "use one scaling law for the whole scene");
    // The law's options are the scene's, like the law: every group gives group 0's.
    const auto same_option = [&](const std::string& key, auto of) {
      for (std::size_t i = 1; i < scene.groups.size(); ++i)
        if (of(scene.groups[i].coarse_grain) != of(scene.groups[0].coarse_grain))
          ctx.fail("groups." + std::to_string(i) + ".coarse_grain." + key, item(f, i).mark,
                   "coarse_grain " + key + " differs from group 0's",
                   "use one " + key + " for the whole scene");
    };
    same_option("torque_power", [](const CoarseGrainSpec& c) { return double(c.torque_power); });
    same_option("surface_energy_power", [](const CoarseGrainSpec& c) { return c.surface_energy_power; });
  }

  // until_force (N): the segment ends once the particles' force on the wall against its velocity reaches
  // this value (a stress target times the loaded area).
  void parse_until_force(MapView& m, const Vec3d& velocity, double& until_force) {
    if (!m.has("until_force")) return;
    until_force = as_num(ctx, m.get("until_force"));
    check(ctx, until_force > 0, m.get("until_force"), "until_force must be > 0 (N)",
          "give the force in N at which the segment ends (a target stress x the loaded area)");
    check(ctx, velocity[0] != 0 || velocity[1] != 0 || velocity[2] != 0, m.get("until_force"),
          "until_force needs the segment's velocity: the force is measured against the motion",
          "give the segment a velocity (e.g. velocity: [0, 0, -0.02]) or remove until_force");
  }

  // motion.oscillation: a vibrated container (Thakur et al. vibrate their cohesionless beds at 60 Hz and
  // 1.5 mm to one porosity whatever the particle size).
  void parse_oscillation(const Field& f, WallSpec::Oscillation& o) {
    MapView m(ctx, f, {"amplitude", "frequency", "direction", "start", "stop"});
    o.amplitude = as_num(ctx, m.require("amplitude", "give the oscillation's amplitude in m"));
    positive(ctx, m, "amplitude", o.amplitude, "give the amplitude in m, > 0");
    o.frequency = as_num(ctx, m.require("frequency", "give the oscillation's frequency in Hz"));
    positive(ctx, m, "frequency", o.frequency, "give the frequency in Hz, > 0");
    opt_vec3(ctx, m, "direction", o.direction);
    const double len = std::sqrt(o.direction[0] * o.direction[0] + o.direction[1] * o.direction[1] +
                                 o.direction[2] * o.direction[2]);
    check(ctx, len > 0, m.has("direction") ? m.get("direction") : f, "direction is zero",
          "give the direction of the oscillation, e.g. [0, 0, 1]");
    for (int a = 0; a < 3; ++a)
      o.direction[a] /= len;
    parse_window(m, o.start, o.stop, "oscillates until the end");
  }

  // A motion's optional window [start, stop): start >= 0, stop after start; `open_end` says what leaving
  // stop out means.
  void parse_window(const MapView& m, double& start, double& stop, const std::string& open_end) {
    opt_num(ctx, m, "start", start);
    non_negative(ctx, m, "start", start, "give the start time in s, >= 0");
    opt_num(ctx, m, "stop", stop);
    if (m.has("stop"))
      check(ctx, stop > start, m.get("stop"),
            "stop " + num_str(stop) + " is not after start " + num_str(start),
            "make stop later than start (or leave it out: " + open_end + ")");
  }

  void parse_motion(const Field& f, WallSpec& w) {
    MapView m(ctx, f,
              {"velocity", "angular_velocity", "rpm", "start", "stop", "until_force", "then", "oscillation"});
    opt_vec3(ctx, m, "velocity", w.velocity);
    if (m.has("angular_velocity") && m.has("rpm"))
      ctx.fail(m.sub("rpm"), m.get("rpm").mark, "both angular_velocity and rpm are given",
               "give only one (angular_velocity in rad/s or rpm in revolutions per minute)");
    opt_num(ctx, m, "angular_velocity", w.angular_velocity);
    if (m.has("rpm")) w.angular_velocity = as_num(ctx, m.get("rpm")) * 2 * kPi / 60.0;
    parse_window(m, w.motion_start, w.motion_stop, "moves until the end");
    parse_until_force(m, w.velocity, w.motion_until_force);
    if (m.has("oscillation")) parse_oscillation(m.get("oscillation"), w.oscillation);
    if (m.has("then")) {
      const Field list = m.get("then");
      if (!list.node.IsSequence() || list.node.size() > WallSpec::kMaxThen)
        ctx.fail(list.path, list.mark,
                 "expected a list of up to " + std::to_string(WallSpec::kMaxThen) + " motion segments, got " +
                     describe(list.node),
                 "write then: [{velocity: [0, 0, -0.005], start: 0.3, stop: 0.5}]");
      for (std::size_t i = 0; i < list.node.size(); ++i) {
        MapView s(ctx, item(list, i), {"velocity", "start", "stop", "until_force"});
        WallSpec::Segment seg;
        opt_vec3(ctx, s, "velocity", seg.velocity);
        seg.start = as_num(ctx, s.require("start", "give the segment's start time in s"));
        seg.stop = as_num(ctx, s.require("stop", "give the segment's stop time in s"));
        non_negative(ctx, s, "start", seg.start, "give the start time in s, >= 0");
        check(ctx, seg.stop > seg.start, s.get("stop"),
              "stop " + num_str(seg.stop) + " is not after start " + num_str(seg.start),
              "make stop later than start");
        parse_until_force(s, seg.velocity, seg.until_force);
        w.then.push_back(seg);
      }
    }
  }

  // A mesh wall's file, read and placed now, so that an unreadable or unusable mesh is a scene error
  // naming its key.
  void parse_mesh(MapView& m, WallSpec& w) {
    const Field ff =
        m.require("file", "give the mesh file (STL, OBJ, PLY; relative to the scene's directory)");
    w.file = as_str(ctx, ff);
    std::filesystem::path path(w.file);
    if (path.is_relative() && !base_dir.empty()) path = (base_dir / path).lexically_normal();
    w.file_path = path.string();
    if (m.has("scale")) {
      w.scale = as_num(ctx, m.get("scale"));
      check(ctx, w.scale > 0, m.get("scale"), "scale must be > 0 (got " + num_str(w.scale) + ")",
            "give the factor from the file's units to metres, e.g. 0.001 for a file in mm");
    }
    opt_vec3(ctx, m, "rotate", w.rotate);
    opt_vec3(ctx, m, "translate", w.translate);
    if (!std::ifstream(w.file_path))
      ctx.fail(ff.path, ff.mark, "cannot read mesh file '" + w.file_path + "'",
               "check the path (a relative path is taken from the scene file's directory)");
    TriangleMeshData mesh;
    try {
      mesh = load_triangle_mesh(w.file_path, w.scale, w.rotate, w.translate);
    } catch (const std::runtime_error& e) {
      ctx.fail(ff.path, ff.mark, e.what(),
               "export the part as a triangle mesh (binary or ASCII STL, OBJ, PLY)");
    }
    const std::string problem = mesh_problem(mesh);
    if (!problem.empty())
      ctx.fail(ff.path, ff.mark, "mesh '" + w.file + "': " + problem,
               "repair the mesh (remove zero-area triangles) before export");
    const DomainSpec& d = scene.domain;
    for (int a = 0; a < 3; ++a) {
      const double slack = 1e-9 * (d.hi[a] - d.lo[a]);
      if (mesh.lo[a] < d.lo[a] - slack || mesh.hi[a] > d.hi[a] + slack)
        ctx.fail(ff.path, ff.mark,
                 "mesh '" + w.file + "' spans " + "xyz"[a] + " in [" + num_str(mesh.lo[a]) + ", " +
                     num_str(mesh.hi[a]) + "] m, outside the domain's [" + num_str(d.lo[a]) + ", " +
                     num_str(d.hi[a]) + "] m",
                 "place it inside with scale/rotate/translate (scale 0.001 for a file in mm) or enlarge "
                 "domain.lo/hi");
    }
    w.mesh = std::make_shared<const TriangleMeshData>(std::move(mesh));
  }

  void parse_walls(const Field& f) {
    if (f.node.IsNull()) return;
    if (!f.node.IsSequence())
      ctx.fail(f.path, f.mark, "expected a list of walls, got " + describe(f.node),
               "write walls: as a list of '- name: ...' entries");
    for (std::size_t i = 0; i < f.node.size(); ++i) {
      const Field wf = item(f, i);
      MapView m(ctx, wf,
                {"name", "type", "material", "point", "normal", "axis", "radius", "end_radius", "length",
                 "size", "edge", "orifice", "caps", "motion", "file", "scale", "rotate", "translate"});
      WallSpec w;
      w.name = m.has("name") ? as_str(ctx, m.get("name")) : "wall" + std::to_string(i);
      for (const auto& other : scene.walls)
        if (other.name == w.name)
          ctx.fail(m.sub("name"), m.get("name").mark, "wall name '" + w.name + "' is used twice",
                   "give every wall its own name");
      if (m.has("type")) w.type = as_choice(ctx, m.get("type"), kWallTypes, "wall type");
      std::vector<std::string> allowed = {"name", "type", "material", "point", "motion"};
      if (w.type == "plane") allowed.insert(allowed.end(), {"normal", "radius", "size", "edge", "orifice"});
      if (w.type == "cylinder") allowed.insert(allowed.end(), {"axis", "radius", "length", "caps"});
      if (w.type == "cone") allowed.insert(allowed.end(), {"axis", "radius", "end_radius", "length"});
      if (w.type == "mesh") allowed.insert(allowed.end(), {"file", "scale", "rotate", "translate", "axis"});
      for (const auto& k : m.keys())
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
          ctx.fail(m.sub(k), m.get(k).mark, "key '" + k + "' does not apply to a " + w.type + " wall",
                   "remove it (keys for a " + w.type + " wall: " + join(allowed) + ")");
      w.material = material_ref(m.require("material", "name the wall's material"));
      opt_vec3(ctx, m, "point", w.point);
      auto unit_vector = [&](const char* key, Vec3d& v) {
        opt_vec3(ctx, m, key, v);
        const double n = norm(v);
        check(ctx, n > 0, m.get(key), std::string(key) + " is the zero vector",
              "give a direction, e.g. [0, 0, 1]");
        for (double& c : v)
          c /= n;
      };
      auto length_key = [&](const char* key, double& v, bool required, bool zero_ok,
                            const std::string& what) {
        if (!m.has(key)) {
          if (required) m.require(key, "give the " + what + " in m");
          return;
        }
        v = as_num(ctx, m.get(key));
        check(ctx, zero_ok ? v >= 0 : v > 0, m.get(key),
              std::string(key) + " must be " + (zero_ok ? ">= 0" : "> 0") + " (got " + num_str(v) + ")",
              "give the " + what + " in m");
      };
      if (w.type == "plane") {
        unit_vector("normal", w.normal);
        length_key("radius", w.radius, false, false, "radius of the disk that bounds the plane");
        if (m.has("size")) {
          const Field sf = m.get("size");
          if (!sf.node.IsSequence() || sf.node.size() != 2)
            ctx.fail(sf.path, sf.mark, "expected a list of two side lengths, got " + describe(sf.node),
                     "write size: [width, height] in m, e.g. size: [0.05, 0.02]");
          for (std::size_t k = 0; k < 2; ++k) {
            const Field e = item(sf, k);
            w.size[k] = as_num(ctx, e);
            check(ctx, w.size[k] > 0, e, "side length must be > 0 (got " + num_str(w.size[k]) + ")",
                  "give the rectangle's side lengths in m");
          }
        }
        if (m.has("edge")) {
          check(ctx, m.has("size"), m.get("edge"), "edge is given without size",
                "give size: [width, height] too (edge is the direction of the width)");
          Vec3d e = as_vec3(ctx, m.get("edge"));
          const double along = e[0] * w.normal[0] + e[1] * w.normal[1] + e[2] * w.normal[2];
          for (int a = 0; a < 3; ++a)
            e[a] -= along * w.normal[a];
          check(ctx, norm(e) > 1e-9 * norm(as_vec3(ctx, m.get("edge"))), m.get("edge"),
                "edge is parallel to the normal", "give a direction in the plane, e.g. [1, 0, 0]");
          w.edge = e;
        }
        length_key("orifice", w.orifice, false, false, "radius of the hole around point");
        if (m.has("orifice")) {
          check(ctx, w.bounded(), m.get("orifice"), "an orifice needs a bounded plane",
                "give radius (a disk) or size (a rectangle) too: an infinite plane has no rim to cut into");
          const double limit = w.radius > 0 ? w.radius : 0.5 * std::min(w.size[0], w.size[1]);
          check(ctx, w.orifice < limit, m.get("orifice"),
                "orifice " + num_str(w.orifice) + " m does not fit inside the plane (" + num_str(limit) +
                    " m)",
                "make the orifice smaller than the plane's radius or half its shorter side");
        }
      } else if (w.type == "mesh") {
        parse_mesh(m, w);
        unit_vector("axis", w.axis); // of the rotation in `motion` (through point)
      } else {
        unit_vector("axis", w.axis);
        length_key("length", w.length, true, false, w.type + " length along its axis");
        if (w.type == "cylinder") {
          length_key("radius", w.radius, true, false, "cylinder radius");
          opt_bool(ctx, m, "caps", w.caps);
        } else {
          length_key("radius", w.radius, true, true, "cone radius at point (0 for a closed tip)");
          length_key("end_radius", w.end_radius, true, true, "cone radius at the far end");
          check(ctx, w.radius > 0 || w.end_radius > 0, m.get("end_radius"), "both radii are 0",
                "give the cone's radius at point (the orifice) and at the far end");
        }
      }
      if (m.has("motion")) {
        parse_motion(m.get("motion"), w);
        // The output places a moving mesh from its prescribed motion alone.
        bool until = w.motion_until_force > 0;
        for (const WallSpec::Segment& seg : w.then)
          until = until || seg.until_force > 0;
        check(ctx, !(until && w.type == "mesh"), m.get("motion"),
              "until_force is not available on mesh walls",
              "end the mesh's segment at a time (stop), or press with a plane wall");
      }
      scene.walls.push_back(w);
    }
  }

  void parse_outlets(const Field& f) {
    if (f.node.IsNull()) return;
    if (!f.node.IsSequence())
      ctx.fail(f.path, f.mark, "expected a list of outlets, got " + describe(f.node),
               "write outlets: as a list of '- name: ...' entries");
    for (std::size_t i = 0; i < f.node.size(); ++i) {
      const Field of = item(f, i);
      MapView m(ctx, of, {"name", "type", "point", "normal", "lo", "hi", "every"});
      OutletSpec o;
      o.name = m.has("name") ? as_str(ctx, m.get("name")) : "outlet" + std::to_string(i);
      for (const auto& other : scene.outlets)
        check(ctx, other.name != o.name, m.has("name") ? m.get("name") : of,
              "outlet name '" + o.name + "' is used twice", "give every outlet its own name");
      check(ctx, o.name.find('/') == std::string::npos, m.get("name"), "outlet name contains '/'",
            "use letters, digits and '_'");
      if (m.has("type")) o.type = as_choice(ctx, m.get("type"), kOutletTypes, "outlet type");
      const std::vector<std::string> allowed =
          o.type == "plane" ? std::vector<std::string>{"name", "type", "point", "normal", "every"}
                            : std::vector<std::string>{"name", "type", "lo", "hi", "every"};
      for (const auto& k : m.keys())
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
          ctx.fail(m.sub(k), m.get(k).mark, "key '" + k + "' does not apply to a " + o.type + " outlet",
                   "remove it (keys for a " + o.type + " outlet: " + join(allowed) + ")");
      if (o.type == "plane") {
        o.point = as_vec3(ctx, m.require("point", "give a point on the outlet plane, e.g. [0, 0, 0]"));
        o.normal = as_vec3(ctx, m.require("normal", "give the normal pointing to the particles kept"));
        const double n = norm(o.normal);
        check(ctx, n > 0, m.get("normal"), "normal is the zero vector", "give a direction, e.g. [0, 0, 1]");
        for (double& c : o.normal)
          c /= n;
      } else {
        o.lo = as_vec3(ctx, m.require("lo", "give the box's lower corner"));
        o.hi = as_vec3(ctx, m.require("hi", "give the box's upper corner"));
        for (int a = 0; a < 3; ++a)
          check(ctx, o.hi[a] > o.lo[a], m.get("hi"),
                std::string("outlet hi ") + kAxis[a] + " = " + num_str(o.hi[a]) + " is not above lo " +
                    kAxis[a] + " = " + num_str(o.lo[a]),
                "make every component of hi larger than lo");
      }
      opt_num(ctx, m, "every", o.every);
      positive(ctx, m, "every", o.every, "give the time between outlet checks in s");
      scene.outlets.push_back(o);
    }
  }

  void parse_time(const Field& f) {
    MapView m(ctx, f, {"end", "step", "fraction", "force_step", "resolve_adhesion"});
    TimeSpec& t = scene.time;
    const Field ef = m.require("end", "give the simulated end time in s, e.g. end: 0.5");
    t.end = as_num(ctx, ef);
    check(ctx, t.end > 0, ef, "time.end must be > 0 (got " + num_str(t.end) + ")", "give the end time in s");
    if (m.has("step")) {
      const Field sf = m.get("step");
      if (sf.node.IsScalar() && sf.node.Scalar() == "auto") {
        t.step = 0;
      } else {
        double v = 0;
        if (!sf.node.IsScalar() || !YAML::convert<double>::decode(sf.node, v) || !std::isfinite(v))
          ctx.fail(sf.path, sf.mark, "expected 'auto' or a number, got " + describe(sf.node),
                   "write step: auto or step: 1e-6 (s)");
        check(ctx, v > 0, sf, "time step must be > 0 (got " + num_str(v) + ")",
              "write step: auto or a step in s");
        t.step = v;
      }
    }
    opt_num(ctx, m, "fraction", t.fraction);
    if (m.has("fraction"))
      check(ctx, t.fraction > 0 && t.fraction <= 1, m.get("fraction"),
            "fraction " + num_str(t.fraction) + " is outside (0, 1]",
            "give the fraction of the stable time step, typically 0.1-0.3");
    opt_bool(ctx, m, "force_step", t.force_step);
    opt_bool(ctx, m, "resolve_adhesion", t.resolve_adhesion);
  }

  void parse_output(const Field& f) {
    MapView m(ctx, f, {"every", "fields", "file"});
    OutputSpec& o = scene.output;
    opt_num(ctx, m, "every", o.every);
    non_negative(ctx, m, "every", o.every,
                 "give the simulated time between frames in s (0: first and last only)");
    if (m.has("fields")) {
      const Field ff = m.get("fields");
      if (!ff.node.IsSequence())
        ctx.fail(ff.path, ff.mark, "expected a list of field names, got " + describe(ff.node),
                 "write fields: [" + join(kOutputFields) + "]");
      o.fields.clear();
      for (std::size_t i = 0; i < ff.node.size(); ++i) {
        const std::string s = as_choice(ctx, item(ff, i), kOutputFields, "output field");
        if (std::find(o.fields.begin(), o.fields.end(), s) == o.fields.end()) o.fields.push_back(s);
      }
    }
    if (m.has("file")) o.file = as_str(ctx, m.get("file"));
  }

  void parse_stop(const Field& f) {
    MapView m(ctx, f, {"kinetic_energy_below", "min_time"});
    opt_num(ctx, m, "kinetic_energy_below", scene.stop.kinetic_energy_below);
    positive(ctx, m, "kinetic_energy_below", scene.stop.kinetic_energy_below,
             "give a kinetic energy threshold in J (leave it out to run to time.end)");
    opt_num(ctx, m, "min_time", scene.stop.min_time);
    non_negative(ctx, m, "min_time", scene.stop.min_time, "give a time in s, >= 0");
  }

  void parse_neighbour(const Field& f) {
    MapView m(ctx, f, {"skin", "skin_fraction", "reorder_every", "force_pass"});
    NeighbourSpec& n = scene.neighbour;
    opt_num(ctx, m, "skin", n.skin);
    non_negative(ctx, m, "skin", n.skin, "give the absolute skin in m, or use skin_fraction");
    opt_num(ctx, m, "skin_fraction", n.skin_fraction);
    positive(ctx, m, "skin_fraction", n.skin_fraction,
             "give the skin as a fraction of the largest diameter, e.g. 0.2");
    if (m.has("reorder_every")) {
      const long r = as_int(ctx, m.get("reorder_every"));
      check(ctx, r >= 0 && r < 1000000000L, m.get("reorder_every"), "reorder_every must be >= 0",
            "give how many list builds between spatial reorders (0: never)");
      n.reorder_every = static_cast<int>(r);
    }
    if (m.has("force_pass"))
      n.force_pass = as_choice(ctx, m.get("force_pass"), {"auto", "blocks", "pairs"}, "force pass");
  }

  void parse_stability(const Field& f) {
    MapView m(ctx, f, {"max_overlap_fraction", "relax_initial_overlaps", "overlap_tolerance"});
    StabilitySpec& s = scene.stability;
    opt_num(ctx, m, "max_overlap_fraction", s.max_overlap_fraction);
    if (m.has("max_overlap_fraction"))
      check(ctx, s.max_overlap_fraction > 0 && s.max_overlap_fraction <= 1, m.get("max_overlap_fraction"),
            "max_overlap_fraction " + num_str(s.max_overlap_fraction) + " is outside (0, 1]",
            "give a fraction of the smaller radius, e.g. 0.5");
    opt_bool(ctx, m, "relax_initial_overlaps", s.relax_initial_overlaps);
    opt_num(ctx, m, "overlap_tolerance", s.overlap_tolerance);
    non_negative(ctx, m, "overlap_tolerance", s.overlap_tolerance,
                 "give the allowed initial overlap as a fraction of the smaller radius, e.g. 0.01");
  }

  void parse_analyses(const Field& f) {
    if (f.node.IsNull()) return;
    if (!f.node.IsSequence())
      ctx.fail(f.path, f.mark, "expected a list of analyses, got " + describe(f.node),
               "write analyses: as a list of '- type: ...' entries");
    for (std::size_t i = 0; i < f.node.size(); ++i) {
      const Field af = item(f, i);
      if (!af.node.IsMap())
        ctx.fail(af.path, af.mark, "expected a map, got " + describe(af.node),
                 "write '- type: <analysis>, ...'");
      std::vector<std::string> keys;
      for (auto it = af.node.begin(); it != af.node.end(); ++it)
        keys.push_back(it->first.Scalar());
      MapView m(ctx, af, keys); // any parameter names; duplicates still caught
      AnalysisSpec a;
      a.type = as_str(ctx, m.require("type", "name the analysis type"));
      a.name = m.has("name") ? as_str(ctx, m.get("name")) : a.type;
      for (const auto& other : scene.analyses)
        if (other.name == a.name)
          ctx.fail(m.sub("name"), af.mark, "analysis name '" + a.name + "' is used twice",
                   "give each analysis its own name");
      for (const auto& k : keys) {
        if (k == "type" || k == "name") continue;
        const Field pf = m.get(k);
        if (pf.node.IsScalar()) {
          a.params[k] = pf.node.Scalar();
        } else {
          YAML::Emitter em;
          em << YAML::Flow << pf.node;
          a.params[k] = em.c_str();
        }
      }
      scene.analyses.push_back(a);
    }
  }

  // Each material used by a group or a wall has what the chosen contact law needs.
  void check_materials_for_laws() {
    std::vector<std::pair<std::string, std::string>> used; // material, user
    for (std::size_t i = 0; i < scene.groups.size(); ++i)
      used.push_back({scene.groups[i].material, "groups." + std::to_string(i)});
    for (std::size_t i = 0; i < scene.walls.size(); ++i)
      used.push_back({scene.walls[i].material, "walls." + std::to_string(i)});
    const ContactSpec& c = scene.contact;
    for (const auto& use : used) {
      // Named copies, not structured bindings: the lambda below captures them (C++17 cannot).
      const std::string& name = use.first;
      const std::string& user = use.second;
      const MaterialSpec& m = scene.materials[scene.material_index(name)];
      const Field& f = material_fields.at(name);
      const std::string used_by = " (used by " + user + ")";
      if (!models::is_spring_like(c.normal) && !(m.youngs_modulus > 0))
        ctx.fail(f.path + ".youngs_modulus", f.mark,
                 "material '" + name + "' has no youngs_modulus, needed by contact.normal " + c.normal +
                     used_by,
                 "add youngs_modulus: <Pa>");
      // What each chosen component declares it needs; a wall needs no adhesion parameters when walls are
      // not adhesive.
      const bool wall_only = user.rfind("walls.", 0) == 0;
      models::for_each_chosen_component(c, [&](auto component, const char* kind) {
        using C = typename decltype(component)::type;
        if constexpr (models::HasMaterialMissing<C>::value) {
          if (std::string(kind) == "adhesion" && wall_only && !c.wall_adhesion) return;
          if (const char* missing = C::material_missing(m))
            ctx.fail(f.path + "." + C::material_block, f.mark,
                     "material '" + name + "' has no " + missing + ", needed by contact." + kind + " " +
                         C::name + used_by,
                     std::string("add ") + C::material_example);
        }
      });
    }
    for (std::size_t i = 0; i < scene.groups.size(); ++i) {
      const MaterialSpec& m = scene.materials[scene.material_index(scene.groups[i].material)];
      const Field& f = material_fields.at(m.name);
      if (!(m.density > 0))
        ctx.fail(f.path + ".density", f.mark,
                 "material '" + m.name + "' has no density, needed by particles of groups." +
                     std::to_string(i),
                 "add density: <kg/m^3>");
    }
  }

  // The scaling law against the contact law (setup/scaling.hpp: check_scaling), reported at the law's key.
  void check_scaling_for_laws() {
    try {
      check_scaling(scene);
    } catch (const std::invalid_argument& e) {
      ctx.fail("groups.0.coarse_grain.law", coarse_law_mark, e.what(), "");
    }
  }

  void parse(const YAML::Node& root) {
    const Field rf{root, "", YAML::Mark()};
    if (!root.IsMap())
      ctx.fail("", mark_of(root, YAML::Mark::null_mark()),
               "the scene is not a map of keys (got " + describe(root) + ")",
               "start from an example in scenes/");
    MapView m(ctx, rf,
              {"description", "domain", "gravity", "materials", "contact", "pairs", "groups", "walls",
               "outlets", "time", "output", "stop", "neighbour", "stability", "analyses"});
    if (m.has("description")) as_str(ctx, m.get("description"));
    parse_domain(m.require("domain", "give domain: {lo: [x, y, z], hi: [x, y, z]} in m"));
    opt_vec3(ctx, m, "gravity", scene.gravity);
    parse_materials(
        m.require("materials", "define at least one material: materials: {name: {density: ...}}"));
    if (m.has("contact")) parse_contact(m.get("contact"));
    if (m.has("pairs")) parse_pairs(m.get("pairs"));
    parse_groups(m.require("groups", "give a list of particle groups"));
    if (m.has("walls")) parse_walls(m.get("walls"));
    if (m.has("outlets")) parse_outlets(m.get("outlets"));
    parse_time(m.require("time", "give time: {end: <s>}"));
    if (m.has("output")) parse_output(m.get("output"));
    if (m.has("stop")) parse_stop(m.get("stop"));
    if (m.has("neighbour")) parse_neighbour(m.get("neighbour"));
    if (m.has("stability")) parse_stability(m.get("stability"));
    if (m.has("analyses")) parse_analyses(m.get("analyses"));
    check_materials_for_laws();
    check_scaling_for_laws();
  }
};

void apply_override(YAML::Node& root, const std::string& text, Ctx& ctx) {
  const std::string where = ctx.source + ":--set '" + text + "'";
  const auto eq = text.find('=');
  if (eq == std::string::npos)
    throw SceneError(scene_error_message(where, "", "an override must be key.path=value",
                                         "write e.g. --set groups.0.count=500"));
  const std::string path = trim(text.substr(0, eq));
  const std::string value = trim(text.substr(eq + 1));
  const auto comps = split_path(path);
  for (const auto& c : comps)
    if (c.empty())
      throw SceneError(
          scene_error_message(where, path, "the key path has an empty part",
                              "separate keys and list indices by single dots, e.g. walls.1.radius"));
  if (value.empty())
    throw SceneError(scene_error_message(where, path, "no value after '='", "write key.path=value"));
  YAML::Node value_node;
  try {
    value_node = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw SceneError(scene_error_message(where, path, "the value is not valid YAML (" + e.msg + ")",
                                         "quote it or write a number, a [list] or a {map}"));
  }
  if (!root.IsMap())
    throw SceneError(
        scene_error_message(where, path, "the scene is not a map of keys", "fix the scene file"));
  YAML::Node cur;
  cur.reset(root);
  std::string sofar;
  for (std::size_t i = 0; i < comps.size(); ++i) {
    const std::string& k = comps[i];
    const bool last = i + 1 == comps.size();
    const std::string parent = sofar.empty() ? "the scene" : "'" + sofar + "'";
    sofar += (sofar.empty() ? "" : ".") + k;
    if (cur.IsMap()) {
      const YAML::Node& ccur = cur;
      YAML::Node child = ccur[k];
      if (!child.IsDefined()) {
        if (last) {
          cur[k] = value_node; // a new leaf: checked by validation like any key
          break;
        }
        std::vector<std::string> keys;
        for (auto it = cur.begin(); it != cur.end(); ++it)
          keys.push_back(it->first.Scalar());
        const std::string c = closest(k, keys);
        throw SceneError(scene_error_message(
            where, path,
            "'" + sofar + "' does not exist in the scene (" + parent + " has no key '" + k + "')",
            (c.empty() ? std::string() : "did you mean '" + c + "'? ") +
                "only the last key of a path may be new; set a whole map instead, e.g. --set " + sofar +
                "={key: value}"));
      }
      if (last) {
        cur[k] = value_node;
        break;
      }
      cur.reset(child);
    } else if (cur.IsSequence()) {
      const bool digits =
          !k.empty() && std::all_of(k.begin(), k.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
      if (!digits || k.size() > 9 || std::stoul(k) >= cur.size())
        throw SceneError(scene_error_message(where, path,
                                             "'" + sofar + "' does not exist (" + parent + " is a list of " +
                                                 std::to_string(cur.size()) + " items)",
                                             cur.size()
                                                 ? "use an index from 0 to " + std::to_string(cur.size() - 1)
                                                 : "the list is empty; set the whole list instead"));
      const std::size_t idx = std::stoul(k);
      if (last) {
        cur[idx] = value_node;
        break;
      }
      YAML::Node child = cur[idx];
      cur.reset(child);
    } else {
      throw SceneError(scene_error_message(
          where, path, "'" + sofar + "' does not exist (" + parent + " is a single value, not a map or list)",
          "set " + parent + " itself"));
    }
  }
  ctx.overrides.push_back({comps, text});
}

Scene parse_impl(const std::string& yaml, const std::string& source_name,
                 const std::vector<std::string>& overrides, const std::filesystem::path& base_dir) {
  Parser p;
  p.ctx.source = source_name;
  p.base_dir = base_dir;
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw SceneError(scene_error_message(source_name + ":" + std::to_string(e.mark.line + 1), "",
                                         "YAML syntax error: " + e.msg,
                                         "fix the YAML (indentation, ':' after keys, matching brackets)"));
  } catch (const YAML::Exception& e) {
    throw SceneError(scene_error_message(source_name, "", "cannot parse YAML: " + e.msg, "fix the YAML"));
  }
  if (!root.IsDefined() || root.IsNull())
    throw SceneError(
        scene_error_message(source_name, "", "the scene is empty", "start from an example in scenes/"));
  for (const auto& o : overrides)
    apply_override(root, o, p.ctx);
  try {
    p.parse(root);
  } catch (const YAML::Exception& e) { // should not happen: every access is checked
    throw SceneError(scene_error_message(source_name + ":" + std::to_string(e.mark.line + 1), "",
                                         "cannot read the scene: " + e.msg, "check the YAML structure"));
  }
  YAML::Emitter em;
  em << root;
  p.scene.resolved_yaml = std::string(em.c_str()) + "\n";
  p.scene.source_file = source_name;
  return p.scene;
}

} // namespace

Scene parse_scene_text(const std::string& yaml, const std::string& source_name,
                       const std::vector<std::string>& overrides) {
  return parse_impl(yaml, source_name, overrides, std::filesystem::path(source_name).parent_path());
}

Scene parse_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw SceneError(scene_error_message(path, "", "cannot open the scene file",
                                         "check the path and that the file is readable"));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_impl(ss.str(), path, overrides, std::filesystem::path(path).parent_path());
}

} // namespace cgdem
