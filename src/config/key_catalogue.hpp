// Every key a configuration file may hold, described once for the reader and the reference.
// [model] and [layers] (and the [grid] axes that set a model parameter) come from the physics'
// parameter table; the other sections' keys are listed in key_catalogue.cpp. The reader refuses
// to read a key that is not listed (a logic error the tests catch), and for a number it checks
// that the range it enforces is the one listed, so the generated reference cannot drift.
#pragma once
#include <cmath>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace ajx::config {

struct KeyInfo {
  std::string section;   // "integrator", "protocol.segment", "grid", ...
  std::string key;
  std::string type;      // number, whole number, word, text, boolean, 3-vector, list, table
  std::string unit;      // SI, "" for none
  std::string allowed;   // the range or the words, as the reader enforces them
  std::string fallback;  // the default, "" when the key is required or has none
  std::string doc;
  // For a number with a fixed range (the reader checks its bounds against these); NaN lo when
  // the range depends on other keys (then `allowed` says how).
  double lo = std::nan(""), hi = std::nan("");
  bool lo_open = false, hi_open = false;
};

// All keys, sections in file order.
const std::vector<KeyInfo>& key_catalogue();
// The entry for a key of a section as the reader names it ("schedule[2]", "variant.clutch.model",
// "grid.drive_radius" are the sections schedule, model, grid.*), or nullptr.
const KeyInfo* find_key(std::string_view section, std::string_view key);
// The catalogue's name for a reader's section prefix.
std::string generic_section(std::string_view prefix);

// The catalogue's entries the reader has read in this process, "section.key" (a test reads a
// corpus of files and checks that no catalogue entry is stale).
void note_read(const KeyInfo& k);
std::vector<std::string> keys_read();

// The reference as Markdown: one table per section (the docs site's configuration page).
std::string key_reference_markdown();

}  // namespace ajx::config
