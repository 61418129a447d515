#include "parallel/farm.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <ctime>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <list>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <unordered_set>
#include <utility>

#include "parallel/mpi_env.hpp"

namespace ajx::parallel {

const char* to_string(FarmStatus status) {
  switch (status) {
    case FarmStatus::Completed: return "completed";
    case FarmStatus::Interrupted: return "interrupted";
    case FarmStatus::Aborted: return "aborted";
  }
  return "unknown";
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU time of the calling thread [s].
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// ---------------------------------------------------------------------------------------------
// Messages. Every message is one MPI_BYTE buffer: a fixed Header, then up to three payloads
// whose lengths the header carries. One message per direction keeps a task to one round trip.
//   worker -> master  kTagHello   header only: "I am ready" (first request for work)
//   worker -> master  kTagResult  output, carry, error text; also asks for the next task
//   master -> worker  kTagTask    input, carry
//   master -> worker  kTagStop    header only, code = FarmStatus
constexpr int kTagHello = 1;
constexpr int kTagResult = 2;
constexpr int kTagTask = 3;
constexpr int kTagStop = 4;
constexpr std::int32_t kMagic = 0x464a4124;  // catches anything that is not a farm header

struct Header {
  std::int32_t magic = kMagic;
  std::int32_t code = 0;  // result: 1 ok / 0 failed; stop: FarmStatus
  std::int64_t task_id = 0;
  std::int64_t chain = 0;
  std::int64_t index = 0;
  std::uint64_t len[3] = {0, 0, 0};
  double seconds = 0;  // result: wall time of the work function
};
// Sent as raw bytes: ranks are assumed to share one architecture.
static_assert(std::is_trivially_copyable_v<Header>);

using Part = std::span<const std::byte>;

Part as_part(const std::string& s) { return std::as_bytes(std::span<const char>(s.data(), s.size())); }

Bytes pack(Header h, Part a = {}, Part b = {}, Part c = {}) {
  const Part parts[3] = {a, b, c};
  std::size_t size = sizeof(Header);
  for (int i = 0; i < 3; ++i) {
    h.len[i] = parts[i].size();
    size += parts[i].size();
  }
  Bytes buf(size);
  std::memcpy(buf.data(), &h, sizeof h);
  std::size_t at = sizeof h;
  for (const Part& p : parts) {
    if (!p.empty()) std::memcpy(buf.data() + at, p.data(), p.size());
    at += p.size();
  }
  return buf;
}

struct Message {
  int source = -1;
  int tag = -1;
  Header header;
  Bytes buf;  // the whole message, header included

  Part part(int i) const {
    std::size_t at = sizeof(Header);
    for (int k = 0; k < i; ++k) at += header.len[k];
    return Part(buf.data() + at, header.len[i]);
  }
  Bytes bytes(int i) const {
    const Part p = part(i);
    return Bytes(p.begin(), p.end());
  }
  std::string text(int i) const {
    const Part p = part(i);
    return std::string(reinterpret_cast<const char*>(p.data()), p.size());
  }
};

// Owns a duplicate of the caller's communicator, so farm tags never meet the caller's
// messages, with errors returned as codes (check_mpi turns them into exceptions).
class FarmComm {
 public:
  explicit FarmComm(MPI_Comm parent) {
    check_mpi(MPI_Comm_dup(parent, &comm_), "MPI_Comm_dup");
    check_mpi(MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
  }
  ~FarmComm() {
    if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);  // nothing useful to do on failure here
  }
  FarmComm(const FarmComm&) = delete;
  FarmComm& operator=(const FarmComm&) = delete;
  MPI_Comm get() const { return comm_; }

  void send(const Bytes& msg, int dest, int tag) const {
    // MPI counts are ints.
    if (msg.size() > static_cast<std::size_t>(INT_MAX))
      throw MpiError("MPI_Send failed: farm message of " + std::to_string(msg.size()) + " bytes exceeds 2 GiB");
    check_mpi(MPI_Send(msg.data(), static_cast<int>(msg.size()), MPI_BYTE, dest, tag, comm_), "MPI_Send");
  }

  // Waits for the next message from `source`, polling with `backoff` between looks: MPI_Probe
  // busy-polls in Open MPI, so a worker waiting for work would hold a core at 100 %.
  template <class Backoff>
  MPI_Status probe(int source, Backoff& backoff) const {
    MPI_Status st;
    for (backoff.reset();; backoff.wait()) {
      int flag = 0;
      check_mpi(MPI_Iprobe(source, MPI_ANY_TAG, comm_, &flag, &st), "MPI_Iprobe");
      if (flag) return st;
    }
  }

  // Non-blocking: a message from anyone, if one is waiting.
  std::optional<MPI_Status> iprobe() const {
    MPI_Status st;
    int flag = 0;
    check_mpi(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm_, &flag, &st), "MPI_Iprobe");
    if (!flag) return std::nullopt;
    return st;
  }

  // Receives the probed message (sizes vary: MPI_Get_count says how much to allocate).
  Message receive(const MPI_Status& probed) const {
    int count = 0;
    check_mpi(MPI_Get_count(&probed, MPI_BYTE, &count), "MPI_Get_count");
    Message m;
    m.source = probed.MPI_SOURCE;
    m.tag = probed.MPI_TAG;
    m.buf.resize(static_cast<std::size_t>(count));
    check_mpi(MPI_Recv(m.buf.data(), count, MPI_BYTE, m.source, m.tag, comm_, MPI_STATUS_IGNORE), "MPI_Recv");
    const auto bad = [&](const char* why) {
      return std::runtime_error("farm: malformed message (tag " + std::to_string(m.tag) + ") from rank " +
                                std::to_string(m.source) + ": " + why);
    };
    if (m.buf.size() < sizeof(Header)) throw bad("shorter than the header");
    std::memcpy(&m.header, m.buf.data(), sizeof(Header));
    if (m.header.magic != kMagic) throw bad("bad magic");
    std::uint64_t payload = 0;
    for (std::uint64_t l : m.header.len) {
      if (l > m.buf.size()) throw bad("payload length out of range");
      payload += l;
    }
    if (payload != m.buf.size() - sizeof(Header)) throw bad("payload lengths do not add up");
    return m;
  }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
};

// The master's sends, non-blocking: a task message larger than the transport's eager limit
// (a few kB on shared memory) is sent by rendezvous, so a blocking MPI_Send to a stopped or
// hung rank would hold the master, and with it every other worker and the task bound that
// should give that rank up, until the rank runs again. Each message stays here until MPI is
// done with it.
class Outbox {
 public:
  explicit Outbox(const FarmComm& comm) : comm_(comm) {}
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;
  // On an error's way out: nothing is waited for (a rank may be hung); the buffers are kept.
  ~Outbox() { close([](int) { return true; }); }

  // The end: what is in flight to a live rank is waited for; what is in flight to a rank given
  // up (lost(rank)) may never be received, so its buffer is kept for the life of the process
  // (the caller then ends the job with MPI_Abort: FarmOptions::task_timeout).
  template <class Lost>
  void close(const Lost& lost) {
    for (Pending& p : pending_) {
      if (p.request == MPI_REQUEST_NULL) continue;  // done, or never started
      if (lost(p.dest)) {
        MPI_Request_free(&p.request);
        kept().push_back(std::move(p.msg));
      } else {
        check_mpi(MPI_Wait(&p.request, MPI_STATUS_IGNORE), "MPI_Wait");
      }
    }
    pending_.clear();
  }

  void post(Bytes msg, int dest, int tag) {
    if (msg.size() > static_cast<std::size_t>(INT_MAX))
      throw MpiError("MPI_Isend failed: farm message of " + std::to_string(msg.size()) + " bytes exceeds 2 GiB");
    pending_.push_back(Pending{std::move(msg), dest, MPI_REQUEST_NULL});
    Pending& p = pending_.back();
    check_mpi(MPI_Isend(p.msg.data(), static_cast<int>(p.msg.size()), MPI_BYTE, dest, tag, comm_.get(), &p.request),
              "MPI_Isend");
  }
  // Forgets the messages MPI is done with (one MPI_Test each).
  void progress() {
    for (auto it = pending_.begin(); it != pending_.end();) {
      int done = 0;
      check_mpi(MPI_Test(&it->request, &done, MPI_STATUS_IGNORE), "MPI_Test");
      it = done ? pending_.erase(it) : std::next(it);
    }
  }

 private:
  struct Pending {
    Bytes msg;
    int dest;
    MPI_Request request;
  };
  static std::deque<Bytes>& kept() {
    static std::deque<Bytes> k;
    return k;
  }
  const FarmComm& comm_;
  std::list<Pending> pending_;  // a list: a request's address must not move while MPI holds it
};

// Runs the work function on one task, timing it and turning exceptions into a failed task.
TaskResult execute(const WorkFunction& work, const Task& task, const Bytes& carry, int rank) {
  TaskResult r;
  r.task_id = task.id;
  r.chain = task.chain;
  r.index = task.index;
  r.ran = true;
  r.rank = rank;
  const auto t0 = Clock::now();
  try {
    Outcome o = work(task, carry);
    r.ok = o.ok;
    r.output = std::move(o.output);
    if (o.ok) r.carry = std::move(o.carry);
    r.error = std::move(o.error);
  } catch (const std::exception& e) {
    r.ok = false;
    r.error = std::string("exception: ") + e.what();
  } catch (...) {
    r.ok = false;
    r.error = "exception of unknown type";
  }
  r.wall_seconds = seconds_since(t0);
  return r;
}

// Threads on rank 0 that run tasks beside the master (FarmOptions::threads). The master gives
// each a task as it gives one to a worker rank and collects the results between its messages.
// They call no MPI: the library is initialised MPI_THREAD_FUNNELED.
class LocalWorkers {
 public:
  LocalWorkers(int n, const WorkFunction& work) : work_(work), jobs_(static_cast<std::size_t>(n)) {
    for (int i = 0; i < n; ++i) threads_.emplace_back([this, i] { loop(static_cast<std::size_t>(i)); });
  }
  ~LocalWorkers() {
    {
      const std::lock_guard<std::mutex> lock(m_);
      quit_ = true;
    }
    work_ready_.notify_all();
    for (std::thread& t : threads_) t.join();  // a task under way is finished first
  }
  LocalWorkers(const LocalWorkers&) = delete;
  LocalWorkers& operator=(const LocalWorkers&) = delete;

  int size() const { return static_cast<int>(jobs_.size()); }
  void give(std::size_t i, const Task& task, const Bytes& carry) {
    {
      const std::lock_guard<std::mutex> lock(m_);
      jobs_[i] = Job{task, carry};
    }
    work_ready_.notify_all();
  }
  // A finished task (its thread's index and result), if one is waiting.
  std::optional<std::pair<std::size_t, TaskResult>> take() {
    const std::lock_guard<std::mutex> lock(m_);
    if (done_.empty()) return std::nullopt;
    auto r = std::move(done_.front());
    done_.pop_front();
    return r;
  }
  // Waits until a result is waiting or `limit` has passed.
  void wait(std::chrono::microseconds limit) {
    std::unique_lock<std::mutex> lock(m_);
    result_ready_.wait_for(lock, limit, [this] { return !done_.empty(); });
  }

 private:
  struct Job {
    Task task;
    Bytes carry;
  };
  void loop(std::size_t i) {
    std::unique_lock<std::mutex> lock(m_);
    while (true) {
      work_ready_.wait(lock, [&] { return quit_ || jobs_[i].has_value(); });
      if (quit_) return;
      Job job = std::move(*jobs_[i]);
      jobs_[i].reset();
      lock.unlock();
      TaskResult r = execute(work_, job.task, job.carry, 0);
      lock.lock();
      done_.emplace_back(i, std::move(r));
      result_ready_.notify_one();
    }
  }

  const WorkFunction& work_;
  std::mutex m_;
  std::condition_variable work_ready_, result_ready_;
  std::vector<std::optional<Job>> jobs_;  // per thread: its task, until it starts it
  std::deque<std::pair<std::size_t, TaskResult>> done_;
  bool quit_ = false;
  std::vector<std::thread> threads_;  // last: started once the members they use exist
};

// ---------------------------------------------------------------------------------------------
// The master's bookkeeping, shared by the in-process (1 rank) and the distributed drivers:
// chain states, the ready set, result delivery, counts and progress. A throwing callback or
// invalid input is recorded in error_ (the drivers then wind down and rethrow).
class Scheduler {
 public:
  Scheduler(std::vector<Chain> chains, const FarmOptions& options, Clock::time_point start)
      : options_(options), start_(start), last_progress_(start) {
    try {
      validate(chains);
    } catch (...) {
      error_ = std::current_exception();
      return;
    }
    std::sort(chains.begin(), chains.end(), [](const Chain& a, const Chain& b) { return a.id < b.id; });
    states_.reserve(chains.size());
    for (Chain& c : chains) {
      total_ += static_cast<std::int64_t>(c.tasks.size());
      states_.push_back(State{std::move(c), 0, false});
      // Sorted positions = sorted chain ids: the set's first element is the lowest chain id.
      if (!states_.back().chain.tasks.empty()) ready_.insert(states_.size() - 1);
    }
  }

  bool failed() const { return error_ != nullptr; }
  std::size_t chains() const { return states_.size(); }
  void rethrow_if_failed() const {
    if (error_) std::rethrow_exception(error_);
  }
  bool has_ready() const { return !failed() && !ready_.empty(); }

  // Takes the ready task of the lowest chain id; its chain is in flight until finish().
  std::size_t take() {
    const std::size_t c = *ready_.begin();
    ready_.erase(ready_.begin());
    states_[c].in_flight = true;
    ++in_flight_;
    return c;
  }
  const Task& task(std::size_t c) const { return states_[c].chain.tasks[states_[c].next]; }
  const Bytes& carry(std::size_t c) const { return states_[c].chain.carry; }

  // The result of chain c's task in flight: delivered, then the chain advances or ends.
  void finish(std::size_t c, TaskResult&& r) {
    State& s = states_[c];
    s.in_flight = false;
    --in_flight_;
    ++done_;
    if (!r.ok) ++failed_;
    if (failed()) return;  // winding down after an error: nothing more is delivered
    deliver(r);
    Bytes().swap(s.chain.tasks[s.next].input);  // the input is no longer needed
    if (r.ok) {
      s.chain.carry = std::move(r.carry);
      if (++s.next < s.chain.tasks.size()) ready_.insert(c);
      return;
    }
    // A failed task ends its chain: report the rest as not run.
    const std::string why = "not run: task " + std::to_string(r.task_id) + " of this chain failed";
    for (std::size_t k = s.next + 1; k < s.chain.tasks.size(); ++k) {
      const Task& t = s.chain.tasks[k];
      TaskResult nr;
      nr.task_id = t.id;
      nr.chain = t.chain;
      nr.index = t.index;
      nr.error = why;
      ++not_run_;
      deliver(nr);
    }
    s.next = s.chain.tasks.size();
  }

  // Chain c's task in flight goes back to the ready set, to run again elsewhere.
  void requeue(std::size_t c) {
    states_[c].in_flight = false;
    --in_flight_;
    ready_.insert(c);
  }

  // Calls on_progress if the interval has passed since the last call (or the start).
  void tick() {
    if (!options_.on_progress || failed()) return;
    if (seconds_since(last_progress_) < options_.progress_interval) return;
    last_progress_ = Clock::now();
    try {
      options_.on_progress(progress());
    } catch (...) {
      error_ = std::current_exception();
    }
  }

  Progress progress() const {
    return Progress{done_, failed_, not_run_, total_, in_flight_, seconds_since(start_)};
  }

  FarmSummary summary(int ranks) const {
    FarmSummary s;
    s.ranks = ranks;
    s.total = total_;
    s.done = done_;
    s.failed = failed_;
    s.not_run = not_run_;
    s.result_seconds = result_seconds_;
    s.unstarted = total_ - done_ - not_run_ - in_flight_;
    s.status = failed() ? FarmStatus::Aborted : s.unstarted > 0 ? FarmStatus::Interrupted : FarmStatus::Completed;
    s.busy_seconds.assign(static_cast<std::size_t>(ranks), 0.0);
    s.tasks_per_rank.assign(static_cast<std::size_t>(ranks), 0);
    return s;
  }

 private:
  struct State {
    Chain chain;
    std::size_t next = 0;  // first task of the chain not finished yet
    bool in_flight = false;
  };

  static void validate(const std::vector<Chain>& chains) {
    std::unordered_set<std::int64_t> chain_ids, task_ids;
    for (const Chain& c : chains) {
      const std::string where = "run_farm: chain " + std::to_string(c.id);
      if (!chain_ids.insert(c.id).second) throw std::invalid_argument(where + " appears twice");
      for (std::size_t k = 0; k < c.tasks.size(); ++k) {
        const Task& t = c.tasks[k];
        const std::string what = where + ", task " + std::to_string(t.id);
        if (!task_ids.insert(t.id).second) throw std::invalid_argument(what + ": task id used twice");
        if (t.chain != c.id) throw std::invalid_argument(what + ": its chain field is " + std::to_string(t.chain));
        if (t.index < 0) throw std::invalid_argument(what + ": negative index");
        if (k > 0 && t.index != c.tasks[k - 1].index + 1)
          throw std::invalid_argument(what + ": index " + std::to_string(t.index) + " does not follow " +
                                      std::to_string(c.tasks[k - 1].index));
      }
    }
  }

  void deliver(const TaskResult& r) {
    if (!options_.on_result || failed()) return;
    const auto t0 = Clock::now();
    try {
      options_.on_result(r);
    } catch (...) {
      error_ = std::current_exception();
    }
    result_seconds_ += seconds_since(t0);
  }

  const FarmOptions& options_;
  Clock::time_point start_, last_progress_;
  std::vector<State> states_;
  std::set<std::size_t> ready_;  // chains whose next task may start
  std::int64_t total_ = 0, done_ = 0, failed_ = 0, not_run_ = 0, in_flight_ = 0;
  double result_seconds_ = 0;  // in on_result
  std::exception_ptr error_;
};

bool stop_requested(const FarmOptions& o) { return o.stop != nullptr && o.stop->load(std::memory_order_acquire); }

// The master's wait between polls: yield first (a tiny task answers within microseconds),
// then sleep longer and longer up to 1 ms so that an idle master leaves the cores to workers.
class Backoff {
 public:
  void reset() { polls_ = 0; }
  // The next pause: none (a yield) for the first 200 polls, then 50 µs doubling up to 1 ms.
  std::chrono::microseconds pause() {
    ++polls_;
    if (polls_ <= 200) return std::chrono::microseconds(0);
    const int doublings = std::min((polls_ - 200) / 8, 5);
    return std::chrono::microseconds(std::min(1000, 50 << doublings));
  }
  void wait() {
    const auto p = pause();
    if (p.count() == 0)
      std::this_thread::yield();
    else
      std::this_thread::sleep_for(p);
  }

 private:
  int polls_ = 0;
};

// One rank: the master runs every task itself.
FarmSummary run_in_process(std::vector<Chain> chains, const WorkFunction& work, const FarmOptions& options,
                           Clock::time_point start) {
  Scheduler sched(std::move(chains), options, start);
  double busy = 0;
  std::int64_t ran = 0;
  while (sched.has_ready() && !stop_requested(options)) {
    const std::size_t c = sched.take();
    TaskResult r = execute(work, sched.task(c), sched.carry(c), 0);
    busy += r.wall_seconds;
    ++ran;
    sched.finish(c, std::move(r));
    sched.tick();
  }
  sched.rethrow_if_failed();
  FarmSummary s = sched.summary(1);
  s.busy_seconds[0] = busy;
  s.tasks_per_rank[0] = ran;
  return s;
}

// The wall-clock bound of a task now [s]; 0: none (FarmOptions::task_timeout).
double task_bound(const FarmOptions& o, double slowest_task) {
  if (o.task_timeout > 0) return o.task_timeout;
  if (o.timeout_factor <= 0 || slowest_task <= 0) return 0.0;
  return std::max(o.min_task_timeout, o.timeout_factor * slowest_task);
}

// The master's record of the workers: what each holds and since when, and which are given up.
// Workers 1 .. ranks-1 are ranks, ranks .. ranks+threads-1 the master's threads (LocalWorkers).
struct Workers {
  int ranks = 1;
  std::vector<std::optional<std::size_t>> assigned;  // chain per worker
  std::vector<Clock::time_point> handed;             // when each worker got its task
  std::vector<bool> lost;                            // past the task bound, given up
  int n_lost = 0;
  Workers(int size, int threads)
      : ranks(size), assigned(static_cast<std::size_t>(size + threads)),
        handed(static_cast<std::size_t>(size + threads)), lost(static_cast<std::size_t>(size + threads), false) {}
  bool local(int w) const { return w >= ranks; }
};

// Tasks in flight past the bound: their workers given up, the tasks handed out again (or, after
// max_attempts timeouts, delivered as failed).
void give_up_late(const FarmOptions& options, double bound, Workers& ws, std::vector<int>& attempts,
                  Scheduler& sched) {
  for (std::size_t w = 1; w < static_cast<std::size_t>(ws.ranks); ++w) {  // a thread of rank 0 cannot be given up
    if (!ws.assigned[w] || seconds_since(ws.handed[w]) <= bound) continue;
    const std::size_t c = *ws.assigned[w];
    ws.assigned[w].reset();
    ws.lost[w] = true;
    ++ws.n_lost;
    const double waited = seconds_since(ws.handed[w]);
    std::fprintf(stderr, "warning: rank %zu: no result after %.1f s (the task bound is %.3g s); rank %zu given up, "
                 "its task handed to another\n", w, waited, bound, w);
    if (++attempts[c] < options.max_attempts) {
      sched.requeue(c);
      continue;
    }
    const Task& t = sched.task(c);
    TaskResult r;
    r.task_id = t.id;
    r.chain = t.chain;
    r.index = t.index;
    r.ran = true;
    r.rank = static_cast<int>(w);
    r.wall_seconds = waited;
    char buf[200];
    std::snprintf(buf, sizeof buf, "no result after %.1f s on rank %zu (the task wall-clock bound is %.3g s; it timed "
                  "out on %d ranks); rank %zu given up", waited, w, bound, attempts[c], w);
    r.error = buf;
    sched.finish(c, std::move(r));
  }
}

// Ready tasks to idle workers, in the order the workers asked; returns the bytes sent.
std::uint64_t hand_out(Outbox& outbox, std::deque<int>& idle, Scheduler& sched, Workers& ws,
                       LocalWorkers& local) {
  std::uint64_t sent = 0;
  while (!idle.empty() && sched.has_ready()) {
    const int w = idle.front();
    idle.pop_front();
    const std::size_t c = sched.take();
    const Task& t = sched.task(c);
    ws.assigned[static_cast<std::size_t>(w)] = c;
    ws.handed[static_cast<std::size_t>(w)] = Clock::now();
    if (ws.local(w)) {
      local.give(static_cast<std::size_t>(w - ws.ranks), t, sched.carry(c));
      continue;
    }
    Header h;
    h.task_id = t.id;
    h.chain = t.chain;
    h.index = t.index;
    Bytes msg = pack(h, t.input, sched.carry(c));
    sent += msg.size();
    outbox.post(std::move(msg), w, kTagTask);
  }
  return sent;
}

// A worker's result message as the task's result.
TaskResult result_of(const Message& m) {
  TaskResult r;
  r.task_id = m.header.task_id;
  r.chain = m.header.chain;
  r.index = m.header.index;
  r.ran = true;
  r.ok = m.header.code == 1;
  r.output = m.bytes(0);
  r.carry = m.bytes(1);
  r.error = m.text(2);
  r.wall_seconds = m.header.seconds;
  r.rank = m.source;
  return r;
}

// The end of the master's loop: every worker rank told to stop, the summary with the lost ranks
// and the bytes sent (rethrows the error that stopped the farm, if any).
FarmSummary wind_up(Outbox& outbox, int size, const Scheduler& sched, const Workers& ws, std::uint64_t sent) {
  FarmSummary s = sched.summary(size);
  Header stop;
  stop.code = static_cast<std::int32_t>(s.status);
  for (int w = 1; w < size; ++w) {
    Bytes msg = pack(stop);
    sent += msg.size();
    outbox.post(std::move(msg), w, kTagStop);
  }
  outbox.close([&](int w) { return bool(ws.lost[static_cast<std::size_t>(w)]); });
  sched.rethrow_if_failed();
  for (int w = 1; w < size; ++w)
    if (ws.lost[static_cast<std::size_t>(w)]) s.lost_ranks.push_back(w);
  s.bytes_sent = sent;
  return s;
}

// The master's loop: ready tasks to idle workers (ranks and its own threads), their results
// delivered, the task bound watched, until nothing is left or a stop winds it down.
FarmSummary run_master(const FarmComm& comm, int size, std::vector<Chain> chains, const WorkFunction& work,
                       const FarmOptions& options, Clock::time_point start) {
  const double cpu0 = thread_cpu_seconds();
  Scheduler sched(std::move(chains), options, start);
  Outbox outbox(comm);
  LocalWorkers local(std::max(0, options.threads), work);
  const int workers = size - 1 + local.size();
  std::vector<double> busy(static_cast<std::size_t>(size), 0.0);
  std::vector<std::int64_t> ran(static_cast<std::size_t>(size), 0);
  Workers ws(size, local.size());
  std::deque<int> idle;  // workers waiting for a task, in the order they asked
  for (int i = 0; i < local.size(); ++i) idle.push_back(size + i);
  std::vector<int> attempts(sched.chains(), 0);  // per chain: timeouts of its task in flight
  double slowest = 0;  // the longest task finished so far [s]
  Clock::time_point last_timeout_check = start;
  std::uint64_t sent = 0, received = 0;
  bool stopping = false;
  Backoff backoff;
  // Worker w's result for the chain it holds; w is idle again.
  const auto finished = [&](int w, TaskResult&& r) {
    std::optional<std::size_t>& slot = ws.assigned[static_cast<std::size_t>(w)];
    if (!slot || r.task_id != sched.task(*slot).id)
      throw std::runtime_error("farm: rank " + std::to_string(r.rank) + " returned task " + std::to_string(r.task_id) +
                               ", which it was not given");
    const std::size_t c = *slot;
    slot.reset();
    busy[static_cast<std::size_t>(r.rank)] += r.wall_seconds;
    ++ran[static_cast<std::size_t>(r.rank)];
    slowest = std::max(slowest, r.wall_seconds);
    attempts[c] = 0;
    sched.finish(c, std::move(r));
    idle.push_back(w);
  };

  while (true) {
    // A stop request or an error: no new task; results in flight still come back.
    if (!stopping && (stop_requested(options) || sched.failed())) stopping = true;
    if (!stopping) sent += hand_out(outbox, idle, sched, ws, local);
    outbox.progress();
    // Done when every worker is waiting (so none has a message still on its way) and there is
    // nothing more to hand out.
    // Lost workers never ask again: with none left, what is still ready never starts.
    const int active = workers - ws.n_lost;
    if (static_cast<int>(idle.size()) == active && (stopping || !sched.has_ready() || active == 0)) break;

    // Timeouts are checked every 50 ms at most (a pass costs one look per worker).
    const double bound = task_bound(options, slowest);
    if (bound > 0 && seconds_since(last_timeout_check) > 0.05) {
      give_up_late(options, bound, ws, attempts, sched);
      last_timeout_check = Clock::now();
    }
    if (auto done = local.take()) {
      finished(size + static_cast<int>(done->first), std::move(done->second));
      backoff.reset();
      sched.tick();
      continue;
    }
    const std::optional<MPI_Status> st = comm.iprobe();
    if (!st) {
      sched.tick();
      if (size == 1) {
        local.wait(std::chrono::milliseconds(1));  // only threads: their results wake the master
      } else if (local.size() > 0) {
        // Asleep on the threads' results, so a thread's finished task is taken at once (not at
        // the end of the pause) and the next handed to it; the pause bounds the wait for a rank.
        if (const auto p = backoff.pause(); p.count() == 0)
          std::this_thread::yield();
        else
          local.wait(p);
      } else {
        backoff.wait();
      }
      continue;
    }
    backoff.reset();
    Message m = comm.receive(*st);
    received += m.buf.size();
    const int w = m.source;
    if (m.tag == kTagResult && ws.lost[static_cast<std::size_t>(w)]) {
      // The late result of a task handed out again (or reported failed): dropped; the rank works again.
      ws.lost[static_cast<std::size_t>(w)] = false;
      --ws.n_lost;
      idle.push_back(w);
    } else if (m.tag == kTagResult) {
      finished(w, result_of(m));
    } else if (m.tag == kTagHello) {
      idle.push_back(w);
    } else {
      throw std::runtime_error("farm: unexpected message tag " + std::to_string(m.tag) + " from rank " +
                               std::to_string(w));
    }
    sched.tick();
  }

  FarmSummary s = wind_up(outbox, size, sched, ws, sent);
  s.busy_seconds = std::move(busy);
  s.tasks_per_rank = std::move(ran);
  s.bytes_received = received;
  s.master_cpu_seconds = thread_cpu_seconds() - cpu0;
  return s;
}

FarmSummary run_worker(const FarmComm& comm, int rank, int size, const WorkFunction& work) {
  FarmSummary s;
  s.ranks = size;
  s.busy_seconds.assign(static_cast<std::size_t>(size), 0.0);
  s.tasks_per_rank.assign(static_cast<std::size_t>(size), 0);
  comm.send(pack(Header{}), 0, kTagHello);
  Backoff backoff;
  while (true) {
    const Message m = comm.receive(comm.probe(0, backoff));
    if (m.tag == kTagStop) {
      if (m.header.code < 0 || m.header.code > static_cast<std::int32_t>(FarmStatus::Aborted))
        throw std::runtime_error("farm: stop message with unknown status " + std::to_string(m.header.code));
      s.status = static_cast<FarmStatus>(m.header.code);
      return s;
    }
    if (m.tag != kTagTask) throw std::runtime_error("farm: unexpected message tag " + std::to_string(m.tag) + " from the master");
    Task t;
    t.id = m.header.task_id;
    t.chain = m.header.chain;
    t.index = m.header.index;
    t.input = m.bytes(0);
    const TaskResult r = execute(work, t, m.bytes(1), rank);
    s.busy_seconds[static_cast<std::size_t>(rank)] += r.wall_seconds;
    ++s.tasks_per_rank[static_cast<std::size_t>(rank)];
    Header h;
    h.task_id = t.id;
    h.chain = t.chain;
    h.index = t.index;
    h.code = r.ok ? 1 : 0;
    h.seconds = r.wall_seconds;
    comm.send(pack(h, r.output, r.carry, as_part(r.error)), 0, kTagResult);
  }
}

}  // namespace

FarmSummary run_farm(std::vector<Chain> chains, const WorkFunction& work, const FarmOptions& options) {
  const auto start = Clock::now();
  const FarmComm comm(options.comm);
  const int rank = comm_rank(comm.get());
  const int size = comm_size(comm.get());
  FarmSummary s;
  if (size == 1 && options.threads <= 1)
    s = run_in_process(std::move(chains), work, options, start);
  else if (rank == 0)
    s = run_master(comm, size, std::move(chains), work, options, start);
  else
    s = run_worker(comm, rank, size, work);
  s.wall_seconds = seconds_since(start);
  if (rank == 0 && s.wall_seconds > 0) s.tasks_per_second = static_cast<double>(s.done) / s.wall_seconds;
  return s;
}

}  // namespace ajx::parallel
