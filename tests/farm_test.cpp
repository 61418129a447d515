// The task farm on 1 rank (no mpirun: rank 0 runs every task in process): chain order and
// carries, failures, resume, stop requests, validation, callbacks' errors, progress, the
// signal helpers and the checked MPI layer. The multi-rank behaviour is farm_mpi_test.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "parallel/farm.hpp"
#include "parallel/mpi_env.hpp"
#include "parallel/signals.hpp"

namespace ajx::parallel {
namespace {

// A workload whose outputs depend on the whole carry received (a running hash of the chain's
// inputs), and which refuses a carry that is not its predecessor's.
struct Input {
  std::uint64_t value = 0;
  std::int32_t sleep_us = 0;
  std::int32_t fail = 0;
  std::int32_t throw_ = 0;
};
struct Carry {
  std::int64_t chain = 0;
  std::int64_t last_index = -1;
  std::uint64_t hash = 0;
};

template <class T>
Bytes encode(const T& v) {
  Bytes b(sizeof(T));
  std::memcpy(b.data(), &v, sizeof(T));
  return b;
}
template <class T>
T decode(const Bytes& b) {
  if (b.size() != sizeof(T)) throw std::runtime_error("bad buffer size");
  T v;
  std::memcpy(&v, b.data(), sizeof(T));
  return v;
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  return h * 0xff51afd7ed558ccdull;
}

std::vector<std::int64_t> g_ran;  // ids executed by work(), in order
bool g_effects = true;            // sleeps (off while computing expectations)

Outcome work(const Task& t, const Bytes& carry_in) {
  Carry c = decode<Carry>(carry_in);
  if (c.chain != t.chain || c.last_index != t.index - 1) return {false, {}, {}, "carry out of order"};
  const Input in = decode<Input>(t.input);
  if (g_effects) {
    g_ran.push_back(t.id);
    if (in.sleep_us) std::this_thread::sleep_for(std::chrono::microseconds(in.sleep_us));
  }
  if (in.throw_) throw std::runtime_error("boom");
  if (in.fail) return {false, {}, {}, "asked to fail"};
  c.hash = mix(mix(c.hash, in.value), static_cast<std::uint64_t>(t.id));
  c.last_index = t.index;
  return {true, encode(c.hash * 3 + 1), encode(c), {}};
}

std::int64_t tid(int chain, int index) { return 100 * chain + index; }

std::vector<Chain> make_chains(int n_chains, int length, int sleep_us = 0,
                               std::set<std::pair<int, int>> fail = {}, std::set<std::pair<int, int>> throws = {}) {
  std::vector<Chain> out;
  for (int c = n_chains - 1; c >= 0; --c) {  // reverse order on purpose
    Chain ch{c, encode(Carry{c, -1, static_cast<std::uint64_t>(c) * 7919u}), {}};
    for (int k = 0; k < length; ++k) {
      Input in{static_cast<std::uint64_t>(c * 1000003 + k * 17), sleep_us, fail.count({c, k}) ? 1 : 0,
               throws.count({c, k}) ? 1 : 0};
      ch.tasks.push_back(Task{tid(c, k), c, k, encode(in)});
    }
    out.push_back(std::move(ch));
  }
  return out;
}

// Serial reference, without the farm: id -> output (ok tasks only).
std::map<std::int64_t, Bytes> expected_outputs(const std::vector<Chain>& chains) {
  g_effects = false;
  std::map<std::int64_t, Bytes> out;
  for (const Chain& ch : chains) {
    Bytes carry = ch.carry;
    for (const Task& t : ch.tasks) {
      Outcome o;
      try {
        o = work(t, carry);
      } catch (const std::exception&) {
        break;
      }
      if (!o.ok) break;
      out[t.id] = o.output;
      carry = o.carry;
    }
  }
  g_effects = true;
  return out;
}

struct FarmRun {
  FarmSummary summary;
  std::map<std::int64_t, TaskResult> results;
  std::vector<std::int64_t> order;  // ids in delivery order
  int duplicates = 0;
};

FarmRun run(std::vector<Chain> chains, FarmOptions opt = {}) {
  FarmRun r;
  auto user = opt.on_result;
  opt.on_result = [&](const TaskResult& res) {
    if (!r.results.emplace(res.task_id, res).second) ++r.duplicates;
    r.order.push_back(res.task_id);
    if (user) user(res);
  };
  g_ran.clear();
  r.summary = run_farm(std::move(chains), work, opt);
  return r;
}

std::map<std::int64_t, Bytes> ok_outputs(const FarmRun& r) {
  std::map<std::int64_t, Bytes> out;
  for (const auto& [id, res] : r.results)
    if (res.ok) out[id] = res.output;
  return out;
}

TEST(Farm, EveryTaskRunsOnceInChainOrderAndMatchesSerial) {
  const auto chains = make_chains(7, 6);
  const FarmRun r = run(chains);
  EXPECT_EQ(r.summary.status, FarmStatus::Completed);
  EXPECT_EQ(r.summary.ranks, 1);
  EXPECT_EQ(r.summary.total, 42);
  EXPECT_EQ(r.summary.done, 42);
  EXPECT_EQ(r.summary.failed + r.summary.not_run + r.summary.unstarted, 0);
  EXPECT_EQ(r.duplicates, 0);
  EXPECT_EQ(g_ran.size(), 42u);
  EXPECT_EQ(std::set<std::int64_t>(g_ran.begin(), g_ran.end()).size(), 42u);
  EXPECT_EQ(ok_outputs(r), expected_outputs(chains));
  for (const auto& [id, res] : r.results) {
    EXPECT_TRUE(res.ran && res.ok) << id;
    EXPECT_EQ(res.rank, 0);
    EXPECT_EQ(res.chain, id / 100);
    EXPECT_EQ(res.index, id % 100);
    EXPECT_EQ(decode<Carry>(res.carry).last_index, res.index);  // the carry for a resume
  }
  EXPECT_EQ(r.summary.tasks_per_rank, std::vector<std::int64_t>{42});
  ASSERT_EQ(r.summary.busy_seconds.size(), 1u);
  EXPECT_GE(r.summary.busy_seconds[0], 0.0);
  EXPECT_EQ(r.summary.bytes_sent + r.summary.bytes_received, 0u);  // nothing moved between ranks
  EXPECT_GT(r.summary.tasks_per_second, 0.0);
}

TEST(Farm, PrefersTheLowestReadyChain) {
  // One rank: the lowest chain is always ready again after its task, so chains run one by one.
  const FarmRun r = run(make_chains(4, 3));
  std::vector<std::int64_t> want;
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 3; ++k) want.push_back(tid(c, k));
  EXPECT_EQ(r.order, want);
}

TEST(Farm, FailedTaskEndsOnlyItsChain) {
  const auto chains = make_chains(5, 6, 0, {{2, 3}, {4, 0}}, {{1, 5}});
  const FarmRun r = run(chains);
  EXPECT_EQ(r.summary.status, FarmStatus::Completed);
  EXPECT_EQ(r.results.size(), 30u);
  EXPECT_EQ(r.summary.failed, 3);
  EXPECT_EQ(r.summary.not_run, 2 + 5);
  EXPECT_EQ(r.summary.done, 30 - 7);
  const TaskResult& f = r.results.at(tid(2, 3));
  EXPECT_TRUE(f.ran);
  EXPECT_FALSE(f.ok);
  EXPECT_EQ(f.error, "asked to fail");
  const TaskResult& e = r.results.at(tid(1, 5));
  EXPECT_FALSE(e.ok);
  EXPECT_EQ(e.error, "exception: boom");  // a throwing work function is a failed task
  for (int k = 4; k < 6; ++k) {
    const TaskResult& n = r.results.at(tid(2, k));
    EXPECT_FALSE(n.ran);
    EXPECT_FALSE(n.ok);
    EXPECT_EQ(n.rank, -1);
    EXPECT_EQ(n.error, "not run: task 203 of this chain failed");
    EXPECT_EQ(std::count(g_ran.begin(), g_ran.end(), tid(2, k)), 0);  // never executed
  }
  EXPECT_EQ(r.results.at(tid(4, 5)).error, "not run: task 400 of this chain failed");
  // The failure is delivered before the chain's not-run reports.
  const auto pos = [&](std::int64_t id) { return std::find(r.order.begin(), r.order.end(), id) - r.order.begin(); };
  EXPECT_LT(pos(tid(2, 3)), pos(tid(2, 4)));
  // Other chains complete with the serial outputs.
  const auto want = expected_outputs(chains);
  EXPECT_EQ(ok_outputs(r), want);
  EXPECT_EQ(want.size(), 30u - 10u);
}

TEST(Farm, ResumeFromTheMiddleGivesTheSameOutputs) {
  const auto chains = make_chains(4, 8);
  const FarmRun full = run(chains);
  std::vector<Chain> resumed;
  std::map<std::int64_t, Bytes> want;
  for (Chain ch : chains) {
    const int k = 1 + static_cast<int>(ch.id) * 2;  // 1, 3, 5, 7
    ch.carry = full.results.at(tid(static_cast<int>(ch.id), k - 1)).carry;
    ch.tasks.erase(ch.tasks.begin(), ch.tasks.begin() + k);
    for (const Task& t : ch.tasks) want[t.id] = full.results.at(t.id).output;
    resumed.push_back(std::move(ch));
  }
  const FarmRun r = run(resumed);
  EXPECT_EQ(r.summary.status, FarmStatus::Completed);
  EXPECT_EQ(r.summary.total, 7 + 5 + 3 + 1);
  EXPECT_EQ(ok_outputs(r), want);
  EXPECT_EQ(g_ran.size(), want.size());
}

TEST(Farm, StopRequestInterruptsAndTheRestResumes) {
  const auto chains = make_chains(3, 10, 200);
  std::atomic<bool> stop{false};
  FarmOptions opt;
  opt.stop = &stop;
  int seen = 0;
  opt.on_result = [&](const TaskResult&) {
    if (++seen == 5) stop = true;
  };
  const FarmRun r = run(chains, opt);
  EXPECT_EQ(r.summary.status, FarmStatus::Interrupted);
  EXPECT_EQ(r.results.size(), 5u);  // one rank: nothing else was in flight
  EXPECT_EQ(g_ran.size(), 5u);
  EXPECT_EQ(r.summary.done, 5);
  EXPECT_EQ(r.summary.unstarted, 25);
  // Resume every chain after its last delivered task.
  std::vector<Chain> rest;
  for (Chain ch : chains) {
    std::size_t k = 0;
    while (k < ch.tasks.size() && r.results.count(ch.tasks[k].id)) ++k;
    if (k > 0) ch.carry = r.results.at(ch.tasks[k - 1].id).carry;
    ch.tasks.erase(ch.tasks.begin(), ch.tasks.begin() + static_cast<std::ptrdiff_t>(k));
    rest.push_back(std::move(ch));
  }
  const FarmRun r2 = run(rest);
  EXPECT_EQ(r2.summary.status, FarmStatus::Completed);
  auto all = ok_outputs(r);
  for (const auto& [id, out] : ok_outputs(r2)) EXPECT_TRUE(all.emplace(id, out).second) << "ran twice: " << id;
  EXPECT_EQ(all, expected_outputs(chains));
}

// FarmOptions::threads on one rank: that many threads integrate at once, each task runs once in
// its chain's order, and the outputs are the serial ones; a stop request leaves only what was
// in flight, and the rest resumes to the same outputs.
TEST(Farm, ThreadsOnOneRankRunAtOnceWithTheSameOutputs) {
  std::atomic<int> running{0}, most{0}, calls{0};
  const WorkFunction threaded = [&](const Task& t, const Bytes& carry) {
    const int now = ++running;
    for (int m = most.load(); now > m && !most.compare_exchange_weak(m, now);) {
    }
    ++calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    --running;
    return work(t, carry);  // with g_effects off: it only hashes (g_ran is not for threads)
  };
  const auto chains = make_chains(8, 4);
  const auto want = expected_outputs(chains);
  g_effects = false;
  FarmOptions opt;
  opt.threads = 3;
  std::map<std::int64_t, Bytes> got;
  std::map<std::int64_t, std::int64_t> last;  // per chain: the last index delivered
  bool in_order = true;
  opt.on_result = [&](const TaskResult& r) {
    EXPECT_TRUE(r.ok) << r.error;
    got[r.task_id] = r.output;
    auto [it, fresh] = last.emplace(r.chain, r.index);
    if (!fresh) in_order = in_order && r.index == it->second + 1, it->second = r.index;
  };
  const FarmSummary s = run_farm(chains, threaded, opt);
  EXPECT_EQ(s.status, FarmStatus::Completed);
  EXPECT_EQ(got, want);
  EXPECT_TRUE(in_order);
  EXPECT_EQ(calls.load(), 32);
  EXPECT_EQ(most.load(), 3);  // 8 chains ready, 3 threads: all three busy at once
  EXPECT_EQ(s.tasks_per_rank, std::vector<std::int64_t>{32});
  EXPECT_GT(s.busy_seconds[0], 2.5 * 32 * 0.005 / 3);  // summed over the threads

  // Stop after 5 results: at most the 2 others in flight are delivered; the rest resumes.
  std::atomic<bool> stop{false};
  FarmOptions o2;
  o2.threads = 3;
  o2.stop = &stop;
  std::map<std::int64_t, TaskResult> first;
  o2.on_result = [&](const TaskResult& r) {
    first.emplace(r.task_id, r);
    if (first.size() == 5) stop = true;
  };
  const FarmSummary s2 = run_farm(chains, threaded, o2);
  EXPECT_EQ(s2.status, FarmStatus::Interrupted);
  EXPECT_GE(first.size(), 5u);
  EXPECT_LE(first.size(), 7u);
  std::vector<Chain> rest;
  for (Chain ch : chains) {
    std::size_t k = 0;
    while (k < ch.tasks.size() && first.count(ch.tasks[k].id)) ++k;
    if (k > 0) ch.carry = first.at(ch.tasks[k - 1].id).carry;
    ch.tasks.erase(ch.tasks.begin(), ch.tasks.begin() + static_cast<std::ptrdiff_t>(k));
    rest.push_back(std::move(ch));
  }
  std::map<std::int64_t, Bytes> all;
  for (const auto& [id, r] : first) all[id] = r.output;
  FarmOptions o3;
  o3.threads = 2;
  o3.on_result = [&](const TaskResult& r) { EXPECT_TRUE(all.emplace(r.task_id, r.output).second) << r.task_id; };
  EXPECT_EQ(run_farm(rest, threaded, o3).status, FarmStatus::Completed);
  g_effects = true;
  EXPECT_EQ(all, want);
}

TEST(Farm, StopAlreadyRequestedRunsNothing) {
  std::atomic<bool> stop{true};
  FarmOptions opt;
  opt.stop = &stop;
  const FarmRun r = run(make_chains(2, 2), opt);
  EXPECT_EQ(r.summary.status, FarmStatus::Interrupted);
  EXPECT_TRUE(r.results.empty());
  EXPECT_TRUE(g_ran.empty());
  EXPECT_EQ(r.summary.unstarted, 4);
}

TEST(Farm, StopAfterTheLastTaskIsCompleted) {
  std::atomic<bool> stop{false};
  FarmOptions opt;
  opt.stop = &stop;
  int seen = 0;
  opt.on_result = [&](const TaskResult&) {
    if (++seen == 4) stop = true;
  };
  EXPECT_EQ(run(make_chains(2, 2), opt).summary.status, FarmStatus::Completed);
}

TEST(Farm, EmptyWorkCompletes) {
  const FarmRun r = run({});
  EXPECT_EQ(r.summary.status, FarmStatus::Completed);
  EXPECT_EQ(r.summary.total, 0);
  const FarmRun r2 = run({Chain{3, {}, {}}});  // a chain with nothing left to do
  EXPECT_EQ(r2.summary.status, FarmStatus::Completed);
}

TEST(Farm, InvalidChainsAreRejectedBeforeAnythingRuns) {
  const auto expect_invalid = [](std::vector<Chain> chains, const std::string& fragment) {
    g_ran.clear();
    try {
      run_farm(std::move(chains), work);
      ADD_FAILURE() << "no exception for " << fragment;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
    EXPECT_TRUE(g_ran.empty());
  };
  auto dup_task = make_chains(2, 3);
  dup_task[0].tasks[1].id = dup_task[1].tasks[0].id;
  expect_invalid(dup_task, "task id used twice");
  auto dup_chain = make_chains(2, 3);
  dup_chain[1].id = dup_chain[0].id;
  expect_invalid(dup_chain, "appears twice");
  auto wrong_chain = make_chains(2, 3);
  wrong_chain[0].tasks[2].chain = 5;
  expect_invalid(wrong_chain, "its chain field is 5");
  auto gap = make_chains(2, 3);
  gap[1].tasks[2].index = 3;
  expect_invalid(gap, "does not follow");
}

TEST(Farm, ExceptionFromOnResultPropagatesAndStopsDelivery) {
  int seen = 0;
  FarmOptions opt;
  opt.on_result = [&](const TaskResult&) {
    if (++seen == 3) throw std::runtime_error("disk full");
  };
  g_ran.clear();
  EXPECT_THROW(
      {
        try {
          run_farm(make_chains(3, 3), work, opt);
        } catch (const std::runtime_error& e) {
          EXPECT_STREQ(e.what(), "disk full");
          throw;
        }
      },
      std::runtime_error);
  EXPECT_EQ(seen, 3);
  EXPECT_EQ(g_ran.size(), 3u);
}

TEST(Farm, ProgressIsRateLimitedAndConsistent) {
  std::vector<Progress> seen;
  FarmOptions opt;
  opt.progress_interval = 0.02;
  opt.on_progress = [&](const Progress& p) { seen.push_back(p); };
  const FarmRun r = run(make_chains(3, 10, 3000, {{1, 4}}), opt);  // about 0.07 s of work
  ASSERT_GE(seen.size(), 2u);
  EXPECT_GE(seen.front().elapsed_seconds, 0.02);
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].total, 30);
    EXPECT_EQ(seen[i].in_flight, 0);  // between tasks, with one rank
    EXPECT_LE(seen[i].done + seen[i].not_run, 30);
    if (i > 0) {
      EXPECT_GE(seen[i].elapsed_seconds - seen[i - 1].elapsed_seconds, 0.02 - 1e-9);
      EXPECT_GE(seen[i].done, seen[i - 1].done);
    }
  }
  EXPECT_LE(seen.back().elapsed_seconds, r.summary.wall_seconds);
}

TEST(Farm, OtherCommunicatorOfOneRankGivesTheSameResults) {
  const auto chains = make_chains(5, 4);
  FarmOptions opt;
  opt.comm = MPI_COMM_SELF;
  EXPECT_EQ(ok_outputs(run(chains, opt)), ok_outputs(run(chains)));
}

TEST(Farm, ManyTinyTasks) {
  const FarmRun r = run(make_chains(40, 50));
  EXPECT_EQ(r.summary.status, FarmStatus::Completed);
  EXPECT_EQ(r.results.size(), 2000u);
  std::printf("measured farm: %.0f tasks/s (2000 tiny tasks in process, 1 rank)\n", r.summary.tasks_per_second);
}

TEST(Mpi, CheckedCallsThrowNamingTheCall) {
  EXPECT_NO_THROW(check_mpi(MPI_SUCCESS, "MPI_Send"));
  try {
    check_mpi(MPI_ERR_RANK, "MPI_Send");
    ADD_FAILURE() << "no exception";
  } catch (const MpiError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("MPI_Send failed: ", 0), 0u) << e.what();
  }
  // A real failing call: rank 5 does not exist (MpiEnvironment made errors return).
  int x = 0;
  try {
    check_mpi(MPI_Send(&x, 1, MPI_INT, 5, 0, MPI_COMM_WORLD), "MPI_Send");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("MPI_Send failed"), std::string::npos) << e.what();
  }
  EXPECT_EQ(comm_rank(MPI_COMM_WORLD), 0);
  EXPECT_EQ(comm_size(MPI_COMM_WORLD), 1);
}

TEST(Signals, StopHandlersSetTheFlagAndWorkersIgnoreSignals) {
  std::atomic<bool> flag{false};
  install_stop_handlers(flag);
  std::raise(SIGINT);
  EXPECT_TRUE(flag.load());
  flag = false;
  std::raise(SIGUSR1);  // what to send to mpirun: it forwards SIGUSR1 to every rank
  EXPECT_TRUE(flag.load());
  std::raise(SIGUSR1);  // repeated SIGUSR1 is harmless
  flag = false;
  std::raise(SIGTERM);
  EXPECT_TRUE(flag.load());
  ignore_stop_signals();
  std::raise(SIGINT);
  std::raise(SIGTERM);
  std::raise(SIGUSR1);
  restore_default_signals();
  SUCCEED() << "still alive";
}

TEST(SignalsDeathTest, SecondInterruptKills) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        std::atomic<bool> flag{false};
        install_stop_handlers(flag);
        std::raise(SIGINT);
        if (!flag.load()) std::_Exit(3);
        std::raise(SIGINT);
        std::_Exit(4);
      },
      testing::KilledBySignal(SIGINT), "");
}

}  // namespace
}  // namespace ajx::parallel

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ajx::parallel::MpiEnvironment env(argc, argv);  // the farm needs MPI even on 1 rank
  return RUN_ALL_TESTS();
}
