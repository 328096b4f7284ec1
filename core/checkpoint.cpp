#include "core/checkpoint.hpp"
#include "core/crash_probe.hpp"
#include "core/hdf5_guard.hpp"
#include "core/hdf5_support.hpp"

#include <hdf5.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/result_writer.hpp" // hdf5_mutex()

namespace cgdem {
namespace {

constexpr const char* kFormat = "cgdem-checkpoint";
constexpr std::int32_t kFormatVersion = 1;

using h5::check;
using h5::check_id;
using h5::fail;
using h5::Hid;
using h5::read_attr;
using h5::read_string_attr;
using h5::vlen_string_type;

void write_attr(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, const void* v) {
  Hid space(H5Screate(H5S_SCALAR), H5Sclose, "create dataspace");
  Hid a(H5Acreate2(obj, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
        std::string("create attribute ") + name);
  check(H5Awrite(a, mem_type, v), std::string("write attribute ") + name);
}

void check_name(const std::string& kind, const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
    throw std::runtime_error(kind + " name '" + name + "' cannot name an HDF5 dataset");
}

void write_array(hid_t group, const std::string& name, hid_t file_type, hid_t mem_type, const void* data,
                 std::size_t n, bool scalar) {
  hsize_t dims[1] = {hsize_t(n)};
  Hid space(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, dims, nullptr), H5Sclose,
            "create dataspace");
  Hid ds(H5Dcreate2(group, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
         "create dataset " + name);
  if (n > 0) check(H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write dataset " + name);
}

std::vector<std::string> list_names(hid_t group) {
  std::vector<std::string> names;
  check(H5Literate(
            group, H5_INDEX_NAME, H5_ITER_INC, nullptr,
            [](hid_t, const char* name, const H5L_info_t*, void* d) -> herr_t {
              static_cast<std::vector<std::string>*>(d)->push_back(name);
              return 0;
            },
            &names),
        "list group");
  return names;
}

// Reads a dataset stored with exactly the given class and size (no conversion but byte order). Checkpoints
// are written unfiltered, so a dataset claiming more bytes than the whole file is damaged: refused before
// its buffer is allocated (a fuzzed checkpoint claimed 25 GB).
template <class T>
std::vector<T> read_array(hid_t group, const std::string& name, H5T_class_t cls, hid_t mem_type, bool scalar,
                          hsize_t file_bytes) {
  Hid ds(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + name);
  Hid ft(H5Dget_type(ds), H5Tclose, "get type of " + name);
  if (H5Tget_class(ft) != cls || H5Tget_size(ft) != sizeof(T))
    throw std::runtime_error("dataset " + name + " has an unexpected type");
  Hid space(H5Dget_space(ds), H5Sclose, "get dataspace of " + name);
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank != (scalar ? 0 : 1)) throw std::runtime_error("dataset " + name + " has an unexpected shape");
  hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0) fail("size of " + name);
  if (static_cast<hsize_t>(n) > file_bytes / sizeof(T))
    throw std::runtime_error("dataset " + name + " claims " + std::to_string(n) + " values, more than the " +
                             std::to_string(file_bytes) + "-byte file holds");
  std::vector<T> v(static_cast<std::size_t>(n));
  if (n > 0) check(H5Dread(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "read dataset " + name);
  return v;
}

void fsync_or_throw(const std::string& p, bool dir) {
  int fd = ::open(p.c_str(), dir ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) throw std::runtime_error("open " + p + ": " + std::strerror(errno));
  int r = ::fsync(fd);
  int e = errno;
  ::close(fd);
  if (r != 0 && !(dir && (e == EINVAL || e == EROFS)))
    throw std::runtime_error("fsync " + p + ": " + std::strerror(e));
}

std::string dir_of(const std::string& p) {
  auto s = p.find_last_of('/');
  if (s == std::string::npos) return ".";
  return s == 0 ? "/" : p.substr(0, s);
}

void write_file(const std::string& p, const CheckpointData& d) {
  H5Guard g;
  Hid fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create fapl");
  check(H5Pset_fclose_degree(fapl, H5F_CLOSE_SEMI), "set close degree");
  Hid file(H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose, "create " + p);
  {
    Hid st = vlen_string_type();
    const char* fmt = kFormat;
    write_attr(file, "format", st, st, &fmt);
    write_attr(file, "format_version", H5T_STD_I32LE, H5T_NATIVE_INT32, &kFormatVersion);
    write_attr(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &d.time);
    const std::int64_t step = d.step;
    write_attr(file, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &step);
    const char* scene = d.scene_yaml.c_str();
    write_attr(file, "scene", st, st, &scene);
    Hid reals(H5Gcreate2(file, "reals", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create /reals");
    for (const auto& kv : d.reals) {
      check_name("real array", kv.first);
      write_array(reals, kv.first, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, kv.second.data(), kv.second.size(),
                  false);
    }
    Hid ints(H5Gcreate2(file, "ints", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create /ints");
    for (const auto& kv : d.ints) {
      check_name("integer array", kv.first);
      write_array(ints, kv.first, H5T_STD_I64LE, H5T_NATIVE_INT64, kv.second.data(), kv.second.size(), false);
    }
    Hid scalars(H5Gcreate2(file, "scalars", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                "create /scalars");
    for (const auto& kv : d.scalars) {
      check_name("scalar", kv.first);
      write_array(scalars, kv.first, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &kv.second, 1, true);
    }
  }
  file.close("close " + p);
}

} // namespace

void write_checkpoint(const std::string& path, const CheckpointData& data) {
  const std::string tmp = path + ".tmp";
  try {
    write_file(tmp, data);
    fsync_or_throw(tmp, false);
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      throw std::runtime_error("rename " + tmp + ": " + std::strerror(errno));
    fsync_or_throw(dir_of(path), true);
  } catch (const std::exception& e) {
    ::unlink(tmp.c_str());
    throw std::runtime_error("cgdem: cannot write checkpoint '" + path + "': " + e.what());
  }
}

namespace {

CheckpointData read_file(const std::string& path) {
  {
    H5Guard g;
    Hid file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open file");
    hsize_t file_bytes = 0;
    check(H5Fget_filesize(file, &file_bytes), "size of file");
    if (H5Aexists(file, "format") <= 0 || read_string_attr(file, "format") != kFormat)
      throw std::runtime_error("not a cgdem checkpoint");
    std::int32_t version = 0;
    read_attr(file, "format_version", H5T_NATIVE_INT32, &version);
    if (version != kFormatVersion)
      throw std::runtime_error("unsupported checkpoint format version " + std::to_string(version));
    CheckpointData d;
    read_attr(file, "time", H5T_NATIVE_DOUBLE, &d.time);
    std::int64_t step = 0;
    read_attr(file, "step", H5T_NATIVE_INT64, &step);
    d.step = step;
    d.scene_yaml = read_string_attr(file, "scene");
    Hid reals(H5Gopen2(file, "reals", H5P_DEFAULT), H5Gclose, "open /reals");
    for (const auto& n : list_names(reals))
      d.reals[n] = read_array<double>(reals, n, H5T_FLOAT, H5T_NATIVE_DOUBLE, false, file_bytes);
    Hid ints(H5Gopen2(file, "ints", H5P_DEFAULT), H5Gclose, "open /ints");
    for (const auto& n : list_names(ints))
      d.ints[n] = read_array<std::int64_t>(ints, n, H5T_INTEGER, H5T_NATIVE_INT64, false, file_bytes);
    Hid scalars(H5Gopen2(file, "scalars", H5P_DEFAULT), H5Gclose, "open /scalars");
    for (const auto& n : list_names(scalars))
      d.scalars[n] = read_array<double>(scalars, n, H5T_FLOAT, H5T_NATIVE_DOUBLE, true, file_bytes).at(0);
    return d;
  }
}

} // namespace

CheckpointData read_checkpoint(const std::string& path) {
  try {
    // A damaged file can crash libhdf5 itself, or make it loop (found by fuzzing: tests/fuzz/crashes/):
    // read it in a child first.
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (const std::string why = crash_probe([&] { read_file(path); }, probe_time_limit(ec ? 0 : bytes));
        !why.empty())
      throw std::runtime_error(why);
    return read_file(path);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read checkpoint '" + path + "': " + e.what());
  }
}

} // namespace cgdem
