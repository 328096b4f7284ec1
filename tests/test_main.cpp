// GoogleTest main that brings Kokkos up once for every test (OpenMP and Serial both available).
#include <gtest/gtest.h>
#include <Kokkos_Core.hpp>
#include <cstdlib>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  setenv("OMP_PROC_BIND", "false", 0); // tests share the machine with other processes

  Kokkos::ScopeGuard kokkos(argc, argv);
  return RUN_ALL_TESTS();
}
