#include "core/result_reader.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "core/hdf5_guard.hpp"

namespace cgdem {
namespace {

using h5::check;
using h5::Hid;

// The number of values a dataset holds (0 when it is absent).
hsize_t values_in(hid_t loc, const std::string& name) {
  if (H5Lexists(loc, name.c_str(), H5P_DEFAULT) <= 0) return 0;
  Hid ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + name);
  Hid space(H5Dget_space(ds), H5Sclose, "get the dataspace of " + name);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0) h5::fail("size of " + name);
  return static_cast<hsize_t>(n);
}

// The first `count` values of a dataset (all of it when count is its size), converted to T's type.
template <class T>
std::vector<T> read_values(hid_t loc, const std::string& name, hid_t mem_type, hsize_t count) {
  std::vector<T> out(count);
  if (count == 0) return out;
  Hid ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + name);
  Hid space(H5Dget_space(ds), H5Sclose, "get the dataspace of " + name);
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 2) h5::fail("rank of " + name);
  hsize_t dims[2] = {0, 1};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  const hsize_t per_row = rank == 2 ? dims[1] : 1;
  if (count % per_row != 0 || count / per_row > dims[0])
    throw std::runtime_error(name + " holds " + std::to_string(dims[0] * per_row) +
                             " values, fewer than the " + std::to_string(count) + " expected");
  const hsize_t start[2] = {0, 0}, rows[2] = {count / per_row, per_row};
  check(H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, rows, nullptr), "select " + name);
  Hid memory(H5Screate_simple(rank, rows, nullptr), H5Sclose, "create the memory space of " + name);
  check(H5Dread(ds, mem_type, memory, space, H5P_DEFAULT, out.data()), "read " + name);
  return out;
}

std::vector<std::string> split_names(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string name; std::getline(in, name, ',');)
    if (!name.empty()) out.push_back(name);
  return out;
}

} // namespace

ResultReader::ResultReader(const std::string& path) : path_(path) {
  H5Guard guard;
  try {
    file_ = Hid(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open");
    if (H5Aexists(file_, "scene") <= 0 || H5Aexists(file_, "time_step") <= 0 ||
        H5Lexists(file_, "frames", H5P_DEFAULT) <= 0)
      throw std::runtime_error("not a cgdem result (no scene or time_step attribute, or no /frames)");
    scene_yaml_ = h5::read_string_attr(file_, "scene");
    h5::read_attr(file_, "time_step", H5T_NATIVE_DOUBLE, &time_step_);
    if (H5Aexists(file_, "wall_names") > 0)
      wall_names_ = split_names(h5::read_string_attr(file_, "wall_names"));
    std::int64_t frames = 0, rows = 0;
    h5::read_attr(file_, "frames_complete", H5T_NATIVE_INT64, &frames);
    h5::read_attr(file_, "series_complete", H5T_NATIVE_INT64, &rows);
    frames_ = static_cast<std::size_t>(frames);
    Hid series(H5Gopen2(file_, "series", H5P_DEFAULT), H5Gclose, "open /series");
    series_time_ = read_values<double>(series, "time", H5T_NATIVE_DOUBLE, rows);
    series_step_ = read_values<std::int64_t>(series, "step", H5T_NATIVE_INT64, rows);
    for (const std::string& w : wall_names_)
      wall_force_.push_back(read_values<double>(series, "wall_force/" + w, H5T_NATIVE_DOUBLE, 3 * rows));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("result file '" + path + "': " + e.what());
  }
}

ResultReader::~ResultReader() {
  H5Guard guard;
  file_ = Hid(); // the file's identifier closed here, inside the guard
}

FrameData ResultReader::frame(std::size_t k) const {
  if (k >= frames_)
    throw std::runtime_error("result file '" + path_ + "': no frame " + std::to_string(k) + " (it holds " +
                             std::to_string(frames_) + ")");
  char name[32];
  std::snprintf(name, sizeof name, "frames/%06zu", k);
  H5Guard guard;
  try {
    Hid g(H5Gopen2(file_, name, H5P_DEFAULT), H5Gclose, std::string("open ") + name);
    FrameData f;
    h5::read_attr(g, "time", H5T_NATIVE_DOUBLE, &f.time);
    h5::read_attr(g, "step", H5T_NATIVE_INT64, &f.step);
    const hsize_t n = values_in(g, "radius");
    f.radius = read_values<double>(g, "radius", H5T_NATIVE_DOUBLE, n);
    f.position = read_values<double>(g, "position", H5T_NATIVE_DOUBLE, 3 * n);
    f.id = read_values<std::int64_t>(g, "id", H5T_NATIVE_INT64, n);
    // The optional fields: as written, or empty.
    auto optional = [&](const char* field, hsize_t per_particle) {
      return values_in(g, field) > 0 ? per_particle * n : 0;
    };
    f.velocity = read_values<double>(g, "velocity", H5T_NATIVE_DOUBLE, optional("velocity", 3));
    f.angular_velocity =
        read_values<double>(g, "angular_velocity", H5T_NATIVE_DOUBLE, optional("angular_velocity", 3));
    f.mass = read_values<double>(g, "mass", H5T_NATIVE_DOUBLE, optional("mass", 1));
    f.group = read_values<std::int32_t>(g, "group", H5T_NATIVE_INT32, optional("group", 1));
    return f;
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("result file '" + path_ + "': " + e.what());
  }
}

std::vector<double> ResultReader::wall_force(std::size_t row) const {
  std::vector<double> out;
  for (const auto& w : wall_force_)
    for (int a = 0; a < 3; ++a)
      out.push_back(w.at(3 * row + a));
  return out;
}

} // namespace cgdem
