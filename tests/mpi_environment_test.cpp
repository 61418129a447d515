// The MPI test configuration itself: ranks start (as root in CI, oversubscribed on 2 cores),
// see each other, and agree on a reduction. The sweep's farm tests build on this.
#include <mpi.h>

#include <cstdio>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  long sum = 0, mine = rank;
  MPI_Allreduce(&mine, &sum, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  const long expected = long(size) * (size - 1) / 2;
  const bool ok = size == 3 && sum == expected;
  if (rank == 0) std::printf("mpi: %d ranks, sum of ranks %ld (expected %ld): %s\n", size, sum, expected, ok ? "1 passed, 0 failed" : "0 passed, 1 failed");
  MPI_Finalize();
  return ok ? 0 : 1;
}
