// MPI task farm: runs CHAINS of tasks on the ranks of a communicator. Knows nothing of
// physics: inputs, outputs and carries are opaque bytes.
//
// A chain is an ordered list of tasks. Task k of a chain starts only after task k-1 of the
// same chain has finished, and receives the carry task k-1 returned (task 0 receives the
// chain's initial carry). Chains are independent and run in parallel. A chain may start at
// an index k > 0 with the carry of task k-1: that is how an interrupted sweep resumes.
// A failed task ends its chain: the chain's later tasks are not run and are reported as
// "not run: task <id> of this chain failed".
//
// Rank 0 is the master. It owns the queue and hands ready tasks to workers that ask for work
// (pull model), preferring the ready task of the lowest chain id, and delivers every result
// to on_result in completion order. Its workers are the other ranks and FarmOptions::threads
// threads of its own, which run tasks beside the master's loop (so that with N ranks on N
// cores, N processes integrate); with 1 rank and 1 thread it runs every task itself, with the
// same callbacks and results.
//
// All ranks of the communicator must call run_farm together (it duplicates the communicator,
// so farm messages never mix with the caller's). Only rank 0's chains and callbacks are used.
//
// Errors: a work function that throws yields a failed task (ok = false, error = what()).
// An exception from on_result/on_progress, or invalid chains, stops the farm like a stop
// request: the master collects the tasks in flight (without delivering them), tells the
// workers to stop (they return status Aborted) and rethrows. An MPI failure throws MpiError
// on the rank that saw it; the others cannot continue, so the application should then end the
// job with MpiEnvironment::abort. Messages are limited to 2 GiB (MPI int counts) and assume
// ranks of one architecture (headers travel as raw bytes).
#pragma once

#include <mpi.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ajx::parallel {

using Bytes = std::vector<std::byte>;

struct Task {
  std::int64_t id = 0;     // unique over the whole farm run
  std::int64_t chain = 0;  // id of the chain it belongs to
  std::int64_t index = 0;  // position in the chain: 0, 1, ...
  Bytes input;
};

struct Chain {
  std::int64_t id = 0;
  Bytes carry;              // given to tasks.front(): initial carry, or carry of task index-1
  std::vector<Task> tasks;  // consecutive indices starting anywhere; task.chain == id
};

// What the work function returns. On failure, output may still hold partial data; carry is
// ignored (the chain ends).
struct Outcome {
  bool ok = false;
  Bytes output;
  Bytes carry;  // handed to the next task of the chain
  std::string error;
};

// Runs one task. Called on worker ranks (on rank 0 if the communicator has 1 rank).
using WorkFunction = std::function<Outcome(const Task& task, const Bytes& carry_in)>;

// What rank 0 receives for every task.
struct TaskResult {
  std::int64_t task_id = 0;
  std::int64_t chain = 0;
  std::int64_t index = 0;
  bool ran = false;  // false: not run because an earlier task of the chain failed
  bool ok = false;
  Bytes output;
  Bytes carry;       // carry_out of the task: what a resume of the chain at index+1 needs
  std::string error;
  double wall_seconds = 0;  // of the work function, on the rank that ran it
  int rank = -1;            // that rank (-1 if not run)
};

struct Progress {
  std::int64_t done = 0;       // tasks that ran (ok or failed)
  std::int64_t failed = 0;     // of which failed
  std::int64_t not_run = 0;    // skipped because their chain failed earlier
  std::int64_t total = 0;      // tasks given to run_farm
  std::int64_t in_flight = 0;  // handed out, result not back yet
  double elapsed_seconds = 0;
};

enum class FarmStatus : std::int32_t {
  Completed = 0,    // every task ran or was reported not run
  Interrupted = 1,  // a stop request left tasks that never started (not reported)
  Aborted = 2,      // the master raised an error (invalid chains, a callback threw)
};
const char* to_string(FarmStatus status);

struct FarmOptions {
  MPI_Comm comm = MPI_COMM_WORLD;
  // Polled by the master between messages (and between tasks with 1 rank); may be null.
  const std::atomic<bool>* stop = nullptr;
  // Rank 0 only. Called once per task, in completion order.
  std::function<void(const TaskResult&)> on_result;
  // Rank 0 only, optional: called at most every progress_interval seconds.
  std::function<void(const Progress&)> on_progress;
  double progress_interval = 1.0;
  // Wall-clock bound of one task [s], with >= 2 ranks: task_timeout when > 0, else (when
  // timeout_factor > 0) timeout_factor times the slowest task finished so far, at least
  // min_task_timeout (no bound before the first result). A task whose result has not come back
  // within it is handed to another worker (a stopped or hung rank: MPI cannot cancel it), and
  // its rank is given no more work; after max_attempts such timeouts it is delivered as failed
  // ("no result after ... s on rank r") and its chain ends. A rank given up is listed in
  // FarmSummary::lost_ranks; should its late result come after all, it is dropped (the task ran
  // elsewhere) and the rank works again. The caller must end the job with MPI_Abort while ranks
  // are lost: they will not reach MPI_Finalize.
  double task_timeout = 0.0;
  double timeout_factor = 0.0;
  double min_task_timeout = 60.0;
  int max_attempts = 3;
  // Threads on rank 0 that run tasks beside the master, as its workers (they call no MPI; the
  // work function must then be safe to call from several threads). With >= 2 ranks: 1 (rank 0
  // computes like a worker while the master waits between messages) or 0 (the master alone).
  // With 1 rank: 1, the master runs every task itself; more, that many threads run them.
  int threads = 1;
};

// Complete on rank 0. On worker ranks only status, ranks, wall_seconds and this rank's
// entries of busy_seconds / tasks_per_rank are filled.
struct FarmSummary {
  FarmStatus status = FarmStatus::Completed;
  int ranks = 1;
  std::int64_t total = 0, done = 0, failed = 0, not_run = 0;
  std::int64_t unstarted = 0;              // left over by an interruption
  double wall_seconds = 0;
  std::vector<double> busy_seconds;        // per rank: time spent in the work function
  std::vector<std::int64_t> tasks_per_rank;
  std::uint64_t bytes_sent = 0;            // master -> workers, headers included
  std::uint64_t bytes_received = 0;        // workers -> master
  double tasks_per_second = 0;             // done / wall_seconds
  double result_seconds = 0;               // rank 0: time spent in on_result (the master's own work)
  // Rank 0 with workers (ranks or threads): CPU time of the master's loop (its thread alone:
  // receiving, on_result, handing out, polling), what the master takes of its core.
  double master_cpu_seconds = 0;
  std::vector<int> lost_ranks;             // rank 0: ranks still past FarmOptions::task_timeout at the end
};

// Runs the farm; collective over options.comm. `chains` is read on rank 0 only (pass {} on
// the other ranks). Throws std::invalid_argument on rank 0 for duplicate task or chain ids,
// a task whose chain field differs from its chain, or non-consecutive indices (after telling
// the workers to stop).
FarmSummary run_farm(std::vector<Chain> chains, const WorkFunction& work, const FarmOptions& options = {});

}  // namespace ajx::parallel
