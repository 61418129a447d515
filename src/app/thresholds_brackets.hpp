// astrojax thresholds on a sweep with [bisect] chains (thresholds_brackets.cpp).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "results/sweep_reader.hpp"

namespace ajx::app {

// Each chain's names as the report prints them (escaped for printing).
struct ChainNames {
  std::vector<std::string> params_, groups_, variants_, labels_, starts_;  // per chain
  const std::string& params(std::size_t c) const { return params_[c]; }
  const std::string& start(std::size_t c) const { return starts_[c]; }  // its start seed, "" unknown
  const std::string& group(std::size_t c) const { return groups_[c]; }
  const std::string& variant(std::size_t c) const { return variants_[c]; }
  const std::string& label(std::size_t c) const { return labels_[c]; }
};

bool is_bisection_chain(const results::SweepReader& in, std::size_t c);
// The table of every bisection: its bracket, classes, status and probes.
std::string bisection_report(const results::SweepReader& in, const ChainNames& names);
// The CSV of `astrojax thresholds --csv` with the bisections' rows: the ladder's columns, then
// group, variant, one column per grid axis, method (ladder or bisection), width_rad_s,
// before_class, after_class, bisect_status, probes_run, start_seed (the chain's start: one
// threshold found from two starts gives two brackets at one grid point). A bisection without a bracket gives
// before alone (no crossing: the far end, still on the known side) or after alone (the start
// level, already past the threshold).
std::string with_bisection_rows(const std::string& csv, const results::SweepReader& in, const ChainNames& names);

}  // namespace ajx::app
