#include "app/thresholds_farm.hpp"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <numeric>
#include <stdexcept>

#include "config/config.hpp"
#include "parallel/mpi_env.hpp"
#include "parallel/signals.hpp"
#include "sweep/codec.hpp"
#include "sweep/task.hpp"

namespace ajx::app {

namespace {

void put_strings(sweep::ByteWriter& w, const std::vector<std::string>& v) {
  w.put<std::uint64_t>(v.size());
  for (const std::string& s : v) w.put_string(s);
}
std::vector<std::string> get_strings(sweep::ByteReader& r) {
  std::vector<std::string> v(r.get<std::uint64_t>());
  for (std::string& s : v) s = r.get_string();
  return v;
}

// Never empty: an empty broadcast says that rank 0 refused its input.
parallel::Bytes encode(const ChecksContext& c) {
  sweep::ByteWriter w;
  w.put_string(c.config_text);
  w.put_string(c.config_source);
  put_strings(w, c.overrides);
  put_strings(w, c.classifier_settings);
  return w.take();
}
ChecksContext decode_context(const parallel::Bytes& bytes) {
  sweep::ByteReader r(bytes.data(), bytes.size());
  ChecksContext c;
  c.config_text = r.get_string();
  c.config_source = r.get_string();
  c.overrides = get_strings(r);
  c.classifier_settings = get_strings(r);
  if (!r.done()) throw std::runtime_error("thresholds: trailing bytes in the checks' context");
  return c;
}

// A task: its check as input, the start state as its chain's carry; the result as output.
parallel::WorkFunction check_work(const sweep::SweepPlan& plan, const sweep::ClassifierSettings& settings) {
  return [&plan, &settings](const parallel::Task& task, const parallel::Bytes& carry) {
    const sweep::CheckResult result =
        sweep::run_check(sweep::decode_check(task.input), plan, sweep::decode_state(carry), settings);
    parallel::Outcome o;
    std::visit([&o](const auto& r) { o.ok = r.ok, o.error = r.failure; }, result);
    o.output = sweep::encode(result);
    return o;
  };
}

}  // namespace

std::optional<std::vector<sweep::CheckResult>> run_checks(const ChecksContext& context, const sweep::SweepPlan& plan,
                                                         const sweep::ClassifierSettings& settings,
                                                         const std::vector<PlannedCheck>& checks, int threads) {
  parallel::Bytes bytes = encode(context);
  parallel::broadcast(bytes, MPI_COMM_WORLD);
  // One chain of one task per check: they are independent, handed out longest first (by the
  // simulated seconds each integrates), so that the last to finish is a short one; the results
  // are kept by task id, in the order of `checks`.
  std::vector<double> seconds(checks.size());
  for (std::size_t i = 0; i < checks.size(); ++i) seconds[i] = sweep::check_seconds(checks[i].check, plan, checks[i].start);
  std::vector<std::size_t> order(checks.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return seconds[a] > seconds[b]; });
  std::vector<parallel::Chain> chains;
  for (const std::size_t i : order) {
    const auto id = std::int64_t(i);
    chains.push_back({id, sweep::encode(checks[i].start), {{id, id, 0, sweep::encode(checks[i].check)}}});
  }
  std::vector<std::optional<parallel::TaskResult>> got(checks.size());
  std::atomic<bool> stop{false};
  parallel::install_stop_handlers(stop);
  parallel::FarmOptions fo;
  fo.stop = &stop;
  fo.on_result = [&got](const parallel::TaskResult& r) { got[std::size_t(r.task_id)] = r; };
  fo.threads = threads;
  const parallel::FarmSummary fs = parallel::run_farm(std::move(chains), check_work(plan, settings), fo);
  parallel::restore_default_signals();
  if (fs.status != parallel::FarmStatus::Completed) return std::nullopt;
  std::vector<sweep::CheckResult> out;
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const parallel::TaskResult& r = *got[i];
    out.push_back(r.output.empty() ? sweep::failed_check(checks[i].check, r.error) : sweep::decode_check_result(r.output));
  }
  return out;
}

void refuse_checks() {
  parallel::Bytes none;
  parallel::broadcast(none, MPI_COMM_WORLD);
}

void checks_worker() {
  parallel::Bytes bytes;
  parallel::broadcast(bytes, MPI_COMM_WORLD);
  if (bytes.empty()) return;
  const ChecksContext c = decode_context(bytes);
  // Rank 0 made the same plan from the same text (SweepReader::config), so this cannot fail
  // where rank 0 did not.
  const sweep::SweepPlan plan = config::make_plan(config::parse_sweep_config(c.config_text, c.config_source, c.overrides));
  const sweep::ClassifierSettings settings = sweep::parse_classifier_settings(c.classifier_settings);
  parallel::ignore_stop_signals();
  parallel::run_farm({}, check_work(plan, settings));
}

}  // namespace ajx::app
