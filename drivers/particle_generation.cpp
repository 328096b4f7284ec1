// Initial particles from the scene's groups. See drivers/particle_generation.hpp.
#include "drivers/particle_generation.hpp"
#include "drivers/preflight.hpp"
#include "drivers/random.hpp"
#include "drivers/host_cell_grid.hpp"
#include "setup/scaling.hpp"
#include "core/crash_probe.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <unordered_map>

namespace cgdem {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string num_str(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

[[noreturn]] void group_fail(const GroupSpec& g, std::size_t gi, const std::string& sub,
                             const std::string& what, const std::string& fix) {
  const std::string path = "groups." + std::to_string(gi) + (sub.empty() ? "" : "." + sub);
  throw SceneError(scene_error_message(g.source_location.empty() ? "<scene>" : g.source_location, path,
                                       "group '" + g.name + "': " + what, fix));
}

double dist2(const Vec3d& r) {
  return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
}

// ---------------------------------------------------------------------------------------------------
struct GroupParticles {
  std::vector<Vec3d> position;
  std::vector<double> radius, density; // density < 0: the material's
  std::vector<std::int64_t> id;        // < 0: to be assigned
};

std::vector<double> sample_radii(const GroupSpec& g, std::size_t gi) {
  const SizeSpec& s = g.size;
  Rng rng(g.placement.seed, Rng::radius);
  std::vector<double> r(static_cast<std::size_t>(g.count));
  const bool truncate_lo = s.min_radius > 0, truncate_hi = s.max_radius > 0;
  // lognormal: mean and std are those of the radius itself.
  const double sig2 =
      s.mean_radius > 0 ? std::log(1.0 + (s.std_radius * s.std_radius) / (s.mean_radius * s.mean_radius)) : 0;
  const double mu = s.mean_radius > 0 ? std::log(s.mean_radius) - 0.5 * sig2 : 0;
  for (auto& v : r) {
    if (s.distribution == "mono") {
      v = s.radius;
    } else if (s.distribution == "uniform") {
      v = rng.uniform(s.min_radius, s.max_radius);
    } else {
      int tries = 0;
      for (;;) {
        v = s.distribution == "normal" ? s.mean_radius + s.std_radius * rng.normal()
                                       : std::exp(mu + std::sqrt(sig2) * rng.normal());
        const bool ok = v > 0 && (!truncate_lo || v >= s.min_radius) && (!truncate_hi || v <= s.max_radius);
        if (ok) break;
        if (++tries > 100000)
          group_fail(g, gi, "size",
                     "the " + s.distribution + " distribution (mean " + num_str(s.mean_radius) + ", std " +
                         num_str(s.std_radius) + ") almost never falls inside the truncation [min, max]",
                     "widen min/max or move the mean inside them");
      }
    }
    v *= group_scale_factor(g);
  }
  return r;
}

// ---- particle files ---------------------------------------------------------------------------------
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream ss(line);
  while (std::getline(ss, cur, ',')) {
    const auto b = cur.find_first_not_of(" \t\r");
    const auto e = cur.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? "" : cur.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

void read_csv(const GroupSpec& g, std::size_t gi, GroupParticles& out) {
  const std::string& path = g.placement.file;
  std::ifstream in(path);
  const std::string fix = "check the file: a header line id,x,y,z,radius[,density], one particle per line, "
                          "'#' starts a comment line";
  if (!in)
    group_fail(g, gi, "placement.file", "cannot read particle file '" + path + "'",
               "check the path (a relative path is taken from the scene file's directory)");
  std::string line;
  long lineno = 0;
  std::map<std::string, int> col;
  std::size_t ncol = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto fields = split_csv(line);
    const std::string where = "particle file '" + path + "' line " + std::to_string(lineno) + ": ";
    if (col.empty()) {
      for (std::size_t c = 0; c < fields.size(); ++c) {
        const std::string& name = fields[c];
        if (name != "id" && name != "x" && name != "y" && name != "z" && name != "radius" &&
            name != "density")
          group_fail(g, gi, "placement.file", where + "unknown column '" + name + "'", fix);
        if (!col.emplace(name, static_cast<int>(c)).second)
          group_fail(g, gi, "placement.file", where + "column '" + name + "' appears twice", fix);
      }
      for (const char* need : {"x", "y", "z", "radius"})
        if (!col.count(need))
          group_fail(g, gi, "placement.file", where + "the header has no column '" + need + "'", fix);
      ncol = fields.size();
      continue;
    }
    if (fields.size() != ncol)
      group_fail(g, gi, "placement.file",
                 where + "expected " + std::to_string(ncol) + " values, got " + std::to_string(fields.size()),
                 fix);
    auto value = [&](const std::string& name) {
      const std::string& s = fields[col.at(name)];
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (s.empty() || *end != '\0' || !std::isfinite(v))
        group_fail(g, gi, "placement.file", where + name + " '" + s + "' is not a number", fix);
      return v;
    };
    out.position.push_back({value("x"), value("y"), value("z")});
    const double r = value("radius");
    if (!(r > 0))
      group_fail(g, gi, "placement.file", where + "radius " + num_str(r) + " is not positive", fix);
    out.radius.push_back(r);
    double rho = -1;
    if (col.count("density")) {
      rho = value("density");
      if (!(rho > 0))
        group_fail(g, gi, "placement.file", where + "density " + num_str(rho) + " is not positive", fix);
    }
    out.density.push_back(rho);
    std::int64_t id = -1;
    if (col.count("id")) {
      const double v = value("id");
      if (v < 0 || v != std::floor(v) || v > 9e15)
        group_fail(g, gi, "placement.file",
                   where + "id " + fields[col.at("id")] + " is not a non-negative integer", fix);
      id = static_cast<std::int64_t>(v);
    }
    out.id.push_back(id);
  }
  if (col.empty())
    group_fail(g, gi, "placement.file", "particle file '" + path + "' has no header line", fix);
}

// Closes an HDF5 handle on scope exit.
struct H5Closer {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5Closer() {
    if (id >= 0) close(id);
  }
};

struct H5Quiet { // no HDF5 error stack printing while we probe; restored afterwards
  H5E_auto2_t func = nullptr;
  void* data = nullptr;
  H5Quiet() {
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~H5Quiet() { H5Eset_auto2(H5E_DEFAULT, func, data); }
};

void read_hdf5(const GroupSpec& g, std::size_t gi, GroupParticles& out) {
  const std::string& path = g.placement.file;
  const std::string fix =
      "give a cgdem HDF5 result (datasets /frames/NNNNNN/position, radius, id) or a CSV file";
  H5Quiet quiet;
  H5Closer file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (file.id < 0) group_fail(g, gi, "placement.file", "cannot open HDF5 file '" + path + "'", fix);
  H5Closer frames{H5Gopen2(file.id, "/frames", H5P_DEFAULT), H5Gclose};
  if (frames.id < 0)
    group_fail(g, gi, "placement.file", "HDF5 file '" + path + "' has no /frames group", fix);
  H5G_info_t info;
  if (H5Gget_info(frames.id, &info) < 0 || info.nlinks == 0)
    group_fail(g, gi, "placement.file", "HDF5 file '" + path + "' has no frames under /frames", fix);
  std::string last;
  long long last_num = -1;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(frames.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len <= 0) continue;
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    H5Lget_name_by_idx(frames.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(len));
    char* end = nullptr;
    const long long num = std::strtoll(name.c_str(), &end, 10);
    const long long key = (*end == '\0') ? num : -1;
    if (last.empty() || key > last_num || (key == last_num && name > last)) last = name, last_num = key;
  }
  const std::string fpath = "/frames/" + last;
  H5Closer frame{H5Gopen2(file.id, fpath.c_str(), H5P_DEFAULT), H5Gclose};
  if (frame.id < 0) group_fail(g, gi, "placement.file", "cannot open " + fpath + " in '" + path + "'", fix);
  auto read = [&](const char* name, hid_t type, void* buf, hsize_t expect, bool required) -> bool {
    if (H5Lexists(frame.id, name, H5P_DEFAULT) <= 0) {
      if (required)
        group_fail(g, gi, "placement.file", "'" + path + "' " + fpath + " has no dataset '" + name + "'",
                   fix);
      return false;
    }
    H5Closer ds{H5Dopen2(frame.id, name, H5P_DEFAULT), H5Dclose};
    H5Closer space{ds.id >= 0 ? H5Dget_space(ds.id) : -1, H5Sclose};
    const hssize_t n = space.id >= 0 ? H5Sget_simple_extent_npoints(space.id) : -1;
    if (n < 0 || static_cast<hsize_t>(n) != expect ||
        (buf && H5Dread(ds.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) < 0))
      group_fail(g, gi, "placement.file",
                 "cannot read dataset " + fpath + "/" + name + " of '" + path + "' (" + std::to_string(n) +
                     " values, expected " + std::to_string(expect) + ")",
                 fix);
    return true;
  };
  // N from the radius dataset.
  hsize_t n = 0;
  {
    if (H5Lexists(frame.id, "radius", H5P_DEFAULT) <= 0)
      group_fail(g, gi, "placement.file", "'" + path + "' " + fpath + " has no dataset 'radius'", fix);
    H5Closer ds{H5Dopen2(frame.id, "radius", H5P_DEFAULT), H5Dclose};
    H5Closer space{ds.id >= 0 ? H5Dget_space(ds.id) : -1, H5Sclose};
    const hssize_t np = space.id >= 0 ? H5Sget_simple_extent_npoints(space.id) : -1;
    if (np < 0)
      group_fail(g, gi, "placement.file", "cannot read " + fpath + "/radius of '" + path + "'", fix);
    n = static_cast<hsize_t>(np);
    // Results are written unfiltered: more radii than the file has bytes for means a damaged header, refused
    // before the buffers are allocated.
    hsize_t file_bytes = 0;
    if (H5Fget_filesize(file.id, &file_bytes) < 0 || n > file_bytes / sizeof(double))
      group_fail(g, gi, "placement.file",
                 "'" + path + "' " + fpath + "/radius claims " + std::to_string(n) +
                     " particles, more than the " + std::to_string(file_bytes) + "-byte file holds",
                 fix);
  }
  std::vector<double> pos(3 * n), rad(n);
  std::vector<std::int64_t> ids(n);
  read("radius", H5T_NATIVE_DOUBLE, rad.data(), n, true);
  read("position", H5T_NATIVE_DOUBLE, pos.data(), 3 * n, true);
  const bool have_id = read("id", H5T_NATIVE_INT64, ids.data(), n, false);
  for (hsize_t i = 0; i < n; ++i) {
    if (!(rad[i] > 0) || !std::isfinite(rad[i]))
      group_fail(g, gi, "placement.file",
                 "'" + path + "' particle " + std::to_string(i) + " has radius " + num_str(rad[i]), fix);
    out.position.push_back({pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]});
    out.radius.push_back(rad[i]);
    out.density.push_back(-1);
    out.id.push_back(have_id ? ids[i] : -1);
  }
}

bool is_hdf5(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == std::string("\x89HDF\r\n\x1a\n", 8);
}

void load_file(const GroupSpec& g, std::size_t gi, GroupParticles& out) {
  std::ifstream probe(g.placement.file);
  if (!probe)
    group_fail(g, gi, "placement.file", "cannot read particle file '" + g.placement.file + "'",
               "check the path (a relative path is taken from the scene file's directory)");
  if (is_hdf5(g.placement.file)) {
    // A damaged file can crash libhdf5 itself, or make it loop (docs/reliability.md): read it in a child
    // first.
    GroupParticles scratch;
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(g.placement.file, ec);
    if (const std::string why =
            crash_probe([&] { read_hdf5(g, gi, scratch); }, probe_time_limit(ec ? 0 : bytes));
        !why.empty())
      group_fail(g, gi, "placement.file", "HDF5 file '" + g.placement.file + "': " + why,
                 "give a cgdem HDF5 result or a CSV file");
    read_hdf5(g, gi, out);
  } else
    read_csv(g, gi, out);
  const std::size_t n = out.radius.size();
  if (n == 0)
    group_fail(g, gi, "placement.file", "particle file '" + g.placement.file + "' has no particles", "");
  if (g.count > 0) {
    if (static_cast<std::size_t>(g.count) > n)
      group_fail(g, gi, "count",
                 "count " + std::to_string(g.count) + " is more than the " + std::to_string(n) +
                     " particles in '" + g.placement.file + "'",
                 "leave count out (or 0) to take all particles of the file, or lower it");
    const auto c = static_cast<std::size_t>(g.count);
    out.position.resize(c), out.radius.resize(c), out.density.resize(c), out.id.resize(c);
  }
}

// ---- placement ----------------------------------------------------------------------------------------
struct Placed {
  std::vector<Vec3d> position;
  std::vector<double> radius;
};

void place_lattice(const GroupSpec& g, std::size_t gi, const std::vector<double>& r, GroupParticles& out) {
  const PlacementSpec& p = g.placement;
  const double rmax = *std::max_element(r.begin(), r.end());
  const double s = p.spacing > 0 ? p.spacing : 1.05 * 2 * rmax;
  if (s < 2 * rmax * (1 - 1e-12))
    group_fail(g, gi, "placement.spacing",
               "lattice spacing " + num_str(s) + " is below the largest diameter " + num_str(2 * rmax),
               "use a spacing of at least the largest diameter, or leave spacing out (1.05 x it)");
  long n[3];
  for (int a = 0; a < 3; ++a) {
    const double room = p.hi[a] - p.lo[a] - 2 * rmax;
    n[a] = room < 0 ? 0 : static_cast<long>(std::floor(room / s + 1e-9)) + 1;
  }
  const long capacity = n[0] * n[1] * n[2];
  if (g.count > capacity)
    group_fail(g, gi, "placement",
               "the lattice box holds only " + std::to_string(capacity) + " sites (" + std::to_string(n[0]) +
                   " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]) + " at spacing " + num_str(s) +
                   ") for " + std::to_string(g.count) + " particles",
               "enlarge placement lo/hi (e.g. raise hi z), reduce count, or reduce spacing");
  for (long k = 0; k < g.count; ++k) {
    const long i = k % n[0], j = (k / n[0]) % n[1], l = k / (n[0] * n[1]);
    out.position.push_back({p.lo[0] + rmax + i * s, p.lo[1] + rmax + j * s, p.lo[2] + rmax + l * s});
    out.radius.push_back(r[static_cast<std::size_t>(k)]);
    out.density.push_back(-1);
    out.id.push_back(-1);
  }
}

// Random sequential addition inside a box or a cylinder, avoiding every particle already in `grid`.
void place_random(const GroupSpec& g, std::size_t gi, std::vector<double> r, HostCellGrid& grid,
                  Placed& placed, GroupParticles& out) {
  const PlacementSpec& p = g.placement;
  const bool cyl = p.kind == "random_cylinder";
  std::sort(r.begin(), r.end(), std::greater<double>()); // largest first: packs better
  double vol_solid = 0;
  for (double v : r)
    vol_solid += 4.0 / 3.0 * kPi * v * v * v;
  const double vol_region = cyl ? kPi * p.cylinder_radius * p.cylinder_radius * p.cylinder_height
                                : (p.hi[0] - p.lo[0]) * (p.hi[1] - p.lo[1]) * (p.hi[2] - p.lo[2]);
  const double fraction = vol_solid / vol_region;
  const std::string fix =
      std::string("enlarge the region (") + (cyl ? "radius, height" : "lo, hi") +
      ") or place fewer particles; random placement of equal spheres stops near a solid fraction of "
      "0.29-0.32 (polydisperse: 0.42-0.46), docs/scene_format.md";
  if (fraction > 0.5)
    group_fail(g, gi, "placement",
               std::to_string(g.count) + " particles need a solid fraction of " + num_str(fraction) +
                   " in the " + p.kind + " region",
               fix);
  Rng rng(p.seed, Rng::position);
  // The cylinder's frame: e1, e2 across the axis a. Along +z they are x and y exactly, so that a z-aligned
  // cylinder places bit for bit as it always has (adding the zero terms changes no bit).
  const Vec3d a = p.axis;
  Vec3d e1{1, 0, 0}, e2{0, 1, 0};
  if (!(a[0] == 0 && a[1] == 0 && a[2] > 0)) {
    // e1: the unit vector along the coordinate axis least aligned with a, made perpendicular to a.
    const int k = std::fabs(a[0]) <= std::fabs(a[1]) && std::fabs(a[0]) <= std::fabs(a[2]) ? 0
                  : std::fabs(a[1]) <= std::fabs(a[2])                                     ? 1
                                                                                           : 2;
    Vec3d t{0, 0, 0};
    t[k] = 1;
    for (int i = 0; i < 3; ++i)
      e1[i] = t[i] - a[k] * a[i];
    const double n1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int i = 0; i < 3; ++i)
      e1[i] /= n1;
    e2 = {a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2], a[0] * e1[1] - a[1] * e1[0]};
  }
  const int max_tries = 20000;
  for (std::size_t k = 0; k < r.size(); ++k) {
    const double rk = r[k];
    Vec3d x{};
    bool ok = false;
    for (int t = 0; t < max_tries && !ok; ++t) {
      if (cyl) {
        const double rho_max = p.cylinder_radius - rk;
        const double h = p.cylinder_height - 2 * rk;
        if (rho_max < 0 || h < 0)
          group_fail(g, gi, "placement",
                     "a particle of radius " + num_str(rk) + " does not fit in the cylinder",
                     "enlarge the cylinder radius/height");
        const double rho = rho_max * std::sqrt(rng.uniform());
        const double phi = rng.uniform(0, 2 * kPi);
        const double u = rho * std::cos(phi), v = rho * std::sin(phi), along = h * rng.uniform();
        for (int i = 0; i < 3; ++i)
          x[i] = p.center[i] + rk * a[i] + along * a[i] + u * e1[i] + v * e2[i];
      } else {
        for (int a = 0; a < 3; ++a) {
          const double room = p.hi[a] - p.lo[a] - 2 * rk;
          if (room < 0)
            group_fail(g, gi, "placement",
                       "a particle of radius " + num_str(rk) + " does not fit in the box along " +
                           std::string(1, "xyz"[a]),
                       "enlarge placement lo/hi");
          x[a] = p.lo[a] + rk + room * rng.uniform();
        }
      }
      ok = !grid.any_neighbour(x, [&](int j) {
        const double c = rk + placed.radius[static_cast<std::size_t>(j)];
        return dist2(grid.delta(x, placed.position[static_cast<std::size_t>(j)])) < c * c;
      });
    }
    if (!ok)
      group_fail(g, gi, "placement",
                 "could place only " + std::to_string(k) + " of " + std::to_string(g.count) +
                     " particles without overlaps (" + p.kind + ", solid fraction " + num_str(fraction) + ")",
                 fix);
    grid.insert(static_cast<int>(placed.radius.size()), x);
    placed.position.push_back(x);
    placed.radius.push_back(rk);
    out.position.push_back(x);
    out.radius.push_back(rk);
    out.density.push_back(-1);
    out.id.push_back(-1);
  }
}

std::string where_of(const Scene& scene, const ParticleSet& ps, std::size_t i, std::string& path) {
  const int g = i < ps.group.size() ? ps.group[i] : -1;
  if (g >= 0 && static_cast<std::size_t>(g) < scene.groups.size()) {
    path = "groups." + std::to_string(g);
    return scene.groups[static_cast<std::size_t>(g)].source_location.empty()
               ? scene.source_file
               : scene.groups[static_cast<std::size_t>(g)].source_location;
  }
  path = "particles";
  return scene.source_file.empty() ? "<scene>" : scene.source_file;
}

} // namespace

namespace {

// Refuses a scene whose particles cannot fit in memory before they are allocated, naming the largest group.
void check_memory(const Scene& scene, const std::vector<double>& counts) {
  double total = 0;
  std::size_t largest = 0;
  for (std::size_t gi = 0; gi < counts.size(); ++gi) {
    total += counts[gi];
    if (counts[gi] > counts[largest]) largest = gi;
  }
  const std::string what = memory_shortfall(total);
  if (!what.empty())
    group_fail(scene.groups[largest], largest, "count", what,
               "lower the count, or coarse-grain the group (groups.N.coarse_grain)");
}

} // namespace

ParticleSet generate_particles(const Scene& scene) {
  const std::size_t ng = scene.groups.size();
  {
    std::vector<double> counts(ng, 0.0);
    for (std::size_t gi = 0; gi < ng; ++gi)
      if (scene.groups[gi].placement.kind != "file") counts[gi] = double(scene.groups[gi].count);
    if (ng > 0) check_memory(scene, counts);
  }
  std::vector<GroupParticles> gp(ng);
  std::vector<std::vector<double>> radii(ng);
  double rmax = 0;
  for (std::size_t gi = 0; gi < ng; ++gi) {
    const GroupSpec& g = scene.groups[gi];
    if (scene.material_index(g.material) < 0)
      group_fail(g, gi, "material", "material '" + g.material + "' is not defined",
                 "define it under materials");
    if (g.placement.kind == "file") {
      load_file(g, gi, gp[gi]);
      for (double v : gp[gi].radius)
        rmax = std::max(rmax, v);
    } else {
      if (g.count <= 0) group_fail(g, gi, "count", "count must be > 0", "give the number of particles");
      radii[gi] = sample_radii(g, gi);
      for (double v : radii[gi])
        rmax = std::max(rmax, v);
    }
  }
  {
    std::vector<double> counts(ng, 0.0);
    for (std::size_t gi = 0; gi < ng; ++gi)
      counts[gi] = scene.groups[gi].placement.kind == "file" ? double(gp[gi].radius.size())
                                                             : double(scene.groups[gi].count);
    if (ng > 0) check_memory(scene, counts); // now with the particle files' counts
  }
  // Place: file particles first (fixed), then the generated groups in order, each avoiding the earlier ones.
  HostCellGrid grid(scene.domain, 2 * rmax);
  Placed placed;
  auto add_to_grid = [&](const GroupParticles& p) {
    for (std::size_t i = 0; i < p.position.size(); ++i) {
      grid.insert(static_cast<int>(placed.radius.size()), p.position[i]);
      placed.position.push_back(p.position[i]);
      placed.radius.push_back(p.radius[i]);
    }
  };
  for (std::size_t gi = 0; gi < ng; ++gi)
    if (scene.groups[gi].placement.kind == "file") add_to_grid(gp[gi]);
  for (std::size_t gi = 0; gi < ng; ++gi) {
    const GroupSpec& g = scene.groups[gi];
    const std::string& kind = g.placement.kind;
    if (kind == "file") continue;
    if (kind == "lattice") {
      place_lattice(g, gi, radii[gi], gp[gi]);
      add_to_grid(gp[gi]);
    } else if (kind == "random_box" || kind == "random_cylinder") {
      place_random(g, gi, radii[gi], grid, placed, gp[gi]);
    } else if (kind == "inlet") {
      // Placed during the run (drivers/inlets_outlets.cpp); held at the inlet box's centre until then.
      const Vec3d centre{0.5 * (g.placement.lo[0] + g.placement.hi[0]),
                         0.5 * (g.placement.lo[1] + g.placement.hi[1]),
                         0.5 * (g.placement.lo[2] + g.placement.hi[2])};
      gp[gi].radius = radii[gi];
      gp[gi].position.assign(radii[gi].size(), centre);
      gp[gi].density.assign(radii[gi].size(), -1.0);
      gp[gi].id.assign(radii[gi].size(), -1);
    } else {
      group_fail(g, gi, "placement.type", "unknown placement type '" + kind + "'",
                 "use lattice, random_box, random_cylinder or file");
    }
  }
  // Ids: keep the files', continue after the largest.
  std::int64_t next_id = 1;
  std::map<std::int64_t, std::size_t> file_ids;
  for (std::size_t gi = 0; gi < ng; ++gi)
    for (std::int64_t id : gp[gi].id) {
      if (id < 0) continue;
      const auto ins = file_ids.emplace(id, gi);
      if (!ins.second)
        group_fail(scene.groups[gi], gi, "placement.file",
                   "particle id " + std::to_string(id) + " appears twice (also in group '" +
                       scene.groups[ins.first->second].name + "')",
                   "give every particle a unique id, or drop the id column to have ids assigned");
      next_id = std::max(next_id, id + 1);
    }
  ParticleSet ps;
  // Placed groups first, then the inlets' particles (the set's pending tail, in insertion order).
  std::vector<std::size_t> order;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t gi = 0; gi < ng; ++gi)
      if ((scene.groups[gi].placement.kind == "inlet") == (pass == 1)) order.push_back(gi);
  for (std::size_t gi : order) {
    const GroupSpec& g = scene.groups[gi];
    if (g.placement.kind == "inlet") ps.pending += gp[gi].position.size();
    const int mat = scene.material_index(g.material);
    const double rho_mat = scene.materials[static_cast<std::size_t>(mat)].density;
    GroupParticles& p = gp[gi];
    Rng vrng(g.placement.seed, Rng::velocity);
    for (std::size_t i = 0; i < p.position.size(); ++i) {
      const Vec3d u = vrng.unit_vector();
      ps.id.push_back(p.id[i] >= 0 ? p.id[i] : next_id++);
      ps.position.push_back(p.position[i]);
      ps.velocity.push_back({g.velocity[0] + g.velocity_random * u[0],
                             g.velocity[1] + g.velocity_random * u[1],
                             g.velocity[2] + g.velocity_random * u[2]});
      ps.angular_velocity.push_back({0, 0, 0});
      ps.radius.push_back(p.radius[i]);
      ps.density.push_back(p.density[i] > 0 ? p.density[i] : rho_mat);
      ps.material.push_back(mat);
      ps.group.push_back(static_cast<int>(gi));
    }
  }
  return ps;
}

void check_particles(const Scene& scene, const ParticleSet& ps) {
  const std::string src = scene.source_file.empty() ? "<scene>" : scene.source_file;
  if (ps.position.size() != ps.size() || ps.radius.size() != ps.size() || ps.pending > ps.size())
    throw SceneError(scene_error_message(src, "particles",
                                         "the particle set is inconsistent (ids, positions, radii)",
                                         "this is a bug in the particle source; report it"));
  const std::size_t n = ps.size() - ps.pending; // the inlets' particles are checked as they enter
  const DomainSpec& d = scene.domain;
  double rmax = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::string path;
    const std::string loc = where_of(scene, ps, i, path);
    const double r = ps.radius[i];
    const Vec3d& x = ps.position[i];
    const std::string pid = "particle " + std::to_string(ps.id[i]);
    if (!(r > 0) || !std::isfinite(r))
      throw SceneError(
          scene_error_message(loc, path, pid + " has radius " + num_str(r), "give positive radii"));
    for (int a = 0; a < 3; ++a) {
      const double L = d.hi[a] - d.lo[a];
      const std::string ax(1, "xyz"[a]);
      if (!std::isfinite(x[a]))
        throw SceneError(
            scene_error_message(loc, path, pid + " has a non-finite position", "fix its position"));
      if (d.periodic[a]) {
        if (x[a] < d.lo[a] - L || x[a] > d.hi[a] + L)
          throw SceneError(scene_error_message(loc, path,
                                               pid + " is at " + ax + " = " + num_str(x[a]) +
                                                   ", more than a box length outside the periodic domain [" +
                                                   num_str(d.lo[a]) + ", " + num_str(d.hi[a]) + "]",
                                               "move the particles into the domain or fix domain.lo/hi"));
        if (2 * r > L)
          throw SceneError(scene_error_message(loc, path,
                                               pid + " (diameter " + num_str(2 * r) +
                                                   ") is wider than the periodic domain along " + ax,
                                               "make the periodic box longer than a particle diameter"));
      } else if (x[a] < d.lo[a] || x[a] > d.hi[a]) {
        throw SceneError(
            scene_error_message(loc, path,
                                pid + " is outside the domain: " + ax + " = " + num_str(x[a]) + " not in [" +
                                    num_str(d.lo[a]) + ", " + num_str(d.hi[a]) + "]",
                                "move the particles (placement region, file) inside domain.lo/hi or "
                                "enlarge the domain"));
      }
    }
    rmax = std::max(rmax, r);
  }
  if (n == 0) return;
  HostCellGrid grid(d, 2 * rmax);
  for (std::size_t i = 0; i < n; ++i)
    grid.insert(static_cast<int>(i), ps.position[i]);
  const double tol = scene.stability.overlap_tolerance;
  const bool relax = scene.stability.relax_initial_overlaps;
  long count = 0;
  double worst = -1;
  std::size_t wi = 0, wj = 0;
  double w_overlap = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d& xi = ps.position[i];
    const double ri = ps.radius[i];
    grid.for_neighbours(xi, [&](int jj) {
      const auto j = static_cast<std::size_t>(jj);
      if (j <= i) return;
      const double rj = ps.radius[j];
      const double dist = std::sqrt(dist2(grid.delta(xi, ps.position[j])));
      const double overlap = ri + rj - dist;
      if (overlap <= 0) return;
      const double rel = overlap / std::min(ri, rj);
      const bool coincident = dist <= 1e-9 * (ri + rj);
      if (coincident || (!relax && rel > tol)) {
        ++count;
        const double key = coincident ? 1e300 : rel;
        if (key > worst) worst = key, wi = i, wj = j, w_overlap = overlap;
      }
    });
  }
  if (count == 0) return;
  std::string path;
  const std::string loc = where_of(scene, ps, wi, path);
  const double rel = w_overlap / std::min(ps.radius[wi], ps.radius[wj]);
  const bool coincident = worst >= 1e300;
  const std::string what = "particles " + std::to_string(ps.id[wi]) + " and " + std::to_string(ps.id[wj]) +
                           (coincident ? " sit at the same position"
                                       : " overlap by " + num_str(w_overlap) + " m (" + num_str(100 * rel) +
                                             "% of the smaller radius; stability.overlap_tolerance is " +
                                             num_str(100 * tol) + "%)") +
                           (count > 1 ? ", " + std::to_string(count) + " such pairs in all" : "");
  const std::string fix = coincident ? "fix the packing: remove or move the duplicated particles"
                                     : "fix the packing (spacing, region, count, particle file) or set "
                                       "stability.relax_initial_overlaps: true";
  throw SceneError(scene_error_message(loc, path, what, fix));
}

} // namespace cgdem

namespace cgdem {

// Opt-in removal of initial particle-particle overlaps (stability.relax_initial_overlaps): positions
// only, velocities untouched, so no energy is injected (the elastic energy the overlaps would have
// released is simply not created). Jacobi sweeps push both partners apart by half the overlap along the
// line of centres (minimum image on periodic axes) until the largest overlap is below 1e-6 of the
// smaller radius. Walls are not considered.
RelaxReport relax_overlaps(const Scene& scene, ParticleSet& ps) {
  RelaxReport report;
  const std::size_t n = ps.size() - ps.pending;
  if (n == 0) return report;
  const DomainSpec& d = scene.domain;
  double rmax = 0;
  for (double r : ps.radius)
    rmax = std::max(rmax, r);
  const double cell = 2 * rmax;
  std::array<long, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = std::max(1L, static_cast<long>((d.hi[a] - d.lo[a]) / cell));
  auto axis_cell = [&](double x, int a) {
    long c = static_cast<long>((x - d.lo[a]) / (d.hi[a] - d.lo[a]) * dims[a]);
    return std::min(std::max(c, 0L), dims[a] - 1);
  };
  std::vector<Vec3d> shift(n);
  for (int sweep = 0; sweep < 500; ++sweep) {
    std::unordered_map<long, std::vector<std::size_t>> grid;
    std::vector<std::array<long, 3>> at(n);
    for (std::size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a)
        at[i][a] = axis_cell(ps.position[i][a], a);
      grid[(at[i][2] * dims[1] + at[i][1]) * dims[0] + at[i][0]].push_back(i);
    }
    std::fill(shift.begin(), shift.end(), Vec3d{0, 0, 0});
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (long dz = -1; dz <= 1; ++dz)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dx = -1; dx <= 1; ++dx) {
            std::array<long, 3> c{at[i][0] + dx, at[i][1] + dy, at[i][2] + dz};
            bool skip = false;
            for (int a = 0; a < 3; ++a) {
              if (c[a] >= 0 && c[a] < dims[a]) continue;
              if (!d.periodic[a] || dims[a] < 3) skip = true;
              c[a] = (c[a] + dims[a]) % dims[a];
            }
            if (skip) continue;
            const auto it = grid.find((c[2] * dims[1] + c[1]) * dims[0] + c[0]);
            if (it == grid.end()) continue;
            for (std::size_t j : it->second) {
              if (j <= i) continue;
              Vec3d dv;
              double dist2 = 0;
              for (int a = 0; a < 3; ++a) {
                double x = ps.position[j][a] - ps.position[i][a];
                if (d.periodic[a]) x -= (d.hi[a] - d.lo[a]) * std::round(x / (d.hi[a] - d.lo[a]));
                dv[a] = x;
                dist2 += x * x;
              }
              const double overlap = ps.radius[i] + ps.radius[j] - std::sqrt(dist2);
              if (overlap <= 0 || dist2 == 0) continue;
              worst = std::max(worst, overlap / std::min(ps.radius[i], ps.radius[j]));
              const double push = 0.5 * overlap * (1 + 1e-6) / std::sqrt(dist2);
              for (int a = 0; a < 3; ++a) {
                shift[i][a] -= push * dv[a];
                shift[j][a] += push * dv[a];
              }
            }
          }
    if (sweep == 0) report.initial_max_overlap = worst;
    report.final_max_overlap = worst;
    report.sweeps = sweep;
    if (worst < 1e-6) break;
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a)
        ps.position[i][a] += shift[i][a];
  }
  return report;
}

} // namespace cgdem
