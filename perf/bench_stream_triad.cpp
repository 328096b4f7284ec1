// STREAM-like triad a[i] = b[i] + s c[i] on Kokkos' OpenMP backend: the machine's sustainable memory
// bandwidth, the roofline's memory bound for perf/README.md. Three arrays of 2^24 doubles (384 MiB in all,
// far above any cache here); 24 bytes per element are counted, as STREAM does (write-allocate traffic
// not included). Threads from Kokkos' flag: --kokkos-threads=N.
//   build/perf/bench_stream_triad --kokkos-threads=1 ; build/perf/bench_stream_triad --kokkos-threads=2
#include <Kokkos_Core.hpp>
#include <benchmark/benchmark.h>

namespace {

using Space = Kokkos::OpenMP;
using Array = Kokkos::View<double*, Space::memory_space>;

void BM_Triad(benchmark::State& state) {
  const std::size_t n = std::size_t(1) << state.range(0);
  Array a("a", n), b("b", n), c("c", n);
  const Kokkos::RangePolicy<Space> all(0, n);
  // First touch by the same threads and schedule as the timed loop (pages land near their users).
  Kokkos::parallel_for(
      "triad_init", all, KOKKOS_LAMBDA(std::size_t i) {
        a(i) = 0.0;
        b(i) = 1.0;
        c(i) = 2.0;
      });
  Kokkos::fence();
  const double s = 3.0;
  for (auto _ : state) {
    Kokkos::parallel_for(
        "triad", all, KOKKOS_LAMBDA(std::size_t i) { a(i) = b(i) + s * c(i); });
    Kokkos::fence();
  }
  benchmark::DoNotOptimize(a.data());
  const double bytes = 3.0 * sizeof(double) * double(n);
  state.counters["GB"] =
      benchmark::Counter(bytes * 1e-9 * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel("openmp x" + std::to_string(Space::concurrency()));
}
BENCHMARK(BM_Triad)
    ->Arg(24)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

} // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
