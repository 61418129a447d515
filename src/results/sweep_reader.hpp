// The one reader of sweep files (layout: docs/reference/file-format.md; the writer is
// sweep_file.hpp). Opening validates the whole file before anyone uses a value of it: the
// format version (1 to kFileFormatVersion, an integer), every dataset of the layout present
// with its rank, shape and type class, every chunk read once (so a Fletcher32 or deflate
// checksum that fails shows here), no NaN or Inf where the writer never stores one, class
// codes, sample counts, statuses and indices into names in range. Anything wrong throws
// SweepFileError naming the file, the dataset and, where it is one element, its index.
// Every command that reads a sweep file (thresholds, classify, verify, orbits --compare) reads
// it through this class; formats 1 and 2 (strings joined by newlines or commas) still read.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "physics/parameter_table.hpp"
#include "physics/state.hpp"
#include "results/sweep_file.hpp"

namespace ajx::results {

// A sweep file that is damaged or not one: what() is "<file>: /<dataset>: <problem>" (the
// dataset left out when the problem is the whole file).
class SweepFileError : public std::runtime_error {
 public:
  SweepFileError(std::string file, std::string dataset, const std::string& problem);
  const std::string& file() const noexcept { return file_; }
  const std::string& dataset() const noexcept { return dataset_; }  // "windows/class", "" for the file
  const std::string& problem() const noexcept { return problem_; }  // what() without file and dataset

 private:
  std::string file_, dataset_, problem_;
};

// Arrays as read: dims and row-major elements.
template <class T>
using Array = io::Array<T>;

// Names by index (groups, variants, seeds) and the text beside each (purpose, label).
struct NameList {
  std::vector<std::string> names, texts;
  std::vector<std::int32_t> of_chain;  // each chain's index into names
};

// /brackets (format 5, a sweep with [bisect] chains): per bisection chain and per probe, as
// results/brackets_file.hpp writes them.
struct BracketTable {
  std::vector<std::int64_t> chain;                       // per bracket: its chain
  std::vector<std::int32_t> threshold, planned;           // sweep::Threshold; probes planned
  std::vector<double> from, to, width, start_omega;       // [rad/s]
  std::vector<double> known_omega, other_omega;           // the bracket [rad/s]
  std::vector<std::int32_t> known_class, other_class, status;  // status: sweep::BisectStatus, -1 not computed
  std::vector<double> guide;  // [rad/s] the guided chains' predictions (NaN: none); empty in an unguided file
  struct Probes {
    std::vector<std::int64_t> chain, index;
    std::vector<double> omega_m, known_omega, other_omega;
    std::vector<std::int32_t> cls, ran, known_side, status;
    Array<double> stats, powers;  // probes × kNumStats, probes × kNumPowers
  } probes;
  std::size_t size() const { return chain.size(); }
};

class SweepReader {
 public:
  // Opens read-only and validates; throws SweepFileError.
  explicit SweepReader(const std::filesystem::path& path);

  const std::string& path() const { return path_; }
  std::int64_t format_version() const { return version_; }
  std::size_t chains() const { return C_; }
  std::size_t windows() const { return W_; }              // per chain, the longest chain's
  std::size_t samples_per_window() const { return cap_; }  // stored at most
  std::size_t tasks() const { return T_; }

  // /config: the sweep file verbatim, its name and the --set overrides; parsed again.
  const std::string& config_text() const { return config_text_; }
  const std::string& config_source() const { return config_source_; }
  const std::vector<std::string>& overrides() const { return overrides_; }
  config::SweepConfig config() const;  // throws SweepFileError naming /config
  // /provenance@git_commit: the commit of the astrojax that wrote the file, "" without it.
  const std::string& git_commit() const { return git_commit_; }

  const StoredModels& models() const { return models_; }
  const std::vector<std::string>& axes() const { return axes_; }
  const Array<double>& grid_values() const { return grid_; }  // chains × axes; empty without axes
  bool grouped() const { return grouped_; }
  const NameList& groups() const { return groups_; }      // texts: purposes
  const NameList& variants() const { return variants_; }  // texts: labels
  const NameList& start_seeds() const { return start_seeds_; }

  // /windows: chains × windows.
  const Array<std::int32_t>& classes() const { return cls_; }
  const Array<std::int32_t>& direction() const { return dir_; }
  const Array<double>& omega_m_begin() const { return wb_; }
  const Array<double>& omega_m_end() const { return we_; }
  const Array<double>& t_begin() const { return tb_; }  // [s]
  const Array<double>& t_end() const { return te_; }    // [s]
  // A statistic of kStats or kPowers by name; throws std::logic_error for another name.
  const Array<double>& stat(std::string_view name) const;
  const Array<double>& mode_fraction() const { return modes_; }
  // The classifier settings the windows were classified with ("name=value" lines), empty for
  // the defaults.
  const std::vector<std::string>& classifier_settings() const { return classifier_settings_; }

  // /samples: counts (chains × windows) and a column (chains × windows × cap [× 3]), read from
  // the file when asked (it was validated on open).
  const Array<std::int32_t>& count() const { return count_; }
  Array<double> samples(std::string_view column) const;

  // /basins (format 5, a sweep with basin chains): per sample its chain, level row and class;
  // per level its ω_m, samples done and class counts. Empty without basins.
  bool has_basins() const { return !basin_chain_.empty(); }
  const std::vector<std::int64_t>& basin_chain() const { return basin_chain_; }
  const std::vector<std::int32_t>& basin_level() const { return basin_level_; }
  const std::vector<std::int32_t>& basin_class() const { return basin_class_; }
  const std::vector<double>& basin_level_omega() const { return basin_omega_; }
  const std::vector<std::int32_t>& basin_done() const { return basin_done_; }
  const Array<std::int32_t>& basin_count() const { return basin_count_; }  // levels × classes
  const Array<double>& basin_fraction() const { return basin_fraction_; }
  const Array<double>& basin_lower() const { return basin_lower_; }
  const Array<double>& basin_upper() const { return basin_upper_; }
  // Each sample's attractor matched across ω_m (empty in a file made before the matching was
  // stored) and the attractors' names.
  const std::vector<std::int32_t>& basin_attractor() const { return basin_attractor_; }
  const std::vector<std::string>& basin_attractor_names() const { return basin_attractor_names_; }

  // /tasks
  const std::vector<TaskStatus>& status() const { return status_; }
  // A task's last state, where the next task starts (a tie's W_m, W_c from 0 in files that
  // predate the motor's ledger).
  physics::State final_state(std::size_t task) const;
  const std::vector<std::string>& failures() const { return failures_; }

  const io::File& file() const { return f_; }

  // /brackets; none for a sweep without bisections.
  const std::optional<BracketTable>& brackets() const { return brackets_; }

 private:
  [[noreturn]] void fail(std::string_view dataset, const std::string& problem) const;
  io::Dataset dataset(std::string_view name, std::size_t rank, io::TypeClass type) const;
  Array<double> doubles(std::string_view name, const io::Dims& dims) const;
  Array<std::int32_t> ints(std::string_view name, const io::Dims& dims) const;
  std::vector<std::string> strings(std::string_view object, std::string_view attr, char joined_by) const;
  void read_version();
  void read_config();
  void read_chains();
  void read_groups();
  void read_windows();
  void read_samples();
  void read_tasks();
  void read_classes() const;
  void read_basins();
  void read_basin_attractors(std::size_t samples, std::size_t levels);
  void read_brackets();  // sweep_reader_brackets.cpp

  std::string path_;
  io::File f_;
  std::int64_t version_ = 1;
  std::size_t C_ = 0, W_ = 0, cap_ = 0, T_ = 0;
  std::string config_text_, config_source_, git_commit_;
  std::vector<std::string> overrides_, axes_, classifier_settings_, failures_;
  StoredModels models_;
  Array<double> grid_;
  bool grouped_ = false;
  NameList groups_, variants_, start_seeds_;
  Array<std::int32_t> cls_, dir_, count_;
  Array<double> wb_, we_, tb_, te_, modes_;
  std::map<std::string, Array<double>, std::less<>> stats_;
  std::vector<TaskStatus> status_;
  Array<double> final_states_;
  std::vector<std::int64_t> basin_chain_;
  std::vector<std::int32_t> basin_level_, basin_class_, basin_done_, basin_attractor_;
  std::vector<std::string> basin_attractor_names_;
  std::vector<double> basin_omega_;
  Array<std::int32_t> basin_count_;
  Array<double> basin_fraction_, basin_lower_, basin_upper_;
  std::optional<BracketTable> brackets_;
};

}  // namespace ajx::results
