#pragma once
// MPI once per process when cgdem is built with it (CGDEM_MPI, CGDEM_HAVE_MPI) and started by mpirun (or
// another launcher); without it, or started by hand, MPI is not initialized and there is one rank.
// Everything else asks world_rank() / world_size() and never includes mpi.h.
namespace cgdem::parallel {

class MpiSession {
public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

bool built_with_mpi();
int world_rank(); // 0 without MPI
int world_size(); // 1 without MPI
// The largest of each rank's value, on every rank (collective; the value itself without MPI).
int max_over_ranks(int value);
// Ends every rank with `code` (one rank's failure would leave the others waiting in a collective).
[[noreturn]] void abort_all(int code);

} // namespace cgdem::parallel
