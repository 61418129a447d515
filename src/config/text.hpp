// Text from files shown on a terminal: labels, purposes and names may hold any UTF-8 but
// control characters other than TAB (refused at input), and whatever a damaged or foreign file
// holds is escaped before it is printed, so that no byte of it can move the cursor, clear the
// screen or start a new line that looks like the program's own.
#pragma once
#include <cstdint>
#include <fmt/format.h>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace ajx::config {

namespace text_detail {
// The code point of the UTF-8 sequence at s[i] and its length; nullopt for an invalid one.
inline std::optional<std::pair<char32_t, std::size_t>> decode_utf8(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return std::pair{char32_t(c), std::size_t(1)};
  const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return std::nullopt;
  char32_t cp = c & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((b(i + k) & 0xC0) != 0x80) return std::nullopt;
    cp = (cp << 6) | (b(i + k) & 0x3F);
  }
  if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF))
    return std::nullopt;
  return std::pair{cp, n};
}
// C0 controls, DEL and the C1 controls.
constexpr bool is_control(char32_t cp) { return cp < 0x20 || (cp >= 0x7F && cp < 0xA0); }
}  // namespace text_detail

// The first control character other than TAB in `s` (as a code point), if any; a byte that is
// not UTF-8 counts as one (its value).
inline std::optional<char32_t> control_character(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto d = text_detail::decode_utf8(s, i);
    if (!d) return char32_t(static_cast<unsigned char>(s[i]));
    if (text_detail::is_control(d->first) && d->first != U'\t') return d->first;
    i += d->second;
  }
  return std::nullopt;
}

// "U+000A"
inline std::string code_point_name(char32_t cp) { return fmt::format("U+{:04X}", std::uint32_t(cp)); }

// `s` as it may be printed: control characters (TAB too) as \t, \n, \r or \u{XXXX}, bytes that
// are not UTF-8 as \xNN, a backslash as \\; everything else unchanged.
inline std::string printable(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto d = text_detail::decode_utf8(s, i);
    if (!d) {
      out += fmt::format("\\x{:02X}", static_cast<unsigned char>(s[i]));
      ++i;
      continue;
    }
    const char32_t cp = d->first;
    if (cp == U'\\') out += "\\\\";
    else if (cp == U'\t') out += "\\t";
    else if (cp == U'\n') out += "\\n";
    else if (cp == U'\r') out += "\\r";
    else if (text_detail::is_control(cp)) out += fmt::format("\\u{{{:04X}}}", std::uint32_t(cp));
    else out.append(s.substr(i, d->second));
    i += d->second;
  }
  return out;
}

}  // namespace ajx::config
