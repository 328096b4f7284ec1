#pragma once
// Small helpers over HDF5's C API shared by the result writer, the result reader and the checkpoints:
// an owning identifier, checks that turn a failed call into std::runtime_error (with HDF5's own
// description of the innermost error), the variable-length UTF-8 string type, and attribute reads.
// Callers hold an H5Guard (core/hdf5_guard.hpp) around their HDF5 calls and add the file's name to
// the messages.
#include <hdf5.h>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace cgdem::h5 {

// HDF5's description of the innermost error on its stack, as " (...)", or empty; clears the stack.
inline std::string error_detail() {
  std::string out;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* e, void* d) -> herr_t {
        if (n == 0 && e && e->desc) *static_cast<std::string*>(d) = e->desc;
        return 0;
      },
      &out);
  H5Eclear2(H5E_DEFAULT);
  return out.empty() ? std::string() : " (" + out + ")";
}

[[noreturn]] inline void fail(const std::string& what) {
  throw std::runtime_error(what + error_detail());
}

inline hid_t check_id(hid_t id, const std::string& what) {
  if (id < 0) fail(what);
  return id;
}
inline void check(herr_t r, const std::string& what) {
  if (r < 0) fail(what);
}

// Owning HDF5 identifier.
class Hid {
public:
  Hid() = default;
  Hid(hid_t id, herr_t (*closer)(hid_t), const std::string& what)
      : id_(check_id(id, what)), closer_(closer) {}
  Hid(Hid&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = -1; }
  Hid& operator=(Hid&& o) noexcept {
    std::swap(id_, o.id_);
    std::swap(closer_, o.closer_);
    return *this;
  }
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  ~Hid() {
    if (id_ >= 0 && closer_) closer_(id_);
  }
  operator hid_t() const { return id_; }
  // Close now and report failure (used for files, whose close flushes).
  void close(const std::string& what) {
    hid_t id = id_;
    id_ = -1;
    if (id >= 0) check(closer_(id), what);
  }

private:
  hid_t id_ = -1;
  herr_t (*closer_)(hid_t) = nullptr;
};

// Variable-length UTF-8 strings, as every string attribute of cgdem's files is stored.
inline Hid vlen_string_type() {
  Hid t(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  check(H5Tset_size(t, H5T_VARIABLE), "set string size");
  check(H5Tset_cset(t, H5T_CSET_UTF8), "set string charset");
  return t;
}

inline void read_attr(hid_t obj, const char* name, hid_t mem_type, void* v) {
  Hid a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, std::string("open attribute ") + name);
  check(H5Aread(a, mem_type, v), std::string("read attribute ") + name);
}

inline std::string read_string_attr(hid_t obj, const char* name) {
  Hid a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, std::string("open attribute ") + name);
  Hid ft(H5Aget_type(a), H5Tclose, "get attribute type");
  if (H5Tget_class(ft) != H5T_STRING || H5Tis_variable_str(ft) <= 0)
    throw std::runtime_error(std::string("attribute ") + name + " is not a variable-length string");
  Hid t = vlen_string_type();
  char* p = nullptr;
  check(H5Aread(a, t, &p), std::string("read attribute ") + name);
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

} // namespace cgdem::h5
