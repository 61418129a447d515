// Signals for a clean stop of an MPI job. Knows nothing of physics.
//
// The master (rank 0) turns SIGINT, SIGTERM and SIGUSR1 into a stop request: a flag the farm
// polls (FarmOptions::stop). The farm then hands out no new task, collects the tasks in
// flight and returns Interrupted. Workers ignore those signals, because a launcher may deliver
// them to every rank and a worker that died would take the job down before the master has
// collected the results in flight.
//
// Open MPI's mpirun answers SIGINT/SIGTERM by sending SIGTERM to every rank and SIGKILL a few
// seconds later, so under mpirun a graceful stop that needs longer must be requested with
// SIGUSR1 (mpirun forwards it to every rank): `kill -USR1 <pid of mpirun>`.
#pragma once

#include <atomic>

namespace ajx::parallel {

// Rank 0: the first SIGINT/SIGTERM/SIGUSR1 sets `flag` (which must outlive the handlers); a
// second SIGINT/SIGTERM while the flag is still set restores the default action and re-raises,
// so an impatient second Ctrl-C still kills the process. Throws std::runtime_error if a
// handler cannot be installed.
void install_stop_handlers(std::atomic<bool>& flag);

// Worker ranks: ignore SIGINT, SIGTERM and SIGUSR1 (the master decides when workers stop).
// Throws std::runtime_error if the disposition cannot be set.
void ignore_stop_signals();

// Back to the default action for those signals (and forget the flag).
void restore_default_signals();

}  // namespace ajx::parallel
