// The task farm on several ranks (run under mpiexec with 2 and 3 ranks): every task runs
// exactly once on a worker, each task sees exactly its predecessor's carry, the results equal
// a serial computation and the farm on 1 rank (MPI_COMM_SELF), a failure ends only its chain,
// a resumed chain gives the same outputs, a stop request (through the signal helpers) returns
// Interrupted with every handed-out task delivered, errors on the master stop the workers, and
// many tiny tasks get through (throughput printed); broadcast hands rank 0's bytes to all.
// Prints "N passed, M failed" on rank 0.
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "parallel/farm.hpp"
#include "parallel/mpi_env.hpp"
#include "parallel/signals.hpp"

using namespace ajx::parallel;

namespace {

// ------------------------------------------------------------------------------------------
// A workload whose every output depends on the whole carry it received, so any mistake in
// chain order or carry hand-over changes the outputs; the work function also refuses a carry
// that is not its predecessor's.
struct Input {
  std::uint64_t value = 0;
  std::int32_t sleep_us = 0;
  std::int32_t fail = 0;        // return ok = false
  std::int32_t raise_sig = 0;   // raise this signal in the worker (workers ignore it)
  std::int32_t carry_pad = 0;   // extra carry bytes to hand on
};
struct Carry {
  std::int64_t chain = 0;
  std::int64_t last_index = -1;
  std::uint64_t hash = 0;
};
struct Output {
  std::int64_t task_id = 0;
  std::uint64_t hash = 0;
};

template <class T>
Bytes encode(const T& v, std::size_t extra = 0) {
  Bytes b(sizeof(T) + extra);
  std::memcpy(b.data(), &v, sizeof(T));
  return b;
}
template <class T>
T decode(const Bytes& b) {
  if (b.size() < sizeof(T)) throw std::runtime_error("short buffer");
  T v;
  std::memcpy(&v, b.data(), sizeof(T));
  return v;
}

std::uint64_t fnv(const Bytes& b, std::uint64_t h = 1469598103934665603ull) {
  for (std::byte x : b) h = (h ^ std::to_integer<std::uint64_t>(x)) * 1099511628211ull;
  return h;
}

bool g_record = true;               // false while computing expectations
bool g_effects = true;              // sleeps and signals (off for expectations and replays)
std::vector<std::int64_t> g_ran;    // task ids this rank executed

Outcome work(const Task& t, const Bytes& carry_in) {
  Carry c = decode<Carry>(carry_in);
  if (c.chain != t.chain || c.last_index != t.index - 1)
    return {false, {}, {}, "carry out of order: chain " + std::to_string(c.chain) + " last " + std::to_string(c.last_index)};
  const Input in = decode<Input>(t.input);
  if (g_record) g_ran.push_back(t.id);
  if (g_effects) {
    if (in.raise_sig) std::raise(in.raise_sig);
    if (in.sleep_us) std::this_thread::sleep_for(std::chrono::microseconds(in.sleep_us));
  }
  if (in.fail) return {false, encode(Output{t.id, 0}), {}, "asked to fail"};
  const std::uint64_t h = fnv(t.input, fnv(carry_in)) ^ (static_cast<std::uint64_t>(t.id) * 0x9e3779b97f4a7c15ull);
  c.hash = h;
  c.last_index = t.index;
  Bytes carry = encode(c, static_cast<std::size_t>(in.carry_pad));
  for (std::size_t i = sizeof(Carry); i < carry.size(); ++i) carry[i] = static_cast<std::byte>((h >> (i % 56)) & 0xff);
  return {true, encode(Output{t.id, h}), std::move(carry), {}};
}

struct Spec {
  int chains = 4, length = 4;
  int sleep_min_us = 0, sleep_max_us = 0;
  std::set<std::pair<int, int>> fail;  // (chain, index)
  int input_pad = 0, carry_pad = 0;
  int raise_sig = 0;                   // raised by task (0, 1)
};

std::int64_t task_id(int chain, int index) { return 1000 * chain + index + 7; }

std::vector<Chain> make_chains(const Spec& s) {
  std::vector<Chain> out;
  std::uint64_t rnd = 12345;
  for (int c = s.chains - 1; c >= 0; --c) {  // given in reverse: the farm must not rely on order
    Chain ch;
    ch.id = c;
    ch.carry = encode(Carry{c, -1, 0xabcdefull + static_cast<std::uint64_t>(c)});
    for (int k = 0; k < s.length; ++k) {
      rnd = rnd * 6364136223846793005ull + 1442695040888963407ull;
      Input in;
      in.value = rnd;
      in.sleep_us = s.sleep_min_us + (s.sleep_max_us > s.sleep_min_us ? static_cast<int>((rnd >> 33) % static_cast<std::uint64_t>(s.sleep_max_us - s.sleep_min_us)) : 0);
      in.fail = s.fail.count({c, k}) ? 1 : 0;
      in.raise_sig = (c == 0 && k == 1) ? s.raise_sig : 0;
      in.carry_pad = s.carry_pad;
      Bytes input = encode(in, static_cast<std::size_t>(s.input_pad));
      for (std::size_t i = sizeof(Input); i < input.size(); ++i) input[i] = static_cast<std::byte>((rnd >> (i % 50)) & 0xff);
      ch.tasks.push_back(Task{task_id(c, k), c, k, std::move(input)});
    }
    out.push_back(std::move(ch));
  }
  return out;
}

// Serial reference: the chains run one after the other, without the farm.
std::map<std::int64_t, TaskResult> expected(const std::vector<Chain>& chains) {
  g_record = g_effects = false;
  std::map<std::int64_t, TaskResult> out;
  for (const Chain& ch : chains) {
    Bytes carry = ch.carry;
    std::int64_t failed_id = -1;
    for (const Task& t : ch.tasks) {
      TaskResult r;
      r.task_id = t.id;
      r.chain = t.chain;
      r.index = t.index;
      if (failed_id >= 0) {
        r.error = "not run: task " + std::to_string(failed_id) + " of this chain failed";
      } else {
        Outcome o = work(t, carry);
        r.ran = true;
        r.ok = o.ok;
        r.output = o.output;
        r.error = o.error;
        if (o.ok) r.carry = o.carry, carry = o.carry;
        else failed_id = t.id;
      }
      out[t.id] = r;
    }
  }
  g_record = g_effects = true;
  return out;
}

// ------------------------------------------------------------------------------------------
int g_rank = 0, g_size = 1;
int g_passed = 0, g_failed = 0;

void check(bool ok, const char* what, int line) {
  if (ok) {
    ++g_passed;
  } else {
    ++g_failed;
    std::fprintf(stderr, "rank %d: CHECK failed at line %d: %s\n", g_rank, line, what);
  }
}
#define CHECK(cond) check((cond), #cond, __LINE__)

// All task ids executed on any rank since the last clear (rank 0 gets them; others get {}).
std::vector<std::int64_t> gather_ran() {
  const int n = static_cast<int>(g_ran.size());
  std::vector<int> counts(static_cast<std::size_t>(g_size)), displs(static_cast<std::size_t>(g_size));
  check_mpi(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  int total = 0;
  for (int r = 0; r < g_size; ++r) displs[static_cast<std::size_t>(r)] = total, total += counts[static_cast<std::size_t>(r)];
  std::vector<std::int64_t> all(static_cast<std::size_t>(g_rank == 0 ? total : 0));
  check_mpi(MPI_Gatherv(g_ran.data(), n, MPI_INT64_T, all.data(), counts.data(), displs.data(), MPI_INT64_T, 0, MPI_COMM_WORLD),
            "MPI_Gatherv");
  g_ran.clear();
  return all;
}

bool each_once(const std::vector<std::int64_t>& ids) {
  return std::set<std::int64_t>(ids.begin(), ids.end()).size() == ids.size();
}

bool same(const TaskResult& a, const TaskResult& b) {
  return a.task_id == b.task_id && a.chain == b.chain && a.index == b.index && a.ran == b.ran && a.ok == b.ok &&
         a.output == b.output && a.error == b.error && (!a.ok || a.carry == b.carry);
}

bool same_results(const std::map<std::int64_t, TaskResult>& got, const std::map<std::int64_t, TaskResult>& want) {
  if (got.size() != want.size()) return false;
  for (const auto& [id, r] : want) {
    auto it = got.find(id);
    if (it == got.end() || !same(it->second, r)) return false;
  }
  return true;
}

// Collects results on rank 0; counts deliveries and checks per-chain order.
struct Collector {
  std::map<std::int64_t, TaskResult> results;
  std::vector<std::int64_t> order;  // chain ids in completion order
  std::map<std::int64_t, std::int64_t> last_index;
  int duplicates = 0, out_of_order = 0;

  std::function<void(const TaskResult&)> callback() {
    return [this](const TaskResult& r) {
      if (!results.emplace(r.task_id, r).second) ++duplicates;
      auto [it, fresh] = last_index.emplace(r.chain, r.index);
      if (!fresh) {
        if (r.index != it->second + 1) ++out_of_order;
        it->second = r.index;
      }
      order.push_back(r.chain);
    };
  }
};

// ------------------------------------------------------------------------------------------
std::map<std::int64_t, TaskResult> g_full;  // results of test_basic, for the resume test
Spec g_basic_spec;

void test_basic() {
  Spec s;
  s.chains = 16;
  s.length = 10;
  s.sleep_max_us = 2000;
  s.input_pad = 40;
  s.carry_pad = 24;
  g_basic_spec = s;
  Collector col;
  FarmOptions opt;
  opt.on_result = col.callback();
  const auto chains = g_rank == 0 ? make_chains(s) : std::vector<Chain>{};
  const FarmSummary sum = run_farm(chains, work, opt);
  const auto ran = gather_ran();
  CHECK(sum.status == FarmStatus::Completed);
  if (g_rank != 0) {
    CHECK(sum.tasks_per_rank[static_cast<std::size_t>(g_rank)] > 0);
    return;
  }
  const auto want = expected(chains);
  const std::size_t total = static_cast<std::size_t>(s.chains * s.length);
  CHECK(want.size() == total);
  CHECK(same_results(col.results, want));
  CHECK(col.duplicates == 0);
  CHECK(col.out_of_order == 0);
  CHECK(ran.size() == total);  // every task ran exactly once, somewhere
  CHECK(each_once(ran));
  CHECK(sum.total == static_cast<std::int64_t>(total) && sum.done == sum.total && sum.failed == 0 && sum.not_run == 0 &&
        sum.unstarted == 0);
  CHECK(sum.ranks == g_size);
  // Rank 0's thread (FarmOptions::threads = 1, the default) computes beside the master.
  CHECK(sum.tasks_per_rank[0] > 0 && sum.busy_seconds[0] > 0.0);
  CHECK(std::accumulate(sum.tasks_per_rank.begin(), sum.tasks_per_rank.end(), std::int64_t{0}) == sum.total);
  for (int w = 1; w < g_size; ++w) CHECK(sum.busy_seconds[static_cast<std::size_t>(w)] > 0.0);
  const std::size_t sent_away = total - static_cast<std::size_t>(sum.tasks_per_rank[0]);  // rank 0's ran in process
  CHECK(sum.bytes_sent > sent_away * (40 + sizeof(Input)) && sum.bytes_received > sent_away * sizeof(Output));
  CHECK(sum.tasks_per_second > 0 && sum.wall_seconds > 0);
  bool ranks_ok = true;
  for (const auto& [id, r] : col.results) ranks_ok = ranks_ok && r.rank >= 0 && r.rank < g_size && r.wall_seconds >= 0;
  CHECK(ranks_ok);
  g_full = col.results;

  // The same chains on 1 rank (in process on rank 0): identical results.
  Collector one;
  FarmOptions opt1;
  opt1.comm = MPI_COMM_SELF;
  opt1.on_result = one.callback();
  const FarmSummary s1 = run_farm(chains, work, opt1);
  CHECK(s1.status == FarmStatus::Completed && s1.ranks == 1 && s1.tasks_per_rank[0] == s1.total);
  CHECK(same_results(one.results, col.results));
  g_ran.clear();
  std::printf("basic: %lld tasks in %.3f s on %d ranks (%.0f tasks/s, busy", static_cast<long long>(sum.done),
              sum.wall_seconds, g_size, sum.tasks_per_second);
  for (int w = 0; w < g_size; ++w) std::printf(" %.3f", sum.busy_seconds[static_cast<std::size_t>(w)]);
  std::printf(" s)\n");
}

void test_master_alone() {
  // FarmOptions::threads = 0: rank 0 only hands out and delivers; the same results as test_basic.
  Collector col;
  FarmOptions opt;
  opt.threads = 0;
  opt.on_result = col.callback();
  const FarmSummary sum = run_farm(g_rank == 0 ? make_chains(g_basic_spec) : std::vector<Chain>{}, work, opt);
  const auto ran = gather_ran();
  CHECK(sum.status == FarmStatus::Completed);
  if (g_rank != 0) return;
  CHECK(sum.tasks_per_rank[0] == 0 && sum.busy_seconds[0] == 0.0);  // the master computes nothing
  CHECK(same_results(col.results, g_full) && each_once(ran) && ran.size() == g_full.size());
}

void test_lowest_chain_first() {
  // With one worker the order is fully determined: chain 0 to the end, then chain 1, ...
  if (g_size != 2) return;
  Spec s;
  s.chains = 5;
  s.length = 4;
  Collector col;
  FarmOptions opt;
  opt.threads = 0;  // rank 1 the only worker
  opt.on_result = col.callback();
  run_farm(g_rank == 0 ? make_chains(s) : std::vector<Chain>{}, work, opt);
  gather_ran();
  if (g_rank != 0) return;
  CHECK(col.order.size() == 20);
  CHECK(std::is_sorted(col.order.begin(), col.order.end()));
}

void test_failure() {
  Spec s;
  s.chains = 8;
  s.length = 6;
  s.sleep_max_us = 1000;
  s.fail = {{3, 2}, {5, 0}, {6, 5}};
  Collector col;
  FarmOptions opt;
  opt.on_result = col.callback();
  const auto chains = g_rank == 0 ? make_chains(s) : std::vector<Chain>{};
  const FarmSummary sum = run_farm(chains, work, opt);
  const auto ran = gather_ran();
  CHECK(sum.status == FarmStatus::Completed);
  if (g_rank != 0) return;
  const auto want = expected(chains);
  CHECK(same_results(col.results, want));
  CHECK(col.results.size() == 48 && col.duplicates == 0 && col.out_of_order == 0);
  CHECK(sum.failed == 3 && sum.not_run == 3 + 5 + 0 && sum.done == 48 - 8);
  const TaskResult& f = col.results[task_id(3, 2)];
  CHECK(f.ran && !f.ok && f.error == "asked to fail");
  const TaskResult& nr = col.results[task_id(3, 4)];
  CHECK(!nr.ran && !nr.ok && nr.rank == -1 && nr.error == "not run: task " + std::to_string(task_id(3, 2)) + " of this chain failed");
  CHECK(col.results[task_id(4, 5)].ok);  // other chains complete
  // Not-run tasks were never executed; every other task exactly once.
  std::set<std::int64_t> should_run;
  for (const auto& [id, r] : want)
    if (r.ran) should_run.insert(id);
  CHECK(each_once(ran) && std::set<std::int64_t>(ran.begin(), ran.end()) == should_run);
}

void test_resume() {
  // Chain c resumes at index c % length with the carry test_basic delivered for index-1.
  const Spec s = g_basic_spec;
  std::vector<Chain> chains;
  std::map<std::int64_t, TaskResult> want;
  if (g_rank == 0) {
    for (Chain ch : make_chains(s)) {
      const int k = static_cast<int>(ch.id) % s.length;
      if (k > 0) ch.carry = g_full.at(task_id(static_cast<int>(ch.id), k - 1)).carry;
      ch.tasks.erase(ch.tasks.begin(), ch.tasks.begin() + k);
      for (const Task& t : ch.tasks) want[t.id] = g_full.at(t.id);
      chains.push_back(std::move(ch));
    }
  }
  Collector col;
  FarmOptions opt;
  opt.on_result = col.callback();
  const FarmSummary sum = run_farm(chains, work, opt);
  const auto ran = gather_ran();
  CHECK(sum.status == FarmStatus::Completed);
  if (g_rank != 0) return;
  CHECK(!want.empty() && want.size() < g_full.size());
  CHECK(same_results(col.results, want));
  CHECK(ran.size() == want.size() && each_once(ran));
}

void test_stop() {
  // Rank 0 turns SIGINT into a stop request; workers ignore it, and one of them even raises
  // SIGTERM at itself during a task. The stop comes from a SIGINT raised after 8 results.
  std::atomic<bool> stop{false};
  if (g_rank == 0) install_stop_handlers(stop);
  else ignore_stop_signals();
  Spec s;
  s.chains = 12;
  s.length = 8;
  s.sleep_min_us = 5000;
  s.sleep_max_us = 15000;
  s.raise_sig = SIGTERM;
  Collector col;
  FarmOptions opt;
  opt.threads = 0;  // the SIGTERM must be raised on a worker rank, which ignores it
  opt.stop = &stop;
  opt.on_result = [&, cb = col.callback()](const TaskResult& r) {
    cb(r);
    if (col.results.size() == 8) std::raise(SIGINT);
  };
  const auto chains = g_rank == 0 ? make_chains(s) : std::vector<Chain>{};
  const auto t0 = std::chrono::steady_clock::now();
  const FarmSummary sum = run_farm(chains, work, opt);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto ran = gather_ran();
  CHECK(sum.status == FarmStatus::Interrupted);  // on every rank
  if (g_rank != 0) {
    restore_default_signals();
    return;
  }
  CHECK(stop.load());
  const auto want = expected(chains);
  const std::int64_t delivered = static_cast<std::int64_t>(col.results.size());
  CHECK(delivered >= 8 && delivered <= 8 + (g_size - 2));  // at most the tasks still in flight
  CHECK(col.duplicates == 0 && col.out_of_order == 0);
  // Every task handed out ran once and was delivered; nothing else ran.
  std::set<std::int64_t> delivered_ids;
  for (const auto& [id, r] : col.results) delivered_ids.insert(id);
  CHECK(each_once(ran) && std::set<std::int64_t>(ran.begin(), ran.end()) == delivered_ids);
  bool match = true;
  for (const auto& [id, r] : col.results) match = match && same(r, want.at(id));
  CHECK(match);
  CHECK(sum.done == delivered && sum.unstarted == sum.total - delivered && sum.unstarted > 0);
  CHECK(wall < 2.0);

  // Resume what was left: together with the interrupted run, exactly the serial results.
  restore_default_signals();
  std::vector<Chain> rest;
  for (Chain ch : chains) {
    std::size_t k = 0;
    while (k < ch.tasks.size() && col.results.count(ch.tasks[k].id)) ++k;
    if (k > 0) ch.carry = col.results.at(ch.tasks[k - 1].id).carry;
    ch.tasks.erase(ch.tasks.begin(), ch.tasks.begin() + static_cast<std::ptrdiff_t>(k));
    rest.push_back(std::move(ch));
  }
  Collector col2;
  FarmOptions opt2;
  opt2.on_result = col2.callback();
  // The resumed run happens on rank 0 alone (the workers have left this test), without the
  // sleeps and the signal (same inputs: they are part of the hashes).
  opt2.comm = MPI_COMM_SELF;
  g_effects = false;
  const FarmSummary sum2 = run_farm(rest, work, opt2);
  g_effects = true;
  CHECK(each_once(g_ran) && g_ran.size() == col2.results.size());
  g_ran.clear();
  CHECK(sum2.status == FarmStatus::Completed);
  std::map<std::int64_t, TaskResult> all = col.results;
  all.insert(col2.results.begin(), col2.results.end());
  CHECK(all.size() == col.results.size() + col2.results.size());
  CHECK(same_results(all, want));
  std::printf("stop: interrupted after %lld of %lld tasks in %.3f s\n", static_cast<long long>(delivered),
              static_cast<long long>(sum.total), wall);
}

void test_callback_error() {
  Spec s;
  s.chains = 6;
  s.length = 5;
  s.sleep_max_us = 500;
  int delivered = 0;
  FarmOptions opt;
  opt.on_result = [&](const TaskResult&) {
    if (++delivered == 3) throw std::runtime_error("disk full");
  };
  std::string caught;
  FarmSummary sum;
  try {
    sum = run_farm(g_rank == 0 ? make_chains(s) : std::vector<Chain>{}, work, opt);
  } catch (const std::runtime_error& e) {
    caught = e.what();
  }
  const auto ran = gather_ran();
  if (g_rank != 0) {
    CHECK(sum.status == FarmStatus::Aborted && caught.empty());
    return;
  }
  CHECK(caught == "disk full");
  CHECK(delivered == 3);
  CHECK(each_once(ran) && ran.size() < 30);
}

void test_invalid_chains() {
  std::vector<Chain> chains;
  if (g_rank == 0) {
    Spec s;
    chains = make_chains(s);
    chains[1].tasks[2].id = chains[0].tasks[0].id;  // duplicate task id
  }
  bool invalid = false;
  FarmSummary sum;
  try {
    sum = run_farm(chains, work, {});
  } catch (const std::invalid_argument&) {
    invalid = true;
  }
  const auto ran = gather_ran();
  if (g_rank != 0) {
    CHECK(!invalid && sum.status == FarmStatus::Aborted);
    return;
  }
  CHECK(invalid);
  CHECK(ran.empty());
}

void test_large_payloads() {
  Spec s;
  s.chains = 3;
  s.length = 3;
  s.input_pad = 3 << 20;   // 3 MiB inputs, 1 MiB carries: beyond MPI's eager limits
  s.carry_pad = 1 << 20;
  Collector col;
  FarmOptions opt;
  opt.threads = 0;  // every task through MPI
  opt.on_result = col.callback();
  const auto chains = g_rank == 0 ? make_chains(s) : std::vector<Chain>{};
  const FarmSummary sum = run_farm(chains, work, opt);
  gather_ran();
  CHECK(sum.status == FarmStatus::Completed);
  if (g_rank != 0) return;
  CHECK(same_results(col.results, expected(chains)));
  CHECK(sum.bytes_sent > 9u * (3u << 20));
}

void test_progress() {
  Spec s;
  s.chains = 6;
  s.length = 10;
  s.sleep_min_us = 2000;
  s.sleep_max_us = 4000;
  std::vector<Progress> seen;
  FarmOptions opt;
  opt.progress_interval = 0.03;
  opt.on_progress = [&](const Progress& p) { seen.push_back(p); };
  const FarmSummary sum = run_farm(g_rank == 0 ? make_chains(s) : std::vector<Chain>{}, work, opt);
  gather_ran();
  if (g_rank != 0) return;
  CHECK(sum.status == FarmStatus::Completed);
  CHECK(seen.size() >= 2);
  bool ok = !seen.empty() && seen[0].elapsed_seconds >= 0.03;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const Progress& p = seen[i];
    ok = ok && p.total == 60 && p.done <= 60 && p.failed == 0 && p.not_run == 0 && p.in_flight >= 0 &&
         p.in_flight <= g_size;  // the worker ranks and rank 0's thread
    if (i > 0) ok = ok && p.done >= seen[i - 1].done && p.elapsed_seconds - seen[i - 1].elapsed_seconds >= 0.029;
  }
  CHECK(ok);
}

void test_throughput() {
  // 2000 tiny independent tasks, then 2000 tiny tasks in 20 chains of 100.
  for (int chained = 0; chained < 2; ++chained) {
    Spec s;
    s.chains = chained ? 20 : 2000;
    s.length = chained ? 100 : 1;
    const auto chains = g_rank == 0 ? make_chains(s) : std::vector<Chain>{};
    std::size_t count = 0;
    bool all_ok = true;
    FarmOptions opt;
    opt.on_result = [&](const TaskResult& r) { ++count, all_ok = all_ok && r.ok; };
    const FarmSummary sum = run_farm(chains, work, opt);
    const auto ran = gather_ran();
    CHECK(sum.status == FarmStatus::Completed);
    if (g_rank != 0) continue;
    CHECK(count == 2000 && all_ok && ran.size() == 2000 && each_once(ran));
    std::printf("measured farm: %.0f tasks/s (2000 tiny tasks, %s, %d ranks, %.3f s, %.2f MB moved)\n",
                sum.tasks_per_second, chained ? "20 chains of 100" : "independent", g_size, sum.wall_seconds,
                static_cast<double>(sum.bytes_sent + sum.bytes_received) / 1e6);
  }
}

// broadcast (mpi_env.hpp): rank 0's bytes reach every rank exactly, an empty buffer too, while
// the other ranks wait in it as rank 0 works for a while first.
void test_broadcast() {
  for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(100003)}) {
    Bytes want(n);
    for (std::size_t i = 0; i < n; ++i) want[i] = std::byte((i * 131 + 7) & 0xff);
    Bytes got = g_rank == 0 ? want : Bytes(17, std::byte{0x5a});
    if (g_rank == 0) std::this_thread::sleep_for(std::chrono::milliseconds(200));
    broadcast(got, MPI_COMM_WORLD);
    CHECK(got == want);
  }
}

}  // namespace

int main(int argc, char** argv) {
  MpiEnvironment env(argc, argv);
  g_rank = env.rank();
  g_size = env.size();
  if (g_size < 2) {
    std::printf("farm_mpi_test needs at least 2 ranks\n0 passed, 1 failed\n");
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::pair<const char*, void (*)()> tests[] = {
      {"basic", test_basic},
      {"master_alone", test_master_alone},
      {"lowest_chain_first", test_lowest_chain_first},
      {"failure", test_failure},
      {"resume", test_resume},
      {"stop", test_stop},
      {"callback_error", test_callback_error},
      {"invalid_chains", test_invalid_chains},
      {"large_payloads", test_large_payloads},
      {"progress", test_progress},
      {"throughput", test_throughput},
      {"broadcast", test_broadcast},
  };
  for (const auto& [name, fn] : tests) {
    try {
      fn();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rank %d: test %s threw: %s\n", g_rank, name, e.what());
      env.abort(2);  // the other ranks may be waiting in the farm: end the job
    }
    std::fflush(stdout);
    check_mpi(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
  }
  int local[2] = {g_passed, g_failed}, total[2] = {0, 0};
  check_mpi(MPI_Allreduce(local, total, 2, MPI_INT, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
  if (g_rank == 0) {
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("farm_mpi_test on %d ranks (%.2f s): %d passed, %d failed\n", g_size, secs, total[0], total[1]);
  }
  return total[1] == 0 ? 0 : 1;
}
