// astrojax verify: what is damaged in a sweep's file, finished or partial. The file is opened
// through the validating reader (sweep_reader.hpp: the version, every dataset's presence, rank,
// shape and type, every checksum, values out of range), then what a checksum cannot see is
// made again and compared: the layout (/chains, the windows' and tasks' spans, the names and
// labels) from the sweep file stored in /config, and every window's class and statistics from
// its stored samples with the classifier settings the file records. A partial file's journal
// is read (every record has a CRC-32) and its tasks compared with the file's status.
#pragma once
#include <string>
#include <vector>

namespace ajx::results {

struct VerifyReport {
  std::vector<std::string> notes;    // what was found that is not damage
  std::vector<std::string> damaged;  // one line each, naming the dataset and the index; raw
                                     // file contents: escape them where printed
};

VerifyReport verify_sweep_file(const std::string& path);

}  // namespace ajx::results
