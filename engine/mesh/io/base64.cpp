#include "mesh/io/base64.hpp"

#include <array>

namespace softcut::mesh::io {

namespace {
constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

constexpr std::array<signed char, 256> make_table() {
  std::array<signed char, 256> t{};
  for (auto& v : t) v = -1;
  for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kAlphabet[i])] = static_cast<signed char>(i);
  return t;
}
constexpr auto kTable = make_table();
}  // namespace

std::string base64_encode(std::string_view bytes) {
  std::string out((bytes.size() + 2) / 3 * 4, '=');
  std::size_t i = 0, o = 0;
  auto at = [&](std::size_t k) { return static_cast<unsigned char>(bytes[k]); };
  for (; i + 3 <= bytes.size(); i += 3) {
    const unsigned v = at(i) << 16 | at(i + 1) << 8 | at(i + 2);
    out[o++] = kAlphabet[(v >> 18) & 63];
    out[o++] = kAlphabet[(v >> 12) & 63];
    out[o++] = kAlphabet[(v >> 6) & 63];
    out[o++] = kAlphabet[v & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    const unsigned v = at(i) << 16 | (rest == 2 ? at(i + 1) << 8 : 0u);
    out[o++] = kAlphabet[(v >> 18) & 63];
    out[o++] = kAlphabet[(v >> 12) & 63];
    if (rest == 2) out[o] = kAlphabet[(v >> 6) & 63];
  }
  return out;
}

std::optional<std::string> base64_decode(std::string_view text, std::size_t* bad_at) {
  std::string out(text.size() / 4 * 3 + 3, '\0');
  std::size_t o = 0;
  int group[4];
  int n = 0, pad = 0;
  std::size_t group_start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    if (n == 0) group_start = i;
    if (c == '=') {
      // Padding may only end a group of 4, after at least two data characters.
      if (n < 2) {
        if (bad_at) *bad_at = i;
        return std::nullopt;
      }
      group[n++] = 0;
      ++pad;
    } else {
      const int v = kTable[static_cast<unsigned char>(c)];
      if (v < 0 || pad > 0) {
        if (bad_at) *bad_at = i;
        return std::nullopt;
      }
      group[n++] = v;
    }
    if (n == 4) {
      const unsigned v = unsigned(group[0]) << 18 | unsigned(group[1]) << 12 | unsigned(group[2]) << 6 | unsigned(group[3]);
      out[o++] = char((v >> 16) & 255);
      if (pad < 2) out[o++] = char((v >> 8) & 255);
      if (pad < 1) out[o++] = char(v & 255);
      n = 0;
      pad = 0;
    }
  }
  if (n != 0) {
    if (bad_at) *bad_at = group_start;
    return std::nullopt;
  }
  out.resize(o);
  return out;
}

}  // namespace softcut::mesh::io
