#include "parallel/mpi_session.hpp"

#include <cstdlib>
#ifdef CGDEM_HAVE_MPI
#include <mpi.h>
#endif

namespace cgdem::parallel {

#ifdef CGDEM_HAVE_MPI
// Started by a launcher (mpirun, srun, hydra): its environment says so. A process started by hand does not
// initialize MPI at all: a singleton MPI_Init would spawn Open MPI's daemon and write session files for a
// run that never communicates (and fail where files cannot be written).
namespace {
bool launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}
} // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpirun()) return;
  int provided = 0;
  // Only the main thread calls MPI; the OpenMP threads of the kernels never do.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
}
MpiSession::~MpiSession() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (initialized && !finalized) MPI_Finalize();
}
bool built_with_mpi() {
  return true;
}
int world_rank() {
  int initialized = 0, r = 0;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int world_size() {
  int initialized = 0, s = 1;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}
int max_over_ranks(int value) {
  if (world_size() > 1) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return value;
}
void abort_all(int code) {
  if (world_size() > 1) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}
#else
MpiSession::MpiSession(int&, char**&) {}
MpiSession::~MpiSession() = default;
bool built_with_mpi() {
  return false;
}
int world_rank() {
  return 0;
}
int world_size() {
  return 1;
}
int max_over_ranks(int value) {
  return value;
}
void abort_all(int code) {
  std::exit(code);
}
#endif

} // namespace cgdem::parallel
