// Tests of the HDF5/XDMF result writer and the checkpoint files (core/result_writer.hpp,
// core/checkpoint.hpp). Everything is read back with the HDF5 C API, independently of the writer's code.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <random>
#include <regex>
#include <sstream>
#include <thread>

#include "core/checkpoint.hpp"
#include "core/result_writer.hpp"

extern char** environ;

namespace {

using cgdem::CheckpointData;
using cgdem::FrameData;
using cgdem::ResultWriter;
using cgdem::RunInfo;
using cgdem::SeriesRow;
namespace fs = std::filesystem;

const char* const kChildEnv = "CGDEM_TEST_IO_KILL_CHILD";

// ------------------------------------------------------------------------------------------------
// Fixtures and deterministic data.

struct TempDir {
  std::string path;
  TempDir() {
    char tmpl[] = "/tmp/cgdem_test_io_XXXXXX";
    const char* p = ::mkdtemp(tmpl);
    if (!p) throw std::runtime_error("mkdtemp failed");
    path = p;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return path + "/" + name; }
};

RunInfo test_info(std::vector<std::string> walls = {"floor", "lid"}) {
  RunInfo info;
  info.cgdem_version = "0.1.0-test";
  info.scene_yaml = "name: drum\nparticles:\n  - radius: 1.0e-3 # \xc2\xb5m? no, metres\n";
  info.backend = "openmp";
  info.threads = 2;
  info.time_step = 1.25e-6;
  info.scaling_law = "coarse_grain_energy";
  info.scale_factor = 2.5;
  info.wall_names = std::move(walls);
  return info;
}

std::size_t frame_size(std::int64_t k) {
  return k == 1 ? 0 : std::size_t(5 + 3 * (k % 4));
}

FrameData make_frame(std::int64_t k, std::size_t n) {
  FrameData f;
  f.time = 0.001 * double(k) + 1e-9;
  f.step = 1000 * k + 3;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = double(i);
    f.id.push_back(std::int64_t(i) * 7 + k + (std::int64_t(1) << 40));
    f.radius.push_back(1e-3 * (1 + double(i % 5)) + 1e-7 * double(k));
    f.mass.push_back(4.2e-6 * (1 + x) + double(k));
    f.group.push_back(std::int32_t(i % 3) - 1);
    for (int d = 0; d < 3; ++d) {
      f.position.push_back(double(k) + 0.001 * x + 0.1 * d);
      f.velocity.push_back(-0.5 * double(k) + x * 1e-3 - d);
      f.angular_velocity.push_back(1e3 * double(d) - x - double(k) * 1e-2);
    }
  }
  return f;
}

SeriesRow make_row(std::int64_t r, std::size_t walls) {
  SeriesRow row;
  row.time = 0.0005 * double(r);
  row.step = 500 * r;
  row.kinetic_energy = 1.5 + double(r);
  row.rotational_energy = 0.25 * double(r);
  row.contacts = 40 + r;
  for (std::size_t w = 0; w < walls; ++w)
    for (int d = 0; d < 3; ++d)
      row.wall_force.push_back(double(r) * 10 + double(w) + 0.1 * d);
  return row;
}

// ------------------------------------------------------------------------------------------------
// HDF5 read helpers (C API). They hold the process-wide HDF5 lock while a file is open.

struct H5File {
  std::lock_guard<std::mutex> lock{cgdem::hdf5_mutex()};
  hid_t id = -1;
  explicit H5File(const std::string& p) {
    H5E_auto2_t f;
    void* d;
    H5Eget_auto2(H5E_DEFAULT, &f, &d);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    id = H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    H5Eset_auto2(H5E_DEFAULT, f, d);
  }
  ~H5File() {
    if (id >= 0) H5Fclose(id);
  }
  bool ok() const { return id >= 0; }
};

bool exists(hid_t loc, const std::string& path) {
  // Check each component so that missing intermediate groups are not an error.
  std::string cur;
  std::stringstream ss(path);
  std::string part;
  while (std::getline(ss, part, '/')) {
    if (part.empty()) continue;
    cur += "/" + part;
    if (H5Lexists(loc, cur.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return true;
}

std::vector<hsize_t> dims_of(hid_t loc, const std::string& name, std::vector<hsize_t>* maxdims = nullptr) {
  hid_t ds = H5Dopen2(loc, name.c_str(), H5P_DEFAULT);
  if (ds < 0) return {};
  hid_t sp = H5Dget_space(ds);
  int rank = H5Sget_simple_extent_ndims(sp);
  std::vector<hsize_t> d(static_cast<std::size_t>(rank)), m(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(sp, d.data(), m.data());
  if (maxdims) *maxdims = m;
  H5Sclose(sp);
  H5Dclose(ds);
  return d;
}

bool has_type(hid_t loc, const std::string& name, hid_t expected) {
  hid_t ds = H5Dopen2(loc, name.c_str(), H5P_DEFAULT);
  if (ds < 0) return false;
  hid_t t = H5Dget_type(ds);
  bool eq = H5Tequal(t, expected) > 0;
  H5Tclose(t);
  H5Dclose(ds);
  return eq;
}

template <class T>
std::vector<T> read_ds(hid_t loc, const std::string& name, hid_t mem_type) {
  hid_t ds = H5Dopen2(loc, name.c_str(), H5P_DEFAULT);
  if (ds < 0) throw std::runtime_error("cannot open dataset " + name);
  hid_t sp = H5Dget_space(ds);
  hssize_t n = H5Sget_simple_extent_npoints(sp);
  std::vector<T> v(static_cast<std::size_t>(n));
  herr_t r = n > 0 ? H5Dread(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) : 0;
  H5Sclose(sp);
  H5Dclose(ds);
  if (r < 0) throw std::runtime_error("cannot read dataset " + name);
  return v;
}
std::vector<double> read_f64(hid_t loc, const std::string& name) {
  return read_ds<double>(loc, name, H5T_NATIVE_DOUBLE);
}
std::vector<std::int64_t> read_i64(hid_t loc, const std::string& name) {
  return read_ds<std::int64_t>(loc, name, H5T_NATIVE_INT64);
}
std::vector<std::int32_t> read_i32(hid_t loc, const std::string& name) {
  return read_ds<std::int32_t>(loc, name, H5T_NATIVE_INT32);
}

// Attribute of the object at obj_path; file type checked against expected (H5T_STRING class for strings).
template <class T>
T read_attr(hid_t file, const std::string& obj_path, const char* name, hid_t mem_type, hid_t expected_type) {
  hid_t a = H5Aopen_by_name(file, obj_path.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(std::string("no attribute ") + name + " on " + obj_path);
  hid_t t = H5Aget_type(a);
  const bool eq = H5Tequal(t, expected_type) > 0;
  H5Tclose(t);
  T v{};
  herr_t r = H5Aread(a, mem_type, &v);
  H5Aclose(a);
  if (!eq) throw std::runtime_error(std::string("attribute ") + name + " has the wrong type");
  if (r < 0) throw std::runtime_error(std::string("cannot read attribute ") + name);
  return v;
}
double attr_f64(hid_t f, const std::string& o, const char* n) {
  return read_attr<double>(f, o, n, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
}
std::int64_t attr_i64(hid_t f, const std::string& o, const char* n) {
  return read_attr<std::int64_t>(f, o, n, H5T_NATIVE_INT64, H5T_STD_I64LE);
}
std::int32_t attr_i32(hid_t f, const std::string& o, const char* n) {
  return read_attr<std::int32_t>(f, o, n, H5T_NATIVE_INT32, H5T_STD_I32LE);
}
std::string attr_str(hid_t f, const std::string& o, const char* n) {
  hid_t a = H5Aopen_by_name(f, o.c_str(), n, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(std::string("no attribute ") + n);
  hid_t ft = H5Aget_type(a);
  const bool is_str = H5Tget_class(ft) == H5T_STRING && H5Tis_variable_str(ft) > 0;
  H5Tclose(ft);
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char* p = nullptr;
  herr_t r = is_str ? H5Aread(a, t, &p) : -1;
  H5Tclose(t);
  H5Aclose(a);
  if (r < 0) throw std::runtime_error(std::string("cannot read string attribute ") + n);
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

std::vector<std::string> children(hid_t file, const std::string& group) {
  std::vector<std::string> names;
  hid_t g = H5Gopen2(file, group.c_str(), H5P_DEFAULT);
  if (g < 0) return names;
  H5Literate(
      g, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* d) -> herr_t {
        static_cast<std::vector<std::string>*>(d)->push_back(name);
        return 0;
      },
      &names);
  H5Gclose(g);
  return names;
}

std::string frame_group(std::int64_t k) {
  char b[32];
  std::snprintf(b, sizeof b, "/frames/%06lld", static_cast<long long>(k));
  return b;
}

// Checks every dataset of frame k against make_frame(k, n); returns "" or a description of the mismatch.
std::string verify_frame(hid_t f, std::int64_t k, std::size_t n, bool all_fields) {
  const FrameData e = make_frame(k, n);
  const std::string g = frame_group(k);
  try {
    if (attr_f64(f, g, "time") != e.time) return g + ": time";
    if (attr_i64(f, g, "step") != e.step) return g + ": step";
    if (read_i64(f, g + "/id") != e.id) return g + ": id";
    if (read_f64(f, g + "/position") != e.position) return g + ": position";
    if (read_f64(f, g + "/radius") != e.radius) return g + ": radius";
    if (dims_of(f, g + "/position") != std::vector<hsize_t>{n, 3}) return g + ": position shape";
    if (all_fields) {
      if (read_f64(f, g + "/velocity") != e.velocity) return g + ": velocity";
      if (read_f64(f, g + "/angular_velocity") != e.angular_velocity) return g + ": angular_velocity";
      if (read_f64(f, g + "/mass") != e.mass) return g + ": mass";
      if (read_i32(f, g + "/group") != e.group) return g + ": group";
    }
  } catch (const std::exception& ex) {
    return g + ": " + ex.what();
  }
  return "";
}

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct XdmfItem {
  std::vector<hsize_t> dims;
  std::string number_type, precision, file, dataset;
};

// Every DataItem of the XDMF text, plus the number of Uniform grids and their Topology sizes.
struct XdmfInfo {
  std::vector<XdmfItem> items;
  std::vector<std::string> grid_names;
  std::vector<hsize_t> topology_sizes;
  bool well_formed = false;
};

XdmfInfo parse_xdmf(const std::string& text) {
  XdmfInfo x;
  x.well_formed = text.find("<Xdmf") != std::string::npos && text.find("</Xdmf>") != std::string::npos &&
                  text.find("CollectionType=\"Temporal\"") != std::string::npos;
  static const std::regex item_re(
      "<DataItem Dimensions=\"([0-9 ]*)\" NumberType=\"(\\w+)\" Precision=\"(\\d+)\" "
      "Format=\"HDF\">([^<:]+):([^<]+)</DataItem>");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), item_re); it != std::sregex_iterator();
       ++it) {
    XdmfItem item;
    std::stringstream ds((*it)[1].str());
    hsize_t d;
    while (ds >> d)
      item.dims.push_back(d);
    item.number_type = (*it)[2];
    item.precision = (*it)[3];
    item.file = (*it)[4];
    item.dataset = (*it)[5];
    x.items.push_back(item);
  }
  static const std::regex grid_re("<Grid Name=\"([^\"]+)\" GridType=\"Uniform\">");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), grid_re); it != std::sregex_iterator(); ++it)
    x.grid_names.push_back((*it)[1]);
  static const std::regex topo_re("TopologyType=\"Polyvertex\" NumberOfElements=\"(\\d+)\"");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), topo_re); it != std::sregex_iterator(); ++it)
    x.topology_sizes.push_back(std::stoull((*it)[1]));
  return x;
}

// Every dataset the XDMF names exists in the HDF5 file with the stated shape and type. Returns "" if so.
std::string check_xdmf_against_h5(const XdmfInfo& x, hid_t f, const std::string& h5_base) {
  for (const auto& item : x.items) {
    if (item.file != h5_base) return "item names file " + item.file;
    if (!exists(f, item.dataset)) return "missing dataset " + item.dataset;
    if (dims_of(f, item.dataset) != item.dims) return "shape mismatch for " + item.dataset;
    hid_t expected = item.number_type == "Float" ? H5T_IEEE_F64LE
                     : item.precision == "8"     ? H5T_STD_I64LE
                                                 : H5T_STD_I32LE;
    if (item.number_type == "Float" && item.precision != "8") return "precision of " + item.dataset;
    if (!has_type(f, item.dataset, expected)) return "type mismatch for " + item.dataset;
  }
  return "";
}

// ------------------------------------------------------------------------------------------------
// Kill-test child: the test re-executes its own binary with kChildEnv set; this static initializer then
// runs the writer loop before main (and before Kokkos, which the I/O code does not need) until killed.

std::size_t kill_frame_size(std::int64_t k) {
  return std::size_t(20000 + 97 * (k % 13));
}

[[noreturn]] void kill_child(const std::string& dir) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  try {
    ResultWriter w(dir + "/run.h5", test_info(), {"velocity", "angular_velocity", "mass", "group"});
    for (std::int64_t k = 0; k < 100000; ++k) {
      w.write_frame(make_frame(k, kill_frame_size(k)));
      w.write_series(make_row(k, 2));
      if (w.pending() > 6) w.flush(); // bound memory, keep the writer busy
    }
  } catch (const std::exception& e) {
    std::cerr << "kill child: " << e.what() << std::endl;
    std::_Exit(3);
  }
  std::_Exit(0);
}

struct KillChildHook {
  KillChildHook() {
    if (const char* dir = std::getenv(kChildEnv)) kill_child(dir);
  }
} kill_child_hook;

} // namespace

// ==================================================================================================

TEST(ResultWriter, LayoutMatchesContract) {
  TempDir tmp;
  const std::string h5 = tmp / "out.h5";
  const RunInfo info = test_info();
  {
    ResultWriter w(h5, info, {"velocity", "group"});
    for (std::int64_t k = 0; k < 3; ++k)
      w.write_frame(make_frame(k, frame_size(k)));
    w.flush();
    EXPECT_EQ(w.frames_written(), 3);
    EXPECT_EQ(w.pending(), 0u);
    EXPECT_EQ(w.xdmf_path(), tmp / "out.xdmf");
  }
  EXPECT_FALSE(fs::exists(h5 + ".shadow")) << "close removes the shadow";
  EXPECT_FALSE(fs::exists(h5 + ".tmp"));
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(attr_str(f.id, "/", "cgdem_version"), info.cgdem_version);
  EXPECT_EQ(attr_str(f.id, "/", "scene"), info.scene_yaml);
  EXPECT_EQ(attr_str(f.id, "/", "backend"), info.backend);
  EXPECT_EQ(attr_i32(f.id, "/", "threads"), info.threads);
  EXPECT_EQ(attr_f64(f.id, "/", "time_step"), info.time_step);
  EXPECT_EQ(attr_str(f.id, "/", "scaling_law"), info.scaling_law);
  EXPECT_EQ(attr_f64(f.id, "/", "scale_factor"), info.scale_factor);
  EXPECT_EQ(attr_i64(f.id, "/", "frames_complete"), 3);

  EXPECT_EQ(children(f.id, "/frames"), (std::vector<std::string>{"000000", "000001", "000002"}));
  for (std::int64_t k = 0; k < 3; ++k) {
    const std::string g = frame_group(k);
    const hsize_t n = frame_size(k);
    const FrameData e = make_frame(k, n);
    SCOPED_TRACE(g);
    EXPECT_EQ(attr_f64(f.id, g, "time"), e.time);
    EXPECT_EQ(attr_i64(f.id, g, "step"), e.step);
    EXPECT_EQ(children(f.id, g), (std::vector<std::string>{"group", "id", "position", "radius", "velocity"}))
        << "requested fields plus id, position, radius; not mass/angular_velocity";
    EXPECT_EQ(dims_of(f.id, g + "/id"), std::vector<hsize_t>{n});
    EXPECT_EQ(dims_of(f.id, g + "/position"), (std::vector<hsize_t>{n, 3}));
    EXPECT_EQ(dims_of(f.id, g + "/velocity"), (std::vector<hsize_t>{n, 3}));
    EXPECT_EQ(dims_of(f.id, g + "/radius"), std::vector<hsize_t>{n});
    EXPECT_EQ(dims_of(f.id, g + "/group"), std::vector<hsize_t>{n});
    EXPECT_TRUE(has_type(f.id, g + "/id", H5T_STD_I64LE));
    EXPECT_TRUE(has_type(f.id, g + "/position", H5T_IEEE_F64LE));
    EXPECT_TRUE(has_type(f.id, g + "/velocity", H5T_IEEE_F64LE));
    EXPECT_TRUE(has_type(f.id, g + "/radius", H5T_IEEE_F64LE));
    EXPECT_TRUE(has_type(f.id, g + "/group", H5T_STD_I32LE));
    EXPECT_EQ(read_i64(f.id, g + "/id"), e.id);
    EXPECT_EQ(read_f64(f.id, g + "/position"), e.position);
    EXPECT_EQ(read_f64(f.id, g + "/velocity"), e.velocity);
    EXPECT_EQ(read_f64(f.id, g + "/radius"), e.radius);
    EXPECT_EQ(read_i32(f.id, g + "/group"), e.group);
  }
}

TEST(ResultWriter, AllFieldsWrittenWhenRequested) {
  TempDir tmp;
  const std::string h5 = tmp / "all.h5";
  {
    ResultWriter w(h5, test_info({}),
                   {"id", "position", "velocity", "angular_velocity", "radius", "mass", "group"});
    w.write_frame(make_frame(4, 11));
  }
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(children(f.id, "/frames/000000"),
            (std::vector<std::string>{"angular_velocity", "group", "id", "mass", "position", "radius",
                                      "velocity"}));
  EXPECT_EQ(dims_of(f.id, "/frames/000000/angular_velocity"), (std::vector<hsize_t>{11, 3}));
  EXPECT_EQ(dims_of(f.id, "/frames/000000/mass"), std::vector<hsize_t>{11});
  EXPECT_TRUE(has_type(f.id, "/frames/000000/mass", H5T_IEEE_F64LE));
  const FrameData e = make_frame(4, 11);
  EXPECT_EQ(read_f64(f.id, "/frames/000000/angular_velocity"), e.angular_velocity);
  EXPECT_EQ(read_f64(f.id, "/frames/000000/mass"), e.mass);
  EXPECT_EQ(attr_f64(f.id, "/frames/000000", "time"), e.time);
}

TEST(ResultWriter, XdmfNamesOnlyExistingDatasets) {
  TempDir tmp;
  const std::string h5 = tmp / "sim.h5";
  ResultWriter w(h5, test_info(), {"velocity", "mass", "group", "angular_velocity"});
  {
    const XdmfInfo x = parse_xdmf(slurp(w.xdmf_path()));
    EXPECT_TRUE(x.well_formed);
    EXPECT_TRUE(x.grid_names.empty());
  }
  for (std::int64_t k = 0; k < 4; ++k)
    w.write_frame(make_frame(k, frame_size(k)));
  w.flush();
  const std::string text = slurp(tmp / "sim.xdmf");
  const XdmfInfo x = parse_xdmf(text);
  ASSERT_TRUE(x.well_formed);
  EXPECT_EQ(x.grid_names,
            (std::vector<std::string>{"frame_000000", "frame_000001", "frame_000002", "frame_000003"}));
  ASSERT_EQ(x.topology_sizes.size(), 4u);
  for (std::int64_t k = 0; k < 4; ++k)
    EXPECT_EQ(x.topology_sizes[std::size_t(k)], frame_size(k));
  EXPECT_EQ(x.items.size(), 4u * 7u) << "geometry + 6 attributes per frame";
  EXPECT_NE(text.find("GeometryType=\"XYZ\""), std::string::npos);
  EXPECT_NE(text.find("<Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">"),
            std::string::npos);
  EXPECT_NE(text.find("<Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">"),
            std::string::npos);
  static const std::regex time_re("<Time Value=\"([^\"]+)\"/>");
  std::vector<double> times;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), time_re); it != std::sregex_iterator(); ++it)
    times.push_back(std::strtod((*it)[1].str().c_str(), nullptr));
  ASSERT_EQ(times.size(), 4u);
  for (std::int64_t k = 0; k < 4; ++k)
    EXPECT_EQ(times[std::size_t(k)], make_frame(k, 0).time) << "times are exact (17 digits)";
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(check_xdmf_against_h5(x, f.id, "sim.h5"), "");
}

TEST(ResultWriter, SeriesAppendAndWallForceShapes) {
  TempDir tmp;
  const std::string h5 = tmp / "series.h5";
  const std::size_t rows = 5;
  {
    ResultWriter w(h5, test_info(), {});
    for (std::size_t r = 0; r < rows; ++r) {
      SeriesRow row = make_row(std::int64_t(r), 2);
      if (r >= 2 && r <= 3) row.analyses["packing_fraction"] = 0.5 + 0.01 * double(r);
      if (r == 3) row.analyses["coordination"] = 4.5;
      w.write_series(row);
      if (r == 1) w.write_frame(make_frame(0, 3)); // interleaved with frames
      if (r == 2) w.flush();                       // several commits
    }
  }
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(attr_i64(f.id, "/", "series_complete"), std::int64_t(rows));
  EXPECT_EQ(attr_i64(f.id, "/", "frames_complete"), 1);
  std::vector<hsize_t> maxd;
  for (const char* n : {"time", "kinetic_energy", "rotational_energy", "packing_fraction", "coordination"}) {
    const std::string p = std::string("/series/") + n;
    EXPECT_EQ(dims_of(f.id, p, &maxd), std::vector<hsize_t>{rows}) << p;
    EXPECT_EQ(maxd, std::vector<hsize_t>{H5S_UNLIMITED}) << p << " is extendible";
    EXPECT_TRUE(has_type(f.id, p, H5T_IEEE_F64LE)) << p;
  }
  for (const char* n : {"step", "contacts"}) {
    const std::string p = std::string("/series/") + n;
    EXPECT_EQ(dims_of(f.id, p), std::vector<hsize_t>{rows}) << p;
    EXPECT_TRUE(has_type(f.id, p, H5T_STD_I64LE)) << p;
  }
  EXPECT_EQ(children(f.id, "/series/wall_force"), (std::vector<std::string>{"floor", "lid"}));
  for (const char* n : {"floor", "lid"}) {
    const std::string p = std::string("/series/wall_force/") + n;
    EXPECT_EQ(dims_of(f.id, p, &maxd), (std::vector<hsize_t>{rows, 3})) << p;
    EXPECT_EQ(maxd, (std::vector<hsize_t>{H5S_UNLIMITED, 3})) << p;
  }
  const auto time = read_f64(f.id, "/series/time");
  const auto step = read_i64(f.id, "/series/step");
  const auto ke = read_f64(f.id, "/series/kinetic_energy");
  const auto re = read_f64(f.id, "/series/rotational_energy");
  const auto contacts = read_i64(f.id, "/series/contacts");
  const auto floor = read_f64(f.id, "/series/wall_force/floor");
  const auto lid = read_f64(f.id, "/series/wall_force/lid");
  const auto pf = read_f64(f.id, "/series/packing_fraction");
  const auto co = read_f64(f.id, "/series/coordination");
  for (std::size_t r = 0; r < rows; ++r) {
    const SeriesRow e = make_row(std::int64_t(r), 2);
    EXPECT_EQ(time[r], e.time);
    EXPECT_EQ(step[r], e.step);
    EXPECT_EQ(ke[r], e.kinetic_energy);
    EXPECT_EQ(re[r], e.rotational_energy);
    EXPECT_EQ(contacts[r], e.contacts);
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(floor[3 * r + d], e.wall_force[std::size_t(d)]);
      EXPECT_EQ(lid[3 * r + d], e.wall_force[std::size_t(3 + d)]);
    }
    if (r >= 2 && r <= 3)
      EXPECT_EQ(pf[r], 0.5 + 0.01 * double(r));
    else
      EXPECT_TRUE(std::isnan(pf[r])) << "row " << r << " without packing_fraction reads NaN";
    if (r == 3)
      EXPECT_EQ(co[r], 4.5);
    else
      EXPECT_TRUE(std::isnan(co[r]));
  }
}

TEST(ResultWriter, FramesWrittenInOrderWithConcurrentCheckpoints) {
  TempDir tmp;
  const std::string h5 = tmp / "order.h5";
  const std::int64_t frames = 25;
  ResultWriter w(h5, test_info(), {"velocity", "angular_velocity", "mass", "group"});
  CheckpointData cp;
  cp.reals["x"] = {1.0, 2.0};
  for (std::int64_t k = 0; k < frames; ++k) {
    w.write_frame(make_frame(k, frame_size(k)));
    w.write_series(make_row(k, 2));
    cp.step = k;
    cgdem::write_checkpoint(tmp / "cp.h5", cp); // HDF5 from the caller while the writer task runs
  }
  w.flush();
  EXPECT_EQ(w.frames_written(), frames);
  EXPECT_EQ(cgdem::read_checkpoint(tmp / "cp.h5").step, frames - 1);
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(attr_i64(f.id, "/", "frames_complete"), frames);
  EXPECT_EQ(attr_i64(f.id, "/", "series_complete"), frames);
  EXPECT_EQ(children(f.id, "/frames").size(), std::size_t(frames));
  for (std::int64_t k = 0; k < frames; ++k)
    EXPECT_EQ(verify_frame(f.id, k, frame_size(k), true), "");
  EXPECT_EQ(read_i64(f.id, "/series/step").size(), std::size_t(frames));
  const XdmfInfo x = parse_xdmf(slurp(w.xdmf_path()));
  EXPECT_EQ(x.grid_names.size(), std::size_t(frames));
  EXPECT_EQ(check_xdmf_against_h5(x, f.id, "order.h5"), "");
}

TEST(ResultWriter, WriteFrameReturnsWhileLargeFrameIsPending) {
  TempDir tmp;
  ResultWriter w(tmp / "big.h5", test_info(), {"velocity", "angular_velocity", "mass", "group"});
  // The writer task parks in the hook until the test has observed the pending frame. If write_frame waited
  // for the write, it would never return (the hook gives up after 2 minutes and the test fails).
  std::promise<void> gate;
  std::shared_future<void> opened = gate.get_future().share();
  std::atomic<int> hook_calls{0};
  std::atomic<bool> released{false};
  w.set_before_write_hook([&] {
    if (hook_calls++ == 0) released = opened.wait_for(std::chrono::minutes(2)) == std::future_status::ready;
  });
  const std::size_t n = 400000; // ~ 45 MB of particle data
  w.write_frame(make_frame(0, n));
  EXPECT_EQ(w.pending(), 1u) << "write_frame returned before the frame was written";
  EXPECT_EQ(w.frames_written(), 0);
  w.write_series(make_row(0, 2));
  EXPECT_EQ(w.pending(), 2u);
  gate.set_value();
  w.flush();
  EXPECT_TRUE(released);
  EXPECT_EQ(w.pending(), 0u);
  EXPECT_EQ(w.frames_written(), 1);
  H5File f(w.path());
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(dims_of(f.id, "/frames/000000/position"), (std::vector<hsize_t>{n, 3}));
  EXPECT_EQ(verify_frame(f.id, 0, n, true), "");
}

TEST(ResultWriter, InvalidInputRejectedSynchronously) {
  TempDir tmp;
  EXPECT_THROW(ResultWriter(tmp / "a.h5", test_info(), {"temperature"}), std::invalid_argument);
  ResultWriter w(tmp / "b.h5", test_info(), {"mass"});
  FrameData f = make_frame(0, 4);
  f.mass.pop_back();
  EXPECT_THROW(w.write_frame(f), std::invalid_argument);
  FrameData g = make_frame(0, 4);
  g.velocity.clear(); // not requested: fine
  EXPECT_NO_THROW(w.write_frame(g));
  SeriesRow r = make_row(0, 1); // 1 wall's worth for 2 walls
  EXPECT_THROW(w.write_series(r), std::invalid_argument);
  SeriesRow s = make_row(0, 2);
  s.analyses["time"] = 1;
  EXPECT_THROW(w.write_series(s), std::invalid_argument);
  w.flush();
  EXPECT_EQ(w.frames_written(), 1);
  EXPECT_THROW(ResultWriter(tmp / "missing_dir/c.h5", test_info(), {}), std::runtime_error);
}

TEST(ResultWriter, WriterErrorIsReportedAtFlushWithPath) {
  TempDir tmp;
  const std::string dir = tmp / "sub";
  fs::create_directory(dir);
  const std::string h5 = dir + "/doomed.h5";
  ResultWriter w(h5, test_info(), {});
  w.write_frame(make_frame(0, 3));
  w.flush();
  fs::remove_all(dir); // the output directory disappears under the running writer
  w.write_frame(make_frame(1, 3));
  try {
    w.flush();
    FAIL() << "flush should rethrow the writer's error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(h5), std::string::npos) << e.what();
  }
  EXPECT_THROW(w.write_frame(make_frame(2, 3)), std::runtime_error);
  EXPECT_NO_THROW(w.flush()) << "reported once";
}

TEST(ResultWriter, ReplacesPreviousRun) {
  TempDir tmp;
  const std::string h5 = tmp / "again.h5";
  {
    ResultWriter w(h5, test_info(), {});
    for (int k = 0; k < 3; ++k)
      w.write_frame(make_frame(k, 4));
  }
  {
    ResultWriter w(h5, test_info(), {});
    w.write_frame(make_frame(0, 6));
  }
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(children(f.id, "/frames"), std::vector<std::string>{"000000"});
  EXPECT_EQ(verify_frame(f.id, 0, 6, false), "");
  EXPECT_EQ(parse_xdmf(slurp(tmp / "again.xdmf")).grid_names.size(), 1u);
}

// A reader keeping the visible file open (HDF5 takes a shared flock on it) must neither block the writer nor
// see that file change: the writer then rebuilds its shadow instead of writing into the reader's inode.
TEST(ResultWriter, ReaderHoldingTheFileKeepsItsSnapshot) {
  TempDir tmp;
  const std::string h5 = tmp / "live.h5";
  ResultWriter w(h5, test_info(), {});
  w.write_frame(make_frame(0, 5));
  w.flush();
  hid_t reader;
  {
    std::lock_guard<std::mutex> lk(cgdem::hdf5_mutex());
    reader = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  }
  ASSERT_GE(reader, 0);
  for (std::int64_t k = 1; k < 4; ++k) {
    w.write_frame(make_frame(k, 5));
    ASSERT_NO_THROW(w.flush());
  }
  {
    std::lock_guard<std::mutex> lk(cgdem::hdf5_mutex());
    EXPECT_EQ(attr_i64(reader, "/", "frames_complete"), 1) << "the reader's snapshot is unchanged";
    EXPECT_EQ(verify_frame(reader, 0, 5, false), "");
    H5Fclose(reader);
  }
  H5File f(h5);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(attr_i64(f.id, "/", "frames_complete"), 4);
  for (std::int64_t k = 0; k < 4; ++k)
    EXPECT_EQ(verify_frame(f.id, k, 5, false), "");
}

// SIGKILL a writing child at random moments; the visible file must always open and hold a complete prefix.
TEST(ResultWriter, SurvivesSigkillAtRandomMoments) {
  const int kills = 16;
  std::random_device rd;
  const unsigned seed = rd();
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> delay_ms(5, 700);
  int no_file = 0, with_frames = 0, total_frames = 0, max_frames = 0;
  int shadow_unopenable = 0, shadow_mid_write = 0, shadow_partial_frame = 0, shadow_bad_complete = 0;
  std::ostringstream log, tmp_left;
  for (int trial = 0; trial < kills; ++trial) {
    TempDir tmp;
    const std::string env = std::string(kChildEnv) + "=" + tmp.path;
    std::vector<std::string> env_strings;
    for (char** e = environ; *e; ++e)
      env_strings.push_back(*e);
    env_strings.push_back(env);
    std::vector<char*> envp;
    for (auto& s : env_strings)
      envp.push_back(s.data());
    envp.push_back(nullptr);
    char arg0[] = "cgdem_io_kill_child";
    char* argv[] = {arg0, nullptr};
    const int delay = delay_ms(rng);
    pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      ::execve("/proc/self/exe", argv, envp.data());
      std::_Exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay));
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        << "child ended on its own (status " << status << ") before the kill at " << delay << " ms";

    const std::string h5 = tmp / "run.h5";
    SCOPED_TRACE("trial " + std::to_string(trial) + ", kill after " + std::to_string(delay) + " ms, seed " +
                 std::to_string(seed));
    for (const char* t : {"run.h5.tmp", "run.h5.shadow.tmp", "run.xdmf.tmp"})
      if (fs::exists(tmp / t)) tmp_left << t << " ";
    if (!fs::exists(h5)) {
      ++no_file; // killed before the constructor published the file
      EXPECT_FALSE(fs::exists(tmp / "run.xdmf")) << "an XDMF without its HDF5 file";
      log << delay << "ms:nofile ";
      continue;
    }
    std::int64_t fc = -1;
    {
      H5File f(h5);
      ASSERT_TRUE(f.ok()) << "visible file does not open after SIGKILL";
      fc = attr_i64(f.id, "/", "frames_complete");
      const std::int64_t rows = attr_i64(f.id, "/", "series_complete");
      ASSERT_GE(fc, 0);
      EXPECT_EQ(children(f.id, "/frames").size(), std::size_t(fc)) << "frames beyond frames_complete";
      for (std::int64_t k = 0; k < fc; ++k)
        ASSERT_EQ(verify_frame(f.id, k, kill_frame_size(k), true), "");
      const auto step = read_i64(f.id, "/series/step");
      const auto floor = read_f64(f.id, "/series/wall_force/floor");
      ASSERT_EQ(step.size(), std::size_t(rows));
      ASSERT_EQ(floor.size(), std::size_t(3 * rows));
      for (std::int64_t r = 0; r < rows; ++r) {
        ASSERT_EQ(step[std::size_t(r)], make_row(r, 2).step);
        ASSERT_EQ(floor[std::size_t(3 * r + 2)], make_row(r, 2).wall_force[2]);
      }
      if (fs::exists(tmp / "run.xdmf")) {
        const XdmfInfo x = parse_xdmf(slurp(tmp / "run.xdmf"));
        EXPECT_TRUE(x.well_formed);
        EXPECT_LE(x.grid_names.size(), std::size_t(fc)) << "XDMF names frames the file lacks";
        EXPECT_EQ(check_xdmf_against_h5(x, f.id, "run.h5"), "");
      }
    }
    {
      // The shadow is the file that was being written (it lags the visible file by one batch). Count how
      // often the kill interrupted a write to it, and check what it left there.
      H5File s(tmp / "run.h5.shadow");
      hid_t a = s.ok() ? H5Aopen(s.id, "frames_complete", H5P_DEFAULT) : -1;
      if (a < 0) {
        ++shadow_unopenable;
      } else {
        H5Aclose(a);
        const std::int64_t sfc = attr_i64(s.id, "/", "frames_complete");
        const auto groups = children(s.id, "/frames");
        haddr_t eoa = 0;
        H5Fget_eoa(s.id, &eoa);
        // Groups beyond frames_complete, or bytes beyond the stored end of file: the kill hit a write.
        if (std::int64_t(groups.size()) > sfc || fs::file_size(tmp / "run.h5.shadow") > eoa)
          ++shadow_mid_write;
        for (std::int64_t k = 0; k < std::int64_t(groups.size()); ++k)
          if (!verify_frame(s.id, k, kill_frame_size(k), true).empty()) {
            ++(k < sfc ? shadow_bad_complete : shadow_partial_frame);
            break;
          }
      }
    }
    with_frames += fc > 0;
    total_frames += int(fc);
    max_frames = std::max(max_frames, int(fc));
    log << delay << "ms:" << fc << " ";
  }
  std::cout << "[ kill test ] seed " << seed << ", " << kills
            << " kills: frames visible per kill: " << log.str() << "\n[ kill test ] no file yet: " << no_file
            << ", with frames: " << with_frames << ", total frames verified: " << total_frames << " (max "
            << max_frames << ")\n[ kill test ] shadow (the file in flight): unopenable " << shadow_unopenable
            << ", killed mid-write " << shadow_mid_write << ", holding a partial frame "
            << shadow_partial_frame << ", with a bad frame below its frames_complete " << shadow_bad_complete
            << "; tmp files left: " << tmp_left.str() << std::endl;
  RecordProperty("frames_verified", total_frames);
  RecordProperty("shadow_mid_write", shadow_mid_write);
}

// ==================================================================================================

TEST(Checkpoint, RoundTripIsBitwise) {
  TempDir tmp;
  const std::string p = tmp / "state.h5";
  CheckpointData d;
  d.time = 0.1 + 0.2; // not representable exactly in decimal
  d.step = (std::int64_t(1) << 53) + 1;
  double nan_payload;
  const std::uint64_t bits = 0x7ff8dead00beef01ull;
  std::memcpy(&nan_payload, &bits, sizeof bits);
  d.reals["position"] = {1.0 / 3.0,
                         -0.0,
                         5e-324,
                         std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::max(),
                         nan_payload,
                         std::nextafter(1.0, 2.0)};
  d.reals["empty"] = {};
  std::mt19937_64 rng(42);
  std::vector<double> big(100000);
  for (auto& x : big) {
    std::uint64_t b = rng();
    std::memcpy(&x, &b, sizeof x); // arbitrary bit patterns, NaNs included
  }
  d.reals["history.tangential"] = big;
  d.ints["id"] = {0, -1, std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()};
  d.ints["neighbors"] = {};
  d.scalars["wall.lid.z"] = -0.0;
  d.scalars["rng_state"] = nan_payload;
  d.scalars["energy"] = 12.5;
  d.scene_yaml = "name: drum\nunicode: \xce\xbc\xe2\x82\xac\n\ttabs and \"quotes\"\n";
  cgdem::write_checkpoint(p, d);
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  const CheckpointData r = cgdem::read_checkpoint(p);
  auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  EXPECT_TRUE(same_bits(r.time, d.time));
  EXPECT_EQ(r.step, d.step);
  EXPECT_EQ(r.scene_yaml, d.scene_yaml);
  ASSERT_EQ(r.reals.size(), d.reals.size());
  for (const auto& kv : d.reals) {
    ASSERT_TRUE(r.reals.count(kv.first)) << kv.first;
    const auto& got = r.reals.at(kv.first);
    ASSERT_EQ(got.size(), kv.second.size()) << kv.first;
    if (!got.empty()) {
      EXPECT_EQ(std::memcmp(got.data(), kv.second.data(), got.size() * sizeof(double)), 0) << kv.first;
    }
  }
  EXPECT_EQ(r.ints, d.ints);
  ASSERT_EQ(r.scalars.size(), d.scalars.size());
  for (const auto& kv : d.scalars)
    EXPECT_TRUE(same_bits(r.scalars.at(kv.first), kv.second)) << kv.first;

  // Overwriting replaces the file atomically and completely.
  CheckpointData d2;
  d2.step = 7;
  d2.ints["only"] = {1, 2, 3};
  cgdem::write_checkpoint(p, d2);
  const CheckpointData r2 = cgdem::read_checkpoint(p);
  EXPECT_EQ(r2.step, 7);
  EXPECT_TRUE(r2.reals.empty());
  EXPECT_EQ(r2.ints, d2.ints);
}

TEST(Checkpoint, ErrorsNameThePath) {
  TempDir tmp;
  auto expect_error_with = [](const std::function<void()>& f, const std::string& path) {
    try {
      f();
      ADD_FAILURE() << "no exception for " << path;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  const std::string missing = tmp / "nope.h5";
  expect_error_with([&] { cgdem::read_checkpoint(missing); }, missing);
  const std::string no_dir = tmp / "no/such/dir/cp.h5";
  expect_error_with([&] { cgdem::write_checkpoint(no_dir, CheckpointData{}); }, no_dir);
  const std::string garbage = tmp / "garbage.h5";
  std::ofstream(garbage) << "not hdf5 at all";
  expect_error_with([&] { cgdem::read_checkpoint(garbage); }, garbage);
  // A result file is HDF5 but not a checkpoint.
  const std::string result = tmp / "result.h5";
  { ResultWriter w(result, test_info(), {}); }
  expect_error_with([&] { cgdem::read_checkpoint(result); }, result);
  CheckpointData bad;
  bad.reals["a/b"] = {1.0};
  const std::string bad_path = tmp / "bad.h5";
  expect_error_with([&] { cgdem::write_checkpoint(bad_path, bad); }, bad_path);
  EXPECT_FALSE(fs::exists(bad_path));
  EXPECT_FALSE(fs::exists(bad_path + ".tmp"));
}

// Inputs found by fuzzing (scripts/fuzz.sh) that crashed libhdf5 inside read_checkpoint: now an error naming
// the file, and this process lives on.
TEST(Checkpoint, DatasetLargerThanItsFileIsRefusedBeforeAllocation) {
  // A fuzzed checkpoint whose /reals dataset claims 25 GB in a 20 kB file: refused by name, nothing
  // allocated.
  const std::string path = std::string(CGDEM_SOURCE_DIR) + "/tests/fuzz/crashes/checkpoint_huge_dataset.h5";
  ASSERT_TRUE(fs::exists(path)) << path;
  try {
    cgdem::read_checkpoint(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("checkpoint_huge_dataset.h5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("values, more than the 20120-byte file holds"), std::string::npos) << msg;
  }
}

TEST(Checkpoint, FuzzedFilesThatCrashedHdf5GiveAnError) {
  // vlen_heap crashed libhdf5 (SEGV); hdf5_loop made it spin forever, now stopped at the probe's time limit.
  for (const char* name : {"checkpoint_vlen_heap.h5", "checkpoint_hdf5_loop.h5"}) {
    const std::string path = std::string(CGDEM_SOURCE_DIR) + "/tests/fuzz/crashes/" + name;
    ASSERT_TRUE(fs::exists(path)) << path;
    try {
      cgdem::read_checkpoint(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}
