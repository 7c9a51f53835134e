#include "core/printable.hpp"

#include <cstdio>

namespace softcut {

std::size_t utf8_sequence_length(std::string_view s) {
  if (s.empty()) return 0;
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte (RFC 3629 table)
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) n = 3, lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
  else if (c >= 0xF0 && c <= 0xF4) n = 4, lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
  else return 0;
  if (s.size() < n || b(1) < lo || b(1) > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (b(i) < 0x80 || b(i) > 0xBF) return 0;
  return n;
}

std::string printable(std::string_view text, std::size_t max_bytes, bool multiline) {
  std::string out;
  std::size_t i = 0;
  const std::size_t end = text.size() < max_bytes ? text.size() : max_bytes;
  while (i < end) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = c >= 0x80 ? utf8_sequence_length(text.substr(i)) : 1;
    if (c >= 0x80 && n > 0 && i + n <= end) {
      out.append(text.substr(i, n));
      i += n;
      continue;
    }
    if (multiline && (c == '\n' || c == '\t')) {
      out += char(c);
    } else if (c < 0x20 || c == 0x7F || c >= 0x80) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", unsigned(c));
      out += buf;
    } else {
      out += char(c);
    }
    ++i;
  }
  if (end < text.size()) out += "...";
  return out;
}

}  // namespace softcut
