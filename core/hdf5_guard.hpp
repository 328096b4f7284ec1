#pragma once
// Scope guard for HDF5 calls: holds the process-wide HDF5 lock (core/result_writer.hpp: hdf5_mutex) and
// silences HDF5's automatic error printing, so failures surface as our own one-line errors instead.
#include <hdf5.h>
#include <mutex>
#include "core/result_writer.hpp"

namespace cgdem {

class H5Guard {
public:
  H5Guard() : lock_(hdf5_mutex()) {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~H5Guard() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  H5Guard(const H5Guard&) = delete;
  H5Guard& operator=(const H5Guard&) = delete;

private:
  std::lock_guard<std::mutex> lock_;
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

} // namespace cgdem
