// A table of named columns with units, the shape of every output of `astrojax orbits`:
// built from rows by a list of column accessors, written as CSV or as one HDF5 dataset per
// column (results/orbits_file.hpp).
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace ajx::results {

// One column: its name, its unit and one value per row.
struct TableColumn {
  std::string name, unit;
  std::vector<double> values;
};
using Table = std::vector<TableColumn>;

// How a column is read off a row of type Row.
template <class Row>
struct ColumnSpec {
  const char* name;
  const char* unit;
  std::function<double(const Row&)> get;
};

template <class Row>
Table tabulate(const std::vector<ColumnSpec<Row>>& spec, const std::vector<Row>& rows) {
  Table t;
  t.reserve(spec.size());
  for (const ColumnSpec<Row>& c : spec) {
    TableColumn col{c.name, c.unit, {}};
    col.values.reserve(rows.size());
    for (const Row& r : rows) col.values.push_back(c.get(r));
    t.push_back(std::move(col));
  }
  return t;
}

// Text columns written before a table's numbers in its CSV: a name and one value per row.
using TextColumns = std::vector<std::pair<std::string, std::vector<std::string>>>;

// The table as CSV (a header of names, numbers to 12 significant digits); throws
// std::runtime_error naming the path when it cannot be written.
void write_csv(const std::string& path, const Table& t, const TextColumns& leading = {});

}  // namespace ajx::results
