#include "core/result_writer.hpp"
#include "core/hdf5_guard.hpp"
#include "core/hdf5_support.hpp"
#include "core/triangle_mesh.hpp"

#include <hdf5.h>
#include <oneapi/tbb/task_arena.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <variant>

namespace cgdem {

std::mutex& hdf5_mutex() {
  static std::mutex m;
  return m;
}

namespace {

// HDF5 helpers (core/hdf5_support.hpp). Every function here throws std::runtime_error describing what
// failed; the caller adds the file name.
using h5::check;
using h5::check_id;
using h5::Hid;
using h5::vlen_string_type;

// Create or overwrite a scalar attribute.
void set_attr(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, const void* value) {
  htri_t exists = H5Aexists(obj, name);
  check(exists, std::string("query attribute ") + name);
  if (exists > 0) check(H5Adelete(obj, name), std::string("delete attribute ") + name);
  Hid space(H5Screate(H5S_SCALAR), H5Sclose, "create scalar dataspace");
  Hid attr(H5Acreate2(obj, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
           std::string("create attribute ") + name);
  check(H5Awrite(attr, mem_type, value), std::string("write attribute ") + name);
}
void set_attr(hid_t obj, const char* name, double v) {
  set_attr(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
}
void set_attr(hid_t obj, const char* name, std::int64_t v) {
  set_attr(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &v);
}
void set_attr(hid_t obj, const char* name, std::int32_t v) {
  set_attr(obj, name, H5T_STD_I32LE, H5T_NATIVE_INT32, &v);
}
void set_attr(hid_t obj, const char* name, const std::string& v) {
  Hid t = vlen_string_type();
  const char* p = v.c_str();
  set_attr(obj, name, t, t, &p);
}

std::int64_t get_attr_i64(hid_t obj, const char* name) {
  Hid attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, std::string("open attribute ") + name);
  std::int64_t v = 0;
  check(H5Aread(attr, H5T_NATIVE_INT64, &v), std::string("read attribute ") + name);
  return v;
}

// Contiguous dataset of rank 1 (cols == 0) or 2 (N x cols).
void write_dataset(hid_t loc, const char* name, hid_t file_type, hid_t mem_type, const void* data,
                   hsize_t rows, hsize_t cols) {
  hsize_t dims[2] = {rows, cols};
  Hid space(H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose, "create dataspace");
  Hid ds(H5Dcreate2(loc, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
         std::string("create dataset ") + name);
  if (rows > 0)
    check(H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), std::string("write ") + name);
}

Hid open_or_create_group(hid_t loc, const char* name) {
  htri_t exists = H5Lexists(loc, name, H5P_DEFAULT);
  check(exists, std::string("query group ") + name);
  if (exists > 0) return Hid(H5Gopen2(loc, name, H5P_DEFAULT), H5Gclose, std::string("open group ") + name);
  return Hid(H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
             std::string("create group ") + name);
}

// Extendible series dataset: 1-D (cols == 0) or T x cols, chunked, NaN fill for doubles.
void create_series_dataset(hid_t loc, const char* name, hid_t file_type, hsize_t rows, hsize_t cols) {
  const int rank = cols ? 2 : 1;
  hsize_t dims[2] = {rows, cols};
  hsize_t maxdims[2] = {H5S_UNLIMITED, cols};
  hsize_t chunk[2] = {cols ? hsize_t(512) : hsize_t(1024), cols};
  Hid space(H5Screate_simple(rank, dims, maxdims), H5Sclose, "create series dataspace");
  Hid dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create dcpl");
  check(H5Pset_chunk(dcpl, rank, chunk), "set chunk");
  if (H5Tequal(file_type, H5T_IEEE_F64LE) > 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    check(H5Pset_fill_value(dcpl, H5T_NATIVE_DOUBLE, &nan), "set fill value");
  }
  Hid ds(H5Dcreate2(loc, name, file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose,
         std::string("create series dataset ") + name);
}

// Grow a series dataset to `rows` rows and, if value != nullptr, write row rows-1.
void append_row(hid_t loc, const std::string& name, hsize_t rows, hid_t mem_type, const void* value) {
  Hid ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose, "open series dataset " + name);
  Hid old_space(H5Dget_space(ds), H5Sclose, "get dataspace");
  const int rank = H5Sget_simple_extent_ndims(old_space);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(old_space, dims, nullptr);
  if (dims[0] >= rows) throw std::runtime_error("series dataset " + name + " already has the row");
  dims[0] = rows;
  check(H5Dset_extent(ds, dims), "extend series dataset " + name);
  if (!value) return;
  Hid space(H5Dget_space(ds), H5Sclose, "get dataspace");
  hsize_t start[2] = {rows - 1, 0};
  hsize_t count[2] = {1, rank == 2 ? dims[1] : 1};
  check(H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr), "select row");
  Hid mem(H5Screate_simple(rank, count, nullptr), H5Sclose, "create memory dataspace");
  check(H5Dwrite(ds, mem_type, mem, space, H5P_DEFAULT, value), "write series row " + name);
}

// ---------------------------------------------------------------------------------------------------
// POSIX helpers.

[[noreturn]] void sys_fail(const std::string& what) {
  throw std::runtime_error(what + ": " + std::strerror(errno));
}

void fsync_path(const std::string& p, bool directory) {
  int fd = ::open(p.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) sys_fail("open " + p + " for fsync");
  int r = ::fsync(fd);
  int e = errno;
  ::close(fd);
  errno = e;
  if (r != 0 && !(directory && (errno == EINVAL || errno == EROFS))) sys_fail("fsync " + p);
}

std::string dir_of(const std::string& p) {
  auto s = p.find_last_of('/');
  if (s == std::string::npos) return ".";
  if (s == 0) return "/";
  return p.substr(0, s);
}
std::string base_of(const std::string& p) {
  auto s = p.find_last_of('/');
  return s == std::string::npos ? p : p.substr(s + 1);
}

void rename_or_throw(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0) sys_fail("rename " + from + " -> " + to);
}

void copy_file(const std::string& from, const std::string& to) {
  int in = ::open(from.c_str(), O_RDONLY);
  if (in < 0) sys_fail("open " + from);
  int out = ::open(to.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (out < 0) {
    int e = errno;
    ::close(in);
    errno = e;
    sys_fail("create " + to);
  }
  std::vector<char> buf(1 << 20);
  bool ok = true;
  std::string err;
  for (;;) {
    ssize_t n = ::read(in, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      ok = false, err = "read " + from + ": " + std::strerror(errno);
      break;
    }
    if (n == 0) break;
    for (ssize_t off = 0; off < n;) {
      ssize_t w = ::write(out, buf.data() + off, size_t(n - off));
      if (w < 0 && errno == EINTR) continue;
      if (w < 0) {
        ok = false, err = "write " + to + ": " + std::strerror(errno);
        break;
      }
      off += w;
    }
    if (!ok) break;
  }
  if (ok && ::fsync(out) != 0) ok = false, err = "fsync " + to + ": " + std::strerror(errno);
  ::close(in);
  if (::close(out) != 0 && ok) ok = false, err = "close " + to + ": " + std::strerror(errno);
  if (!ok) throw std::runtime_error(err);
}

// Atomically exchange the names a and b. Returns false if only `a -> b` could be done (b's old inode is
// then gone and a no longer exists).
bool exchange_names(const std::string& a, const std::string& b) {
  if (::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0) return true;
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) sys_fail("exchange " + a + " <-> " + b);
  const std::string prev = b + ".prev";
  ::unlink(prev.c_str());
  const bool linked = ::link(b.c_str(), prev.c_str()) == 0;
  rename_or_throw(a, b); // atomic replacement of the visible name
  if (!linked) return false;
  if (std::rename(prev.c_str(), a.c_str()) != 0) {
    ::unlink(prev.c_str());
    return false;
  }
  return true;
}

void write_text_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) sys_fail("create " + tmp);
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0 &&
            ::fsync(fileno(f)) == 0;
  int e = errno;
  if (std::fclose(f) != 0) ok = false;
  if (!ok) {
    ::unlink(tmp.c_str());
    errno = e;
    sys_fail("write " + tmp);
  }
  rename_or_throw(tmp, path);
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
    case '&':
      o += "&amp;";
      break;
    case '<':
      o += "&lt;";
      break;
    case '>':
      o += "&gt;";
      break;
    case '"':
      o += "&quot;";
      break;
    case '\'':
      o += "&apos;";
      break;
    default:
      o += c;
    }
  }
  return o;
}

// ---------------------------------------------------------------------------------------------------
// Fields.

enum Field : unsigned {
  F_ID = 1u << 0,
  F_POSITION = 1u << 1,
  F_VELOCITY = 1u << 2,
  F_ANGULAR_VELOCITY = 1u << 3,
  F_RADIUS = 1u << 4,
  F_MASS = 1u << 5,
  F_GROUP = 1u << 6,
};
struct FieldInfo {
  Field bit;
  const char* name;
  int cols; // 0: N, 3: N x 3
  bool integer;
  int bytes;
};
constexpr FieldInfo kFields[] = {
    {F_POSITION, "position", 3, false, 8},
    {F_VELOCITY, "velocity", 3, false, 8},
    {F_ANGULAR_VELOCITY, "angular_velocity", 3, false, 8},
    {F_RADIUS, "radius", 0, false, 8},
    {F_MASS, "mass", 0, false, 8},
    {F_ID, "id", 0, true, 8},
    {F_GROUP, "group", 0, true, 4},
};
constexpr unsigned kAlwaysWritten = F_ID | F_POSITION | F_RADIUS;

std::size_t field_size(const FrameData& f, Field bit) {
  switch (bit) {
  case F_ID:
    return f.id.size();
  case F_POSITION:
    return f.position.size();
  case F_VELOCITY:
    return f.velocity.size();
  case F_ANGULAR_VELOCITY:
    return f.angular_velocity.size();
  case F_RADIUS:
    return f.radius.size();
  case F_MASS:
    return f.mass.size();
  case F_GROUP:
    return f.group.size();
  }
  return 0;
}

const char* const kBuiltinSeries[] = {"time",     "step",       "kinetic_energy", "rotational_energy",
                                      "contacts", "wall_force", "wall_torque"};

bool is_builtin_series(const std::string& k) {
  for (const char* b : kBuiltinSeries)
    if (k == b) return true;
  return false;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i)
    s += (i ? "," : "") + v[i];
  return s;
}

std::string frame_name(std::int64_t index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06lld", static_cast<long long>(index));
  return buf;
}

struct Op {
  std::int64_t frame_index = -1; // >= 0 for a frame
  // A frame already written to the visible file: its arrays were released and the shadow copies the
  // group from there (H5Ocopy) instead of keeping a second whole frame in memory for the whole run.
  bool frame_in_visible_file = false;
  std::variant<FrameData, SeriesRow> data;
};

struct FrameMeta {
  std::int64_t index;
  double time;
  std::size_t n;
};

} // namespace

// -----------------------------------------------------------------------------------------------------

struct ResultWriter::Impl {
  std::string path, shadow, xdmf, h5_base;
  RunInfo info;
  unsigned fields = kAlwaysWritten;
  std::vector<std::string> field_names;

  // Shared with the caller thread, guarded by mu.
  mutable std::mutex mu;
  std::condition_variable idle_cv;
  std::vector<Op> queue;
  std::size_t pending = 0;
  bool running = false;
  bool failed = false, error_reported = true, closed = false;
  std::string error;
  std::int64_t next_frame = 0;
  std::int64_t frames_visible = 0;
  std::function<void()> hook;

  // Writer-task state (one task at a time).
  std::vector<Op> lagging; // applied to the visible file but not yet to the shadow (frames: no arrays)
  bool shadow_exists = true;
  std::vector<FrameMeta> metas;

  tbb::task_arena arena{1, 0};

  std::string where() const { return "cgdem: result file '" + path + "'"; }

  void create_file(const std::string& p) const {
    H5Guard g;
    Hid fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create fapl");
    check(H5Pset_fclose_degree(fapl, H5F_CLOSE_SEMI), "set close degree");
    Hid file(H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose, "create " + p);
    set_attr(file, "cgdem_version", info.cgdem_version);
    set_attr(file, "scene", info.scene_yaml);
    set_attr(file, "backend", info.backend);
    set_attr(file, "threads", std::int32_t(info.threads));
    set_attr(file, "time_step", info.time_step);
    set_attr(file, "scaling_law", info.scaling_law);
    set_attr(file, "scale_factor", info.scale_factor);
    set_attr(file, "fields", join(field_names));
    set_attr(file, "wall_names", join(info.wall_names));
    {
      Hid frames = open_or_create_group(file, "frames");
      Hid series = open_or_create_group(file, "series");
      for (const char* n : {"time", "kinetic_energy", "rotational_energy"})
        create_series_dataset(series, n, H5T_IEEE_F64LE, 0, 0);
      for (const char* n : {"step", "contacts"})
        create_series_dataset(series, n, H5T_STD_I64LE, 0, 0);
      if (!info.meshes.empty()) {
        Hid meshes = open_or_create_group(file, "meshes");
        for (const auto& m : info.meshes) {
          Hid g = open_or_create_group(meshes, m.name.c_str());
          write_dataset(g, "triangles", H5T_STD_I32LE, H5T_NATIVE_INT32, m.data.triangles.data(),
                        m.data.triangles.size(), 3);
          write_dataset(g, "vertices", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, m.data.vertices.data(),
                        m.data.vertices.size(), 3);
        }
      }
      for (const char* group : {"wall_force", "wall_torque"}) {
        Hid walls = open_or_create_group(series, group);
        for (const auto& w : info.wall_names)
          create_series_dataset(walls, w.c_str(), H5T_IEEE_F64LE, 0, 3);
      }
    }
    set_attr(file, "frames_complete", std::int64_t(0));
    set_attr(file, "series_complete", std::int64_t(0));
    file.close("close " + p);
  }

  void write_frame_group(hid_t file, std::int64_t index, const FrameData& f) const {
    Hid frames(H5Gopen2(file, "frames", H5P_DEFAULT), H5Gclose, "open /frames");
    const std::string name = frame_name(index);
    Hid g(H5Gcreate2(frames, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
          "create /frames/" + name);
    set_attr(g, "time", f.time);
    set_attr(g, "step", std::int64_t(f.step));
    const hsize_t n = f.size();
    for (const auto& fi : kFields) {
      if (!(fields & fi.bit)) continue;
      const void* data = nullptr;
      switch (fi.bit) {
      case F_ID:
        data = f.id.data();
        break;
      case F_POSITION:
        data = f.position.data();
        break;
      case F_VELOCITY:
        data = f.velocity.data();
        break;
      case F_ANGULAR_VELOCITY:
        data = f.angular_velocity.data();
        break;
      case F_RADIUS:
        data = f.radius.data();
        break;
      case F_MASS:
        data = f.mass.data();
        break;
      case F_GROUP:
        data = f.group.data();
        break;
      }
      hid_t ft = fi.integer ? (fi.bytes == 8 ? H5T_STD_I64LE : H5T_STD_I32LE) : H5T_IEEE_F64LE;
      hid_t mt = fi.integer ? (fi.bytes == 8 ? H5T_NATIVE_INT64 : H5T_NATIVE_INT32) : H5T_NATIVE_DOUBLE;
      write_dataset(g, fi.name, ft, mt, data, n, hsize_t(fi.cols));
    }
    // Moving meshes where they are at this frame's time.
    for (const auto& m : info.meshes) {
      if (!m.moves()) continue;
      const Wall& w = m.motion;
      const Vec3 shift = w.point + w.offset(f.time);
      const Real angle = w.angle(f.time);
      std::vector<std::array<double, 3>> v;
      v.reserve(m.data.vertices.size());
      for (const auto& x : m.data.vertices) {
        const Vec3 p = shift + rotate_about(Vec3{x[0], x[1], x[2]} - w.point, w.axis, angle);
        v.push_back({p.x, p.y, p.z});
      }
      write_dataset(g, ("mesh_" + m.name).c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), v.size(), 3);
    }
  }

  void append_series_row(hid_t file, std::int64_t row_index, const SeriesRow& r) const {
    Hid series(H5Gopen2(file, "series", H5P_DEFAULT), H5Gclose, "open /series");
    const hsize_t rows = hsize_t(row_index) + 1;
    // Analysis datasets already present (every non-built-in dataset of /series).
    std::vector<std::string> existing;
    H5Literate(
        series, H5_INDEX_NAME, H5_ITER_INC, nullptr,
        [](hid_t, const char* name, const H5L_info_t*, void* d) -> herr_t {
          static_cast<std::vector<std::string>*>(d)->push_back(name);
          return 0;
        },
        &existing);
    append_row(series, "time", rows, H5T_NATIVE_DOUBLE, &r.time);
    const std::int64_t step = r.step, contacts = r.contacts;
    append_row(series, "step", rows, H5T_NATIVE_INT64, &step);
    append_row(series, "kinetic_energy", rows, H5T_NATIVE_DOUBLE, &r.kinetic_energy);
    append_row(series, "rotational_energy", rows, H5T_NATIVE_DOUBLE, &r.rotational_energy);
    append_row(series, "contacts", rows, H5T_NATIVE_INT64, &contacts);
    {
      Hid walls(H5Gopen2(series, "wall_force", H5P_DEFAULT), H5Gclose, "open /series/wall_force");
      for (std::size_t w = 0; w < info.wall_names.size(); ++w)
        append_row(walls, info.wall_names[w], rows, H5T_NATIVE_DOUBLE, r.wall_force.data() + 3 * w);
    }
    if (H5Lexists(series, "wall_torque", H5P_DEFAULT) > 0) { // files opened for appending may predate it
      Hid walls(H5Gopen2(series, "wall_torque", H5P_DEFAULT), H5Gclose, "open /series/wall_torque");
      for (std::size_t w = 0; w < info.wall_names.size(); ++w)
        append_row(walls, info.wall_names[w], rows, H5T_NATIVE_DOUBLE, r.wall_torque.data() + 3 * w);
    }
    for (const auto& name : existing) {
      if (is_builtin_series(name)) continue;
      auto it = r.analyses.find(name);
      append_row(series, name, rows, H5T_NATIVE_DOUBLE, it == r.analyses.end() ? nullptr : &it->second);
    }
    for (const auto& kv : r.analyses) {
      bool found = false;
      for (const auto& e : existing)
        found = found || e == kv.first;
      if (found) continue;
      create_series_dataset(series, kv.first.c_str(), H5T_IEEE_F64LE, 0, 0); // earlier rows: NaN fill
      append_row(series, kv.first, rows, H5T_NATIVE_DOUBLE, &kv.second);
    }
  }

  // Apply ops (in order) to the closed file p, leaving it closed and fsync'ed.
  void apply(const std::string& p, const std::vector<Op>& a, const std::vector<Op>& b) const {
    {
      H5Guard g;
      Hid fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create fapl");
      check(H5Pset_fclose_degree(fapl, H5F_CLOSE_SEMI), "set close degree");
      Hid file(H5Fopen(p.c_str(), H5F_ACC_RDWR, fapl), H5Fclose, "open " + p);
      std::int64_t frames = get_attr_i64(file, "frames_complete");
      std::int64_t rows = get_attr_i64(file, "series_complete");
      Hid visible; // opened read-only for the first frame copied from it
      for (const auto* ops : {&a, &b}) {
        for (const Op& op : *ops) {
          if (op.frame_index >= 0) {
            if (op.frame_index != frames)
              throw std::runtime_error("frame " + std::to_string(op.frame_index) + " out of order in " + p);
            if (op.frame_in_visible_file) {
              if (visible < 0)
                visible = Hid(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                              "open " + path + " to copy its last frame");
              const std::string name = "/frames/" + frame_name(frames);
              check(H5Ocopy(visible, name.c_str(), file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                    "copy " + name + " from " + path);
            } else {
              write_frame_group(file, frames, std::get<FrameData>(op.data));
            }
            ++frames;
          } else {
            append_series_row(file, rows, std::get<SeriesRow>(op.data));
            ++rows;
          }
        }
      }
      // Counters last: they describe what precedes them.
      set_attr(file, "series_complete", rows);
      set_attr(file, "frames_complete", frames);
      file.close("close " + p);
    }
    fsync_path(p, false);
  }

  std::string xdmf_text() const {
    std::ostringstream x;
    const std::string h5 = xml_escape(h5_base);
    x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      << "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n  <Domain>\n"
      << "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    char tbuf[64];
    for (const FrameMeta& m : metas) {
      const std::string fn = frame_name(m.index);
      std::snprintf(tbuf, sizeof tbuf, "%.17g", m.time);
      auto item = [&](const FieldInfo& fi) {
        std::ostringstream d;
        d << "<DataItem Dimensions=\"" << m.n << (fi.cols ? " 3" : "") << "\" NumberType=\""
          << (fi.integer ? "Int" : "Float") << "\" Precision=\"" << fi.bytes << "\" Format=\"HDF\">" << h5
          << ":/frames/" << fn << "/" << fi.name << "</DataItem>";
        return d.str();
      };
      x << "      <Grid Name=\"frame_" << fn << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << tbuf << "\"/>\n"
        << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << m.n
        << "\" NodesPerElement=\"1\"/>\n"
        << "        <Geometry GeometryType=\"XYZ\">\n          " << item(kFields[0])
        << "\n        </Geometry>\n";
      for (const auto& fi : kFields) {
        if (fi.bit == F_POSITION || !(fields & fi.bit)) continue;
        x << "        <Attribute Name=\"" << fi.name << "\" AttributeType=\""
          << (fi.cols ? "Vector" : "Scalar") << "\" Center=\"Node\">\n          " << item(fi)
          << "\n        </Attribute>\n";
      }
      x << "      </Grid>\n";
    }
    x << "    </Grid>\n";
    // Each mesh wall: its triangles at every frame (static ones with their vertices of time 0).
    for (const auto& mesh : info.meshes) {
      const std::string base = h5 + ":/meshes/" + xml_escape(mesh.name);
      x << "    <Grid Name=\"mesh_" << xml_escape(mesh.name)
        << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
      for (const FrameMeta& m : metas) {
        const std::string fn = frame_name(m.index);
        std::snprintf(tbuf, sizeof tbuf, "%.17g", m.time);
        const std::string vertices =
            mesh.moves() ? h5 + ":/frames/" + fn + "/mesh_" + xml_escape(mesh.name) : base + "/vertices";
        x << "      <Grid Name=\"" << xml_escape(mesh.name) << "_" << fn << "\" GridType=\"Uniform\">\n"
          << "        <Time Value=\"" << tbuf << "\"/>\n"
          << "        <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << mesh.data.triangles.size()
          << "\">\n          <DataItem Dimensions=\"" << mesh.data.triangles.size()
          << " 3\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << base
          << "/triangles</DataItem>\n        </Topology>\n"
          << "        <Geometry GeometryType=\"XYZ\">\n          <DataItem Dimensions=\""
          << mesh.data.vertices.size() << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
          << vertices << "</DataItem>\n        </Geometry>\n      </Grid>\n";
      }
      x << "    </Grid>\n";
    }
    x << "  </Domain>\n</Xdmf>\n";
    return x.str();
  }

  // Write one batch and make it visible (see the header for the protocol).
  void commit(std::vector<Op>& batch) {
    bool done = false;
    if (shadow_exists) {
      try {
        apply(shadow, lagging, batch);
        done = true;
      } catch (const std::exception&) {
        // Shadow unusable (locked by a reader holding the old inode, or damaged): rebuild it below.
      }
    }
    if (!done) {
      const std::string tmp = shadow + ".tmp";
      copy_file(path, tmp);
      rename_or_throw(tmp, shadow);
      apply(shadow, {}, batch);
    }
    shadow_exists = exchange_names(shadow, path);
    fsync_path(dir_of(path), true);
    // Visible now.
    bool new_frames = false;
    for (const Op& op : batch) {
      if (op.frame_index < 0) continue;
      const auto& f = std::get<FrameData>(op.data);
      metas.push_back({op.frame_index, f.time, f.size()});
      new_frames = true;
    }
    if (shadow_exists) {
      lagging = std::move(batch);
      for (Op& op : lagging)
        if (op.frame_index >= 0) {
          op.data = FrameData{};
          op.frame_in_visible_file = true;
        }
    } else {
      lagging.clear();
    }
    {
      std::lock_guard<std::mutex> lk(mu);
      frames_visible = std::int64_t(metas.size());
    }
    if (new_frames) write_text_atomically(xdmf, xdmf_text());
  }

  void drain() {
    for (;;) {
      std::vector<Op> batch;
      std::function<void()> h;
      {
        std::lock_guard<std::mutex> lk(mu);
        if (queue.empty() || failed) {
          running = false;
          idle_cv.notify_all();
          return; // nothing below touches *this
        }
        batch.swap(queue);
        h = hook;
      }
      if (h) h();
      const std::size_t n = batch.size();
      std::string err;
      try {
        commit(batch);
      } catch (const std::exception& e) {
        err = e.what();
      } catch (...) {
        err = "unknown error";
      }
      std::lock_guard<std::mutex> lk(mu);
      if (!err.empty()) {
        failed = true;
        error_reported = false;
        error = where() + ": " + err;
        pending = 0;
        queue.clear();
      } else {
        pending -= n;
      }
    }
  }

  void enqueue(Op op) {
    std::lock_guard<std::mutex> lk(mu);
    if (closed) throw std::runtime_error(where() + ": writer is closed");
    if (failed) throw std::runtime_error(error);
    if (op.frame_index >= 0) op.frame_index = next_frame++;
    queue.push_back(std::move(op));
    ++pending;
    if (!running) {
      running = true;
      arena.enqueue([this] { drain(); });
    }
  }

  void wait_idle() {
    std::unique_lock<std::mutex> lk(mu);
    idle_cv.wait(lk, [&] { return !running; });
  }

  void rethrow_unreported() {
    std::lock_guard<std::mutex> lk(mu);
    if (failed && !error_reported) {
      error_reported = true;
      throw std::runtime_error(error);
    }
  }
};

std::string xdmf_path_for(const std::string& h5_path) {
  const auto slash = h5_path.find_last_of('/');
  const auto dot = h5_path.find_last_of('.');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return (has_ext ? h5_path.substr(0, dot) : h5_path) + ".xdmf";
}

ResultWriter::ResultWriter(const std::string& h5_path, const RunInfo& info,
                           const std::vector<std::string>& fields)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = h5_path;
  m.shadow = h5_path + ".shadow";
  m.xdmf = xdmf_path_for(h5_path);
  m.h5_base = base_of(h5_path);
  m.info = info;
  for (const auto& f : fields) {
    bool known = false;
    for (const auto& fi : kFields)
      if (f == fi.name) m.fields |= fi.bit, known = true;
    if (!known) throw std::invalid_argument("cgdem: unknown output field '" + f + "'");
  }
  for (const auto& fi : kFields)
    if (m.fields & fi.bit) m.field_names.push_back(fi.name);
  for (const auto& w : info.wall_names)
    if (w.empty() || w.find('/') != std::string::npos || w == "." || w == "..")
      throw std::invalid_argument("cgdem: wall name '" + w + "' cannot name an HDF5 dataset");
  try {
    // Old XDMF first: it must never name frames the new file lacks.
    if (::unlink(m.xdmf.c_str()) != 0 && errno != ENOENT) sys_fail("remove " + m.xdmf);
    const std::string tmp = h5_path + ".tmp";
    m.create_file(tmp);
    fsync_path(tmp, false);
    rename_or_throw(tmp, h5_path);
    m.create_file(m.shadow);
    fsync_path(m.shadow, false);
    fsync_path(dir_of(h5_path), true);
    write_text_atomically(m.xdmf, m.xdmf_text());
  } catch (const std::exception& e) {
    throw std::runtime_error(m.where() + ": " + e.what());
  }
}

ResultWriter::~ResultWriter() {
  try {
    close();
  } catch (const std::exception& e) {
    std::cerr << e.what() << std::endl;
  }
}

void ResultWriter::write_frame(FrameData frame) {
  const std::size_t n = frame.size();
  for (const auto& fi : kFields) {
    if (!(impl_->fields & fi.bit)) continue;
    const std::size_t want = fi.cols ? 3 * n : n;
    if (field_size(frame, fi.bit) != want)
      throw std::invalid_argument(impl_->where() + ": frame field '" + fi.name + "' has " +
                                  std::to_string(field_size(frame, fi.bit)) + " values, expected " +
                                  std::to_string(want));
  }
  Op op;
  op.frame_index = 0; // numbered in enqueue
  op.data = std::move(frame);
  impl_->enqueue(std::move(op));
}

void ResultWriter::write_series(SeriesRow row) {
  if (row.wall_torque.empty())
    row.wall_torque.assign(3 * impl_->info.wall_names.size(), std::numeric_limits<double>::quiet_NaN());
  if (row.wall_torque.size() != 3 * impl_->info.wall_names.size())
    throw std::invalid_argument(impl_->where() + ": series row has " +
                                std::to_string(row.wall_torque.size()) +
                                " wall torque values, expected 3 per wall");
  if (row.wall_force.size() != 3 * impl_->info.wall_names.size())
    throw std::invalid_argument(impl_->where() + ": series row has " + std::to_string(row.wall_force.size()) +
                                " wall force values, expected 3 per wall (" +
                                std::to_string(impl_->info.wall_names.size()) + " walls)");
  for (const auto& kv : row.analyses)
    if (kv.first.empty() || kv.first.find('/') != std::string::npos || kv.first == "." || kv.first == ".." ||
        is_builtin_series(kv.first))
      throw std::invalid_argument(impl_->where() + ": analysis name '" + kv.first +
                                  "' cannot be a /series dataset");
  Op op;
  op.frame_index = -1;
  op.data = std::move(row);
  impl_->enqueue(std::move(op));
}

void ResultWriter::flush() {
  impl_->wait_idle();
  impl_->rethrow_unreported();
}

void ResultWriter::close() {
  impl_->wait_idle();
  bool first = false;
  {
    std::lock_guard<std::mutex> lk(impl_->mu);
    first = !impl_->closed;
    impl_->closed = true;
  }
  if (first) {
    ::unlink(impl_->shadow.c_str());
    impl_->shadow_exists = false;
    impl_->lagging.clear();
  }
  impl_->rethrow_unreported();
}

std::size_t ResultWriter::pending() const {
  std::lock_guard<std::mutex> lk(impl_->mu);
  return impl_->pending;
}

std::int64_t ResultWriter::frames_written() const {
  std::lock_guard<std::mutex> lk(impl_->mu);
  return impl_->frames_visible;
}

const std::string& ResultWriter::path() const {
  return impl_->path;
}
const std::string& ResultWriter::xdmf_path() const {
  return impl_->xdmf;
}

void ResultWriter::set_before_write_hook(std::function<void()> hook) {
  std::lock_guard<std::mutex> lk(impl_->mu);
  impl_->hook = std::move(hook);
}

} // namespace cgdem
