#pragma once
// The cgdem executable run from a test: a fixture with a scratch directory per test, and readers for
// the HDF5 results it writes.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace cgdem::testing {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CliTest : public ::testing::Test {
protected:
  fs::path dir;
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("cgdem_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
           std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  // shell_prefix runs in the same shell before cgdem (e.g. a ulimit that cgdem inherits).
  Result cgdem(const std::string& args, const std::string& shell_prefix = "") {
    const std::string cmd = "cd '" + dir.string() + "' && " + shell_prefix +
                            " OMP_PROC_BIND=false '" CGDEM_BINARY "' " + args + " > stdout.txt 2> stderr.txt";
    const int status = std::system(cmd.c_str());
    Result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir / "stdout.txt");
    r.err = slurp(dir / "stderr.txt");
    return r;
  }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; }
  // Runs `run_args` ("run SCENE ...") whole into full.h5 and in two parts: to `split` seconds with a
  // checkpoint there (mid.h5, mid.checkpoint.h5), then continued from it to the end (cont.h5). Returns
  // whether all three exited 0.
  bool run_whole_and_in_two_parts(const std::string& run_args, const std::string& split) {
    return cgdem(run_args + " --out full.h5").code == 0 &&
           cgdem(run_args + " --out mid.h5 --set time.end=" + split + " --checkpoint-every " + split).code ==
               0 &&
           cgdem(run_args + " --out cont.h5 --restart mid.checkpoint.h5").code == 0;
  }
};

inline std::vector<double> read_doubles(hid_t file, const std::string& path) {
  hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (d < 0) return {};
  hid_t s = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  std::vector<double> v(n);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s);
  H5Dclose(d);
  return v;
}

inline std::vector<hsize_t> shape(hid_t file, const std::string& path) {
  hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (d < 0) return {};
  hid_t s = H5Dget_space(d);
  std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(s));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  H5Sclose(s);
  H5Dclose(d);
  return dims;
}

inline int frame_count(hid_t file) {
  hid_t g = H5Gopen2(file, "/frames", H5P_DEFAULT);
  H5G_info_t info;
  H5Gget_info(g, &info);
  H5Gclose(g);
  return static_cast<int>(info.nlinks);
}

inline std::string last_frame(hid_t file) {
  char name[32];
  std::snprintf(name, sizeof name, "/frames/%06d", frame_count(file) - 1);
  return name;
}

// Checks that every dataset the XDMF beside `stem`.h5 names exists in `file` with the stated dimensions;
// returns how many it named.
inline int expect_xdmf_matches(hid_t file, const fs::path& xdmf_path, const std::string& stem) {
  const std::string xdmf = slurp(xdmf_path);
  const std::regex item("Dimensions=\"([0-9 ]+)\"[^>]*>\\s*" + stem + "\\.h5:([^<\\s]+)\\s*<");
  int checked = 0;
  for (auto it = std::sregex_iterator(xdmf.begin(), xdmf.end(), item); it != std::sregex_iterator(); ++it) {
    std::vector<hsize_t> dims;
    std::istringstream ds((*it)[1].str());
    for (hsize_t d; ds >> d;)
      dims.push_back(d);
    EXPECT_EQ(shape(file, (*it)[2].str()), dims) << (*it)[2].str();
    ++checked;
  }
  return checked;
}

} // namespace cgdem::testing
