// Thin checked layer over the few MPI calls the project uses. Knows nothing of physics.
//
// Every MPI call goes through check_mpi: a failure throws MpiError naming the call and MPI's
// own message, e.g. "MPI_Send failed: MPI_ERR_RANK: invalid rank". For that to be possible
// the communicators used must return errors instead of aborting (MPI's default):
// MpiEnvironment sets MPI_ERRORS_RETURN on MPI_COMM_WORLD, and the farm sets it on its own
// duplicate of whatever communicator it is given.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <stdexcept>
#include <vector>

namespace ajx::parallel {

class MpiError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws MpiError "<call> failed: <MPI error string>" unless rc == MPI_SUCCESS.
void check_mpi(int rc, const char* call);

// Rank and size of a communicator (checked).
int comm_rank(MPI_Comm comm);
int comm_size(MPI_Comm comm);

// Whether a launcher (mpirun, mpiexec, srun) started this process as a rank of a job of several,
// known before MPI is initialised: from the launcher's environment (OMPI_COMM_WORLD_SIZE,
// PMI_SIZE, PMIX_RANK).
bool launched_as_rank();

// Rank 0's bytes, on every rank of comm (collective; the others' `bytes` are replaced). A rank
// waits without holding its core (a blocking MPI_Bcast busy-polls in Open MPI), so ranks that
// wait while rank 0 reads its input leave the cores to it.
void broadcast(std::vector<std::byte>& bytes, MPI_Comm comm);

// MPI for the lifetime of main(): initializes MPI (thread level FUNNELED: only the main thread
// calls MPI, helper threads may exist) unless it is already initialized, and finalizes it on
// destruction if this object initialized it. Works without mpirun (a singleton of 1 rank).
// One per process; neither copyable nor movable.
class MpiEnvironment {
 public:
  MpiEnvironment();                          // no command-line arguments passed to MPI
  MpiEnvironment(int& argc, char**& argv);   // MPI may strip its own arguments
  ~MpiEnvironment();
  MpiEnvironment(const MpiEnvironment&) = delete;
  MpiEnvironment& operator=(const MpiEnvironment&) = delete;

  int rank() const { return rank_; }  // in MPI_COMM_WORLD
  int size() const { return size_; }
  bool is_master() const { return rank_ == 0; }

  // Ends every rank of the job now. For fatal errors when size() > 1: finalizing normally
  // while other ranks still wait for messages would hang the job.
  [[noreturn]] void abort(int exit_code) const;

 private:
  void init(int* argc, char*** argv);
  bool owns_ = false;
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace ajx::parallel
