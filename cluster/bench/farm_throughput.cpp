// The master's throughput: how many tasks per second rank 0 hands out and gathers when the
// work takes no time, so that only the farm's messages and bookkeeping count.
//   mpirun --oversubscribe -n R build/farm_throughput [chains] [tasks per chain] [payload bytes]
// Prints tasks/s and the bytes per task in each direction (headers included). The payload is
// the size of each task's output (a sweep task of 6 windows at 100 samples/s returns ~300 kB).
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "parallel/farm.hpp"
#include "parallel/mpi_env.hpp"

int main(int argc, char** argv) {
  ajx::parallel::MpiEnvironment mpi(argc, argv);
  const long chains = argc > 1 ? std::atol(argv[1]) : 64;
  const long per_chain = argc > 2 ? std::atol(argv[2]) : 500;
  const long payload = argc > 3 ? std::atol(argv[3]) : 64;
  std::vector<ajx::parallel::Chain> cs;
  if (mpi.is_master()) {
    std::int64_t id = 0;
    for (long c = 0; c < chains; ++c) {
      ajx::parallel::Chain ch;
      ch.id = c;
      ch.carry.assign(8 * 32, std::byte{0});  // a state: 32 doubles, as a sweep's carry
      for (long k = 0; k < per_chain; ++k) ch.tasks.push_back({id++, c, k, ajx::parallel::Bytes(16)});
      cs.push_back(std::move(ch));
    }
  }
  const auto work = [&](const ajx::parallel::Task&, const ajx::parallel::Bytes& carry) {
    ajx::parallel::Outcome o;
    o.ok = true;
    o.carry = carry;
    o.output.assign(std::size_t(payload), std::byte{1});
    return o;
  };
  ajx::parallel::FarmOptions opt;
  opt.threads = 0;  // the master's messages alone: rank 0's own worker thread would take tasks without any
  const ajx::parallel::FarmSummary s = ajx::parallel::run_farm(std::move(cs), work, opt);
  if (mpi.is_master())
    std::printf("ranks %d  tasks %lld  payload %ld B  wall %.3f s  %.0f tasks/s  %.0f B/task to workers  "
                "%.0f B/task to the master\n",
                mpi.size(), (long long)s.done, payload, s.wall_seconds, s.tasks_per_second,
                double(s.bytes_sent) / double(s.done), double(s.bytes_received) / double(s.done));
  return 0;
}
