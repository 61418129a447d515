#include "results/sweep_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <optional>
#include <span>
#include <utility>

#include "physics/state_row.hpp"
#include "results/basin_file.hpp"
#include "sweep/basin.hpp"
#include "sweep/orbit_classes.hpp"
#include "sweep/orbit_classifier.hpp"

namespace ajx::results {

SweepFileError::SweepFileError(std::string file, std::string dataset, const std::string& problem)
    : std::runtime_error(dataset.empty() ? fmt::format("{}: {}", file, problem)
                                         : fmt::format("{}: /{}: {}", file, dataset, problem)),
      file_(std::move(file)),
      dataset_(std::move(dataset)),
      problem_(problem) {}

StoredModels stored_models(const std::vector<std::string>& columns, const io::Array<double>& model) {
  std::vector<const physics::ParameterInfo*> cols;
  StoredModels out;
  for (const std::string& column : columns) {
    const std::string name = column.substr(0, column.find(" ["));
    const physics::ParameterInfo* info = physics::find_parameter(name);
    if (!info) throw std::runtime_error(fmt::format("unknown column '{}'", name));
    cols.push_back(info);
    out.present.push_back(name);
  }
  if (cols.size() != model.cols())
    throw std::runtime_error(fmt::format("{} columns but {} column names", model.cols(), cols.size()));
  for (const physics::ParameterInfo& info : physics::kParameters)
    if (std::find(out.present.begin(), out.present.end(), info.key) == out.present.end()) out.lacking.emplace_back(info.key);
  for (std::size_t c = 0; c < model.rows(); ++c) {
    physics::Parameters p;
    for (std::size_t j = 0; j < cols.size(); ++j) p.*cols[j]->field = model(c, j);
    out.chains.push_back(p);
  }
  return out;
}

namespace {

std::string dims_text(const io::Dims& d) { return fmt::format("[{}]", fmt::join(d, ", ")); }

// "[c, k]" of element i of an array of dims d.
std::string index_text(const io::Dims& d, std::size_t i) {
  std::vector<std::size_t> idx(d.size());
  for (std::size_t a = d.size(); a-- > 0;) {
    idx[a] = i % d[a];
    i /= d[a];
  }
  return fmt::format("[{}]", fmt::join(idx, ", "));
}

const char* type_name(io::TypeClass t) {
  switch (t) {
    case io::TypeClass::Integer: return "integer";
    case io::TypeClass::Float: return "floating-point";
    case io::TypeClass::String: return "string";
    case io::TypeClass::Other: break;
  }
  return "other";
}

std::vector<std::string> split(const std::string& text, char by, bool keep_empty) {
  std::vector<std::string> out;
  std::size_t a = 0;
  for (std::size_t b; (b = text.find(by, a)) != std::string::npos; a = b + 1)
    if (keep_empty || b > a) out.push_back(text.substr(a, b - a));
  if (keep_empty || a < text.size()) out.push_back(text.substr(a));
  return out;
}

}  // namespace

void SweepReader::fail(std::string_view dataset, const std::string& problem) const {
  throw SweepFileError(path_, std::string(dataset), problem);
}

// The dataset, checked for presence, rank and type class.
io::Dataset SweepReader::dataset(std::string_view name, std::size_t rank, io::TypeClass type) const {
  if (!f_.exists(name)) fail(name, "missing");
  io::Dataset d = f_.open_dataset(name);
  const io::Dims dims = d.dims();
  if (dims.size() != rank) fail(name, fmt::format("has {} dimensions {}, expected {}", dims.size(), dims_text(dims), rank));
  if (d.type_class() != type)
    fail(name, fmt::format("is stored as {}, expected {}", type_name(d.type_class()), type_name(type)));
  return d;
}

Array<double> SweepReader::doubles(std::string_view name, const io::Dims& dims) const {
  const io::Dataset d = dataset(name, dims.size(), io::TypeClass::Float);
  if (d.dims() != dims) fail(name, fmt::format("has shape {}, expected {}", dims_text(d.dims()), dims_text(dims)));
  try {
    return d.read_doubles();
  } catch (const io::Hdf5Error& e) {
    fail(name, fmt::format("cannot be read (a checksum fails or the file is damaged): {}", e.what()));
  }
}

Array<std::int32_t> SweepReader::ints(std::string_view name, const io::Dims& dims) const {
  const io::Dataset d = dataset(name, dims.size(), io::TypeClass::Integer);
  if (d.dims() != dims) fail(name, fmt::format("has shape {}, expected {}", dims_text(d.dims()), dims_text(dims)));
  try {
    return d.read_int32s();
  } catch (const io::Hdf5Error& e) {
    fail(name, fmt::format("cannot be read (a checksum fails or the file is damaged): {}", e.what()));
  }
}

// A list of strings: a 1-D string attribute (format 3), or one string joined by `joined_by`.
std::vector<std::string> SweepReader::strings(std::string_view object, std::string_view attr, char joined_by) const {
  const std::string where = fmt::format("{}@{}", object, attr);
  if (!f_.exists(object)) fail(object, "missing");
  // The groups here are /chains and /tasks; the other holders are datasets.
  const bool group = object == "chains" || object == "tasks";
  std::optional<io::Group> grp;
  std::optional<io::Dataset> dset;
  if (group)
    grp = f_.open_group(object);
  else
    dset = f_.open_dataset(object);
  const io::Object& g = group ? static_cast<const io::Object&>(*grp) : *dset;
  if (!g.has_attribute(attr)) fail(where, "missing");
  if (g.attribute_type_class(attr) != io::TypeClass::String) fail(where, "is not a string");
  const io::Dims dims = g.attribute_dims(attr);
  if (version_ >= 3) {
    if (dims.size() != 1)
      fail(where, fmt::format("is one string, but format_version {} stores a list (one element per item)", version_));
    return g.read_strings_attribute(attr);
  }
  if (!dims.empty())
    fail(where, fmt::format("is a list, but format_version {} joins the items into one string{}", version_,
                            f_.has_attribute("format_version") ? "" : " (the file has no format_version)"));
  return split(g.read_string_attribute(attr), joined_by, joined_by == '\n');
}

SweepReader::SweepReader(const std::filesystem::path& path) : path_(path.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("", "no such file");
  if (std::filesystem::is_directory(path, ec)) fail("", "is a directory, not a file");
  try {
    f_ = io::File::open_read(path);
  } catch (const io::Hdf5Error& e) {
    fail("", fmt::format("cannot be opened as an HDF5 file: {}", e.what()));
  }
  // Damaged metadata can fail anywhere: the step that was reading names the dataset.
  std::string_view step = "";
  try {
    step = "";
    read_version();
    step = "config";
    read_config();
    step = "windows";
    read_windows();
    step = "chains";
    read_chains();
    read_groups();
    step = "samples";
    read_samples();
    step = "tasks";
    read_tasks();
    step = "classes";
    read_classes();
    step = "basins";
    read_basins();
    step = "brackets";
    read_brackets();
  } catch (const io::Hdf5Error& e) {
    fail(step, fmt::format("cannot be read (the file is damaged): {}", e.what()));
  }
}

void SweepReader::read_version() {
  if (f_.has_attribute("format_version")) {
    if (f_.attribute_type_class("format_version") != io::TypeClass::Integer || !f_.attribute_dims("format_version").empty())
      fail("", "the root attribute format_version is not an integer");
    version_ = f_.read_int64_attribute("format_version");
    if (version_ > kFileFormatVersion)
      fail("", fmt::format("file format version {} (root attribute format_version) is newer than this program reads "
                           "({}); use the astrojax that wrote it", version_, kFileFormatVersion));
    if (version_ < 1)
      fail("", fmt::format("file format version {} (root attribute format_version) is not one (1 to {})", version_,
                           kFileFormatVersion));
  }
  if (f_.has_attribute("format")) {
    if (f_.attribute_type_class("format") != io::TypeClass::String) fail("", "the root attribute format is not a string");
    const std::string kind = f_.read_string_attribute("format");
    if (kind != "sweep") fail("", fmt::format("is a {} file, not a sweep's", kind));
  }
}

void SweepReader::read_config() {
  const io::Dataset d = dataset("config", 0, io::TypeClass::String);
  config_text_ = d.read_string();
  if (!d.has_attribute("source") || d.attribute_type_class("source") != io::TypeClass::String)
    fail("config@source", "missing or not a string");
  config_source_ = d.read_string_attribute("source");
  overrides_ = strings("config", "overrides", '\n');
  if (version_ < 3) std::erase(overrides_, std::string());
  // /provenance (written when the sweep finishes) names the commit; a file without it reads "".
  if (f_.exists("provenance")) {
    const io::Group prov = f_.open_group("provenance");
    if (prov.has_attribute("git_commit") && prov.attribute_type_class("git_commit") == io::TypeClass::String &&
        prov.attribute_dims("git_commit").empty())
      git_commit_ = prov.read_string_attribute("git_commit");
  }
}

config::SweepConfig SweepReader::config() const {
  try {
    return config::parse_sweep_config(config_text_, config_source_, overrides_);
  } catch (const config::ConfigError& e) {
    fail("config", fmt::format("the stored sweep file is not valid: {}", e.what()));
  }
}

void SweepReader::read_windows() {
  const io::Dataset cd = dataset("windows/class", 2, io::TypeClass::Integer);
  C_ = cd.dims()[0];
  W_ = cd.dims()[1];
  const io::Dims cw{C_, W_};
  cls_ = ints("windows/class", cw);
  dir_ = ints("windows/direction", cw);
  (void)ints("windows/segment", cw);
  wb_ = doubles("windows/omega_m_begin", cw);
  we_ = doubles("windows/omega_m_end", cw);
  tb_ = doubles("windows/t_begin", cw);
  te_ = doubles("windows/t_end", cw);
  if (version_ >= 2) (void)doubles("windows/phi_begin", cw);
  for (std::size_t i = 0; i < C_ * W_; ++i) {
    const std::int32_t c = cls_.data[i];
    if (c < -1 || c >= std::int32_t(sweep::kNumOrbitClasses))
      fail("windows/class", fmt::format("at {}: class code {} is not one of -1 to {}", index_text(cw, i), c,
                                        sweep::kNumOrbitClasses - 1));
    if (c < 0) continue;  // not computed: its layout may be padding
    const std::pair<const char*, const Array<double>*> spans[] = {
        {"windows/t_begin", &tb_}, {"windows/t_end", &te_}, {"windows/omega_m_begin", &wb_}, {"windows/omega_m_end", &we_}};
    for (const auto& [name, a] : spans)
      if (!std::isfinite(a->data[i])) fail(name, fmt::format("at {}: {} in a computed window", index_text(cw, i), a->data[i]));
    if (dir_.data[i] < -1 || dir_.data[i] > 1)
      fail("windows/direction", fmt::format("at {}: {} is not -1, 0 or +1", index_text(cw, i), dir_.data[i]));
  }
  for (const WindowStat& s : kStats) stats_[s.name] = doubles(std::string("windows/") + s.name, cw);
  for (const WindowPower& s : kPowers) {
    const std::string name = std::string("windows/") + s.name;
    if (version_ < s.since && !f_.exists(name)) {  // before the energy account, or before this column
      stats_[s.name] = Array<double>{cw, std::vector<double>(C_ * W_, kNotComputed)};
      continue;
    }
    stats_[s.name] = doubles(name, cw);
  }
  modes_ = doubles("windows/mode_fraction", {C_, W_, kNumModes});
  const io::Group wg = f_.open_group("windows");
  if (wg.has_attribute("classifier_settings")) {
    if (wg.attribute_type_class("classifier_settings") != io::TypeClass::String)
      fail("windows@classifier_settings", "is not a string");
    const std::string used = wg.read_string_attribute("classifier_settings");
    if (used != "defaults") classifier_settings_ = split(used, '\n', false);
    try {
      (void)sweep::parse_classifier_settings(classifier_settings_);
    } catch (const std::invalid_argument& e) {
      fail("windows@classifier_settings", e.what());
    }
  }
}

void SweepReader::read_chains() {
  const io::Dataset md = dataset("chains/model", 2, io::TypeClass::Float);
  const Array<double> model = doubles("chains/model", {C_, md.dims()[1]});
  const std::vector<std::string> columns = strings("chains/model", "columns", ',');
  try {
    models_ = stored_models(columns, model);
  } catch (const std::runtime_error& e) {
    fail("chains/model", e.what());
  }
  for (std::size_t i = 0; i < model.data.size(); ++i)
    if (std::isnan(model.data[i])) fail("chains/model", fmt::format("at {}: NaN", index_text(model.dims, i)));
  axes_ = strings("chains", "axes", ',');
  if (!axes_.empty()) {
    if (!f_.exists("chains/grid_values"))
      fail("chains/grid_values", fmt::format("missing, though /chains@axes names {} axes", axes_.size()));
    grid_ = doubles("chains/grid_values", {C_, axes_.size()});
  }
}

void SweepReader::read_groups() {
  // Each index in [0, n) of its names; texts (purposes, labels) one per name.
  const auto indexed = [&](const char* name, std::size_t n) {
    Array<std::int32_t> a = ints(name, {C_});
    for (std::size_t c = 0; c < C_; ++c)
      if (a.data[c] < 0 || std::size_t(a.data[c]) >= n)
        fail(name, fmt::format("at [{}]: index {} is not one of 0 to {}", c, a.data[c], std::int64_t(n) - 1));
    return a.data;
  };
  const auto names = [&](NameList& list, const char* ds, const char* texts) {
    list.names = strings(ds, "names", '\n');
    if (texts) {
      list.texts = strings(ds, texts, '\n');
      if (list.texts.size() != list.names.size())
        fail(fmt::format("{}@{}", ds, texts),
             fmt::format("{} of them for the {} of {}@names", list.texts.size(), list.names.size(), ds));
    }
    list.of_chain = indexed(ds, list.names.size());
  };
  if (f_.exists("chains/variant") || f_.exists("chains/group")) {
    grouped_ = true;
    names(groups_, "chains/group", "purposes");
    names(variants_, "chains/variant", "labels");
    names(start_seeds_, "chains/start_seed", nullptr);
    (void)doubles("chains/start_omega", {C_});
    std::size_t parts = 0;
    while (f_.exists(fmt::format("resolved/{}", parts))) ++parts;
    (void)indexed("chains/part", parts);
  }
  if (f_.exists("chains/seed") || f_.exists("chains/hold_omega")) {
    NameList seeds;
    names(seeds, "chains/seed", nullptr);
    (void)doubles("chains/hold_omega", {C_});
    const Array<std::int32_t> pert = ints("chains/perturbation", {C_});
    for (std::size_t c = 0; c < C_; ++c)
      if (pert.data[c] < 0) fail("chains/perturbation", fmt::format("at [{}]: {} is negative", c, pert.data[c]));
  }
}

void SweepReader::read_samples() {
  if (!f_.exists("samples")) fail("samples", "missing: the file stores no samples of its windows");
  count_ = ints("samples/count", {C_, W_});
  cap_ = dataset("samples/t", 3, io::TypeClass::Float).dims()[2];
  for (std::size_t i = 0; i < C_ * W_; ++i) {
    const std::int32_t n = count_.data[i];
    if (n < 0 || std::size_t(n) > cap_)
      fail("samples/count", fmt::format("at {}: {} samples, not 0 to {}", index_text({C_, W_}, i), n, cap_));
    if (n > 0 && cls_.data[i] < 0)
      fail("samples/count", fmt::format("at {}: {} samples in a window never computed (class -1)", index_text({C_, W_}, i), n));
  }
  // Every column read once (its checksums), finite inside each window's count (but in a
  // failed window, whose last samples may be what made the integration fail).
  const auto failed = std::int32_t(sweep::OrbitClass::Failed);
  for (std::size_t k = 0; k < kNumSampleColumns; ++k) {
    const std::size_t width = k < 6 ? 1 : 3;
    const std::string name = std::string("samples/") + kSampleColumns[k];
    const Array<double> a = doubles(name, width == 1 ? io::Dims{C_, W_, cap_} : io::Dims{C_, W_, cap_, 3});
    for (std::size_t i = 0; i < C_ * W_; ++i)
      if (cls_.data[i] != failed)
        for (std::size_t j = 0; j < width * std::size_t(count_.data[i]); ++j)
          if (!std::isfinite(a.data[i * cap_ * width + j]))
            fail(name, fmt::format("at {}: {} inside the window's {} samples", index_text(a.dims, i * cap_ * width + j),
                                   a.data[i * cap_ * width + j], count_.data[i]));
  }
}

Array<double> SweepReader::samples(std::string_view column) const {
  const std::string name = "samples/" + std::string(column);
  const bool vec = column == "r1" || column == "r2";
  return doubles(name, vec ? io::Dims{C_, W_, cap_, 3} : io::Dims{C_, W_, cap_});
}

void SweepReader::read_tasks() {
  T_ = dataset("tasks/status", 1, io::TypeClass::Integer).dims()[0];
  for (const char* name : {"tasks/chain", "tasks/index", "tasks/steps", "tasks/t_begin", "tasks/t_end"})
    if (f_.exists(name) && f_.open_dataset(name).dims() != io::Dims{T_})
      fail("tasks/status", fmt::format("{} tasks, but /{} has shape {}: the task datasets disagree", T_, name,
                                       dims_text(f_.open_dataset(name).dims())));
  const Array<std::int32_t> st = ints("tasks/status", {T_}), chain = ints("tasks/chain", {T_});
  (void)ints("tasks/index", {T_});
  (void)dataset("tasks/steps", 1, io::TypeClass::Integer);
  (void)doubles("tasks/t_begin", {T_});
  (void)doubles("tasks/t_end", {T_});
  for (std::size_t t = 0; t < T_; ++t) {
    if (st.data[t] < 0 || st.data[t] > kMaxTaskStatus)
      fail("tasks/status", fmt::format("at [{}]: status {} is not one of 0 to {}", t, st.data[t], kMaxTaskStatus));
    if (chain.data[t] < 0 || std::size_t(chain.data[t]) >= C_)
      fail("tasks/chain", fmt::format("at [{}]: chain {} is not one of 0 to {}", t, chain.data[t], std::int64_t(C_) - 1));
    status_.push_back(TaskStatus(st.data[t]));
  }
  {
    const io::Dataset d = dataset("tasks/steps", 1, io::TypeClass::Integer);
    if (d.dims() != io::Dims{T_}) fail("tasks/steps", fmt::format("has shape {}, expected [{}]", dims_text(d.dims()), T_));
    try {
      (void)d.read_int64s();
    } catch (const io::Hdf5Error& e) {
      fail("tasks/steps", fmt::format("cannot be read (a checksum fails or the file is damaged): {}", e.what()));
    }
  }
  // Files from before the tie clutch hold 20 columns: t, mode, sigma, s_star, impact_loss, y;
  // files before format 4 lack the motor's ledger, the last two. Missing columns read as NaN.
  const io::Dataset fd = dataset("tasks/final_state", 2, io::TypeClass::Float);
  const std::size_t cols = fd.dims()[1];
  if (cols != physics::kStateCols && !(version_ < 3 && cols == 5 + physics::idx::dim) &&
      !(version_ < 4 && cols == physics::kStateCols - 2))
    fail("tasks/final_state", fmt::format("has {} columns, expected {}", cols, physics::kStateCols));
  final_states_ = doubles("tasks/final_state", {T_, cols});
  if (f_.open_group("tasks").has_attribute("failures")) failures_ = strings("tasks", "failures", '\n');
  if (version_ < 3) std::erase(failures_, std::string());
}

physics::State SweepReader::final_state(std::size_t task) const {
  std::vector<double> row(physics::kStateCols, kNotComputed);
  const std::size_t cols = final_states_.cols();
  std::copy_n(&final_states_.data[task * cols], cols, row.begin());
  physics::State s = physics::state_from_row(row);
  // Files before format 4 hold no motor's ledger: a tie's W_m and W_c would read as NaN. A run
  // restarted from the state (a replay, a hold) integrates them from 0 at its start; the motion
  // does not depend on them.
  if (physics::has_ledger(s.y))
    for (const int i : {physics::idx::rod_work, physics::idx::clutch_loss})
      if (std::isnan(s.y(i))) s.y(i) = 0.0;
  return s;
}

// Format 3: /classes as this program declares them (sweep/orbit_classes.hpp).
void SweepReader::read_classes() const {
  if (version_ < 3) return;
  const std::size_t n = sweep::kNumOrbitClasses;
  const auto list = [&](const char* name) {
    const io::Dataset d = dataset(name, 1, io::TypeClass::String);
    if (d.dims() != io::Dims{n}) fail(name, fmt::format("has shape {}, expected [{}]", dims_text(d.dims()), n));
    return d.read_strings();
  };
  const std::vector<std::string> names = list("classes/name"), colours = list("classes/colour");
  (void)list("classes/description");
  const Array<std::int32_t> circular = ints("classes/circular", {n});
  for (std::size_t k = 0; k < n; ++k) {
    const sweep::OrbitClassInfo& c = sweep::kOrbitClasses[k];
    if (names[k] != c.name) fail("classes/name", fmt::format("at [{}]: '{}', this program's class {} is '{}'", k, names[k], k, c.name));
    if ((circular.data[k] != 0) != c.circular)
      fail("classes/circular", fmt::format("at [{}]: {} for {}, which is {}circular", k, circular.data[k], c.name,
                                           c.circular ? "" : "not "));
    const std::string& col = colours[k];
    if (col.size() != 7 || col[0] != '#' || col.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
      fail("classes/colour", fmt::format("at [{}]: '{}' is not #rrggbb", k, col));
  }
}

const Array<double>& SweepReader::stat(std::string_view name) const {
  const auto it = stats_.find(name);
  if (it == stats_.end()) throw std::logic_error(fmt::format("no window statistic named {}", name));
  return it->second;
}

}  // namespace ajx::results

namespace ajx::results {

// Format 5: /basins, when present, consistent with /windows (each sample's class is its chain's
// window 0) and with itself (counts, fractions and Wilson intervals recomputed to rounding).
void SweepReader::read_basins() {
  if (!f_.exists("basins")) return;
  if (version_ < 5) fail("basins", fmt::format("present in a file of format_version {} (basins came with 5)", version_));
  const io::Dataset cd = dataset("basins/chain", 1, io::TypeClass::Integer);
  const std::size_t S = cd.dims()[0];
  const auto chain = cd.read_int64s().data;
  basin_level_ = ints("basins/level", {S}).data;
  (void)ints("basins/sample", {S});
  basin_class_ = ints("basins/class", {S}).data;
  const Array<double> start = doubles("basins/start", {S, physics::kStateCols});
  const Array<double> features = doubles("basins/features", {S, kNumBasinFeatures});
  const std::size_t L = dataset("basins/levels/omega_m", 1, io::TypeClass::Float).dims()[0];
  basin_omega_ = doubles("basins/levels/omega_m", {L}).data;
  const auto first = dataset("basins/levels/first", 1, io::TypeClass::Integer).read_int64s();
  if (first.dims != io::Dims{L}) fail("basins/levels/first", fmt::format("has shape {}, expected [{}]", dims_text(first.dims), L));
  const auto samples = ints("basins/levels/samples", {L}).data;
  const auto family = ints("basins/levels/family", {L}).data;
  (void)ints("basins/levels/part", {L});
  basin_done_ = ints("basins/levels/done", {L}).data;
  const std::size_t K = sweep::kNumOrbitClasses;
  basin_count_ = ints("basins/levels/count", {L, K});
  basin_fraction_ = doubles("basins/levels/fraction", {L, K});
  basin_lower_ = doubles("basins/levels/lower", {L, K});
  basin_upper_ = doubles("basins/levels/upper", {L, K});
  for (std::size_t i = 0; i < S; ++i) {
    if (chain[i] < 0 || std::size_t(chain[i]) >= C_)
      fail("basins/chain", fmt::format("at [{}]: chain {} is not one of 0 to {}", i, chain[i], std::int64_t(C_) - 1));
    if (basin_level_[i] < 0 || std::size_t(basin_level_[i]) >= L)
      fail("basins/level", fmt::format("at [{}]: level {} is not one of 0 to {}", i, basin_level_[i], std::int64_t(L) - 1));
    const std::int32_t window_class = cls_.data[std::size_t(chain[i]) * W_];
    if (basin_class_[i] != window_class)
      fail("basins/class", fmt::format("at [{}]: class {}, but its chain {} has class {} in /windows/class", i,
                                       basin_class_[i], chain[i], window_class));
    for (std::size_t k = 0; k < physics::kStateCols; ++k)
      if (std::isinf(start(i, k))) fail("basins/start", fmt::format("at [{}, {}]: {}", i, k, start(i, k)));
    for (std::size_t k = 0; k < kNumBasinFeatures; ++k)
      if (std::isinf(features(i, k))) fail("basins/features", fmt::format("at [{}, {}]: {}", i, k, features(i, k)));
  }
  // Counts and fractions recomputed from the samples.
  std::vector<std::int32_t> done(L, 0), count(L * K, 0);
  for (std::size_t i = 0; i < S; ++i)
    if (basin_class_[i] >= 0) ++done[std::size_t(basin_level_[i])], ++count[std::size_t(basin_level_[i]) * K + std::size_t(basin_class_[i])];
  for (std::size_t l = 0; l < L; ++l) {
    if (samples[l] < 1) fail("basins/levels/samples", fmt::format("at [{}]: N = {}, not >= 1", l, samples[l]));
    if (first.data[l] < 0 || std::size_t(first.data[l]) + std::size_t(samples[l]) > S)
      fail("basins/levels/first", fmt::format("at [{}]: rows {} to {} are not inside the {} samples", l, first.data[l],
                                              first.data[l] + samples[l] - 1, S));
    if (family[l] < 0 || family[l] > 2) fail("basins/levels/family", fmt::format("at [{}]: {} is not one of 0 to 2", l, family[l]));
    if (basin_done_[l] != done[l])
      fail("basins/levels/done", fmt::format("at [{}]: {}, but {} of its samples have a class", l, basin_done_[l], done[l]));
    for (std::size_t k = 0; k < K; ++k) {
      const std::size_t i = l * K + k;
      if (basin_count_.data[i] != count[i])
        fail("basins/levels/count", fmt::format("at [{}, {}]: {}, but {} of its samples have class {}", l, k,
                                                basin_count_.data[i], count[i], k));
      const double p = basin_fraction_.data[i], lo = basin_lower_.data[i], hi = basin_upper_.data[i];
      if (done[l] == 0) {
        if (!std::isnan(p)) fail("basins/levels/fraction", fmt::format("at [{}, {}]: {} of no sample done", l, k, p));
        continue;
      }
      const sweep::Interval ci = sweep::wilson_interval(count[i], done[l]);
      if (!(std::abs(p - double(count[i]) / done[l]) <= 1e-12))
        fail("basins/levels/fraction", fmt::format("at [{}, {}]: {}, but count / done = {}", l, k, p, double(count[i]) / done[l]));
      if (!(std::abs(lo - ci.lo) <= 1e-12 && std::abs(hi - ci.hi) <= 1e-12))
        fail("basins/levels/lower", fmt::format("at [{}, {}]: [{}, {}] is not the Wilson interval [{}, {}]", l, k, lo, hi,
                                                ci.lo, ci.hi));
    }
  }
  basin_chain_ = chain;
  read_basin_attractors(S, L);
}

// /basins/attractor and /basins/attractors (written since 2026-11-28; a file of format 5 made
// before has neither, and `astrojax classify` adds them): every sample with a class is on one
// attractor of that class and of its level's part, and the counts, fractions and Wilson
// intervals are those of the samples.
void SweepReader::read_basin_attractors(std::size_t S, std::size_t L) {
  if (!f_.exists("basins/attractor") && !f_.exists("basins/attractors")) return;
  const std::vector<std::int32_t> label = ints("basins/attractor", {S}).data;
  const io::Dataset nd = dataset("basins/attractors/name", 1, io::TypeClass::String);
  const std::size_t A = nd.dims()[0];
  basin_attractor_names_ = nd.read_strings();
  const std::vector<std::int32_t> cls = ints("basins/attractors/class", {A}).data, part = ints("basins/attractors/part", {A}).data;
  const Array<std::int32_t> count = ints("basins/attractors/count", {L, A});
  const Array<double> fraction = doubles("basins/attractors/fraction", {L, A}), lower = doubles("basins/attractors/lower", {L, A}),
                      upper = doubles("basins/attractors/upper", {L, A});
  const std::vector<std::int32_t> level_part = ints("basins/levels/part", {L}).data;
  std::vector<std::int32_t> mine(L * A, 0);
  for (std::size_t i = 0; i < S; ++i) {
    const std::int32_t a = label[i], l = basin_level_[i];
    if ((a < 0) != (basin_class_[i] < 0) || a >= std::int32_t(A))
      fail("basins/attractor", fmt::format("at [{}]: {} for a sample of class {} (the file has {} attractors)", i, a,
                                           basin_class_[i], A));
    if (a < 0) continue;
    if (cls[std::size_t(a)] != basin_class_[i] || part[std::size_t(a)] != level_part[std::size_t(l)])
      fail("basins/attractor", fmt::format("at [{}]: attractor {} (class {}, part {}) for a sample of class {} in part {}", i, a,
                                           cls[std::size_t(a)], part[std::size_t(a)], basin_class_[i], level_part[std::size_t(l)]));
    ++mine[std::size_t(l) * A + std::size_t(a)];
  }
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t a = 0; a < A; ++a) {
      const std::size_t i = l * A + a;
      if (count.data[i] != mine[i])
        fail("basins/attractors/count", fmt::format("at [{}, {}]: {}, but {} of its samples are on it", l, a, count.data[i], mine[i]));
      if (basin_done_[l] == 0) continue;
      const sweep::Interval ci = sweep::wilson_interval(mine[i], basin_done_[l]);
      if (!(std::abs(fraction.data[i] - double(mine[i]) / basin_done_[l]) <= 1e-12) ||
          !(std::abs(lower.data[i] - ci.lo) <= 1e-12 && std::abs(upper.data[i] - ci.hi) <= 1e-12))
        fail("basins/attractors/fraction", fmt::format("at [{}, {}]: {} [{}, {}], but {} of {} with its Wilson interval", l, a,
                                                       fraction.data[i], lower.data[i], upper.data[i], mine[i], basin_done_[l]));
    }
  basin_attractor_ = label;
}

}  // namespace ajx::results
