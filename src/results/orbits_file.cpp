#include "results/orbits_file.hpp"

#include <fmt/format.h>
#include <fstream>
#include <span>
#include <stdexcept>
#include <utility>

#include "io/hdf5_file.hpp"
#include "results/provenance.hpp"

namespace ajx::results {

void write_csv(const std::string& path, const Table& t, const TextColumns& leading) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  const std::size_t rows = !t.empty() ? t.front().values.size() : !leading.empty() ? leading.front().second.size() : 0;
  bool first = true;
  const auto sep = [&] { return std::exchange(first, false) ? "" : ","; };
  for (const auto& [name, values] : leading) out << sep() << name;
  for (const TableColumn& c : t) out << sep() << c.name;
  out << '\n';
  for (std::size_t i = 0; i < rows; ++i) {
    first = true;
    for (const auto& [name, values] : leading) out << sep() << values.at(i);
    for (const TableColumn& c : t) out << sep() << fmt::format("{:.12g}", c.values.at(i));
    out << '\n';
  }
  if (!out.flush()) throw std::runtime_error("cannot write " + path);
}

namespace {

// One dataset per column, each with its unit.
void write_table(io::Group& g, const Table& t) {
  for (const TableColumn& c : t) g.write_dataset(c.name, std::span<const double>(c.values)).set_attribute("units", c.unit);
}

io::File open_output(const std::filesystem::path& out, const std::string& command_line,
                     const config::OrbitsConfig& cfg) {
  io::File f = create_output(out);
  write_format(f, "orbits");
  write_provenance(f, command_line, cfg);
  return f;
}

}  // namespace

void write_orbits_file(const std::filesystem::path& out, const std::string& command_line,
                       const config::OrbitsConfig& cfg, const OrbitsOutput& o) {
  io::File f = open_output(out, command_line, cfg);
  io::Group og = f.create_group("orbits");
  write_table(og, o.orbits);
  if (o.branches) {
    io::Group bg = f.create_group("branches");
    bg.set_attribute("parameter", o.branches->parameter);
    io::Group pg = bg.create_group("points");
    write_table(pg, o.branches->points);
    io::Group eg = bg.create_group("events");
    write_table(eg, o.branches->events);
    eg.set_attribute("kinds", std::span<const std::string>(o.branches->event_kinds));
  }
  if (o.thresholds) {
    io::Group tg = f.create_group("thresholds");
    for (const OrbitsOutput::Threshold& t : *o.thresholds) {
      io::Group g = tg.create_group(t.symbol);
      g.set_attribute("predicted", t.predicted);
      g.set_attribute("measured", t.measured);
      g.set_attribute("mechanism", t.mechanism);
    }
  }
  f.commit();
}

void write_curves_file(const std::filesystem::path& out, const std::string& command_line,
                       const config::OrbitsConfig& cfg, const CurvesOutput& c) {
  io::File f = open_output(out, command_line, cfg);
  io::Group g = f.create_group("curves");
  g.set_attribute("parameter", c.parameter);
  g.set_attribute("parameter_symbol", c.symbol);
  g.set_attribute("parameter_unit", c.unit);
  g.set_attribute("kinds", std::span<const std::string>(c.kinds));
  g.set_attribute("stop_reasons", std::span<const std::string>(c.stop_reasons));
  io::Group pg = g.create_group("points");
  write_table(pg, c.points);
  io::Group mg = g.create_group("codim2");
  write_table(mg, c.codim2);
  mg.set_attribute("names", std::span<const std::string>(c.codim2_names));
  f.commit();
}

}  // namespace ajx::results
