#include "mesh/io/text_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>

namespace softcut::mesh::io {

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string shown(std::string_view tok) {
  return tok.size() > 40 ? std::string(tok.substr(0, 40)) + "..." : std::string(tok);
}
}  // namespace

TextReader::TextReader(std::string source, std::string_view text, int first_line)
    : source_(std::move(source)), text_(text), line_(first_line - 1) {}

bool TextReader::read_line() {
  tokens_.clear();
  next_tok_ = 0;
  if (pos_ >= text_.size()) {
    return false;
  }
  std::size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  line_text_ = text_.substr(pos_, end - pos_);
  pos_ = end + 1;
  ++line_;
  std::size_t i = 0;
  const std::size_t n = line_text_.size();
  while (i < n) {
    while (i < n && is_space(line_text_[i])) ++i;
    if (i >= n || (comment_ && line_text_[i] == comment_)) break;
    std::size_t j = i;
    while (j < n && !is_space(line_text_[j]) && !(comment_ && line_text_[j] == comment_)) ++j;
    tokens_.push_back(line_text_.substr(i, j - i));
    i = j;
  }
  return true;
}

bool TextReader::next_line() {
  while (read_line())
    if (!tokens_.empty()) {
      next_tok_ = tokens_.size();
      return true;
    }
  return false;
}

bool TextReader::next_raw_line() {
  if (!read_line()) return false;
  next_tok_ = tokens_.size();
  return true;
}

bool TextReader::next_token(std::string_view& tok) {
  while (next_tok_ >= tokens_.size())
    if (!read_line()) return false;
  tok = tokens_[next_tok_++];
  return true;
}

std::string_view TextReader::token(std::string_view what) {
  std::string_view tok;
  if (!next_token(tok)) fail_here("unexpected end of file, expected ", what);
  return tok;
}

void TextReader::unget_token() {
  if (next_tok_ > 0) --next_tok_;
}

std::string_view TextReader::take_bytes(std::size_t n, std::string_view what) {
  if (next_tok_ < tokens_.size()) fail_here("unexpected '", shown(tokens_[next_tok_]), "' before ", what);
  if (pos_ > text_.size() || text_.size() - pos_ < n)
    fail_here("file ends inside ", what, " (needs ", n, " bytes, ", pos_ > text_.size() ? 0 : text_.size() - pos_,
              " left)");
  std::string_view out = text_.substr(pos_, n);
  for (char c : out) line_ += c == '\n';
  pos_ += n;
  return out;
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

bool parse_int(std::string_view s, std::int64_t& v) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

bool parse_double(std::string_view s, double& v) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty() || s[0] == '+') return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

std::int64_t TextReader::to_int(std::string_view tok, std::string_view what) const {
  std::int64_t v;
  if (!parse_int(tok, v)) fail_here("expected an integer for ", what, ", found '", shown(tok), "'");
  return v;
}

int TextReader::to_index(std::string_view tok, std::string_view what) const {
  const std::int64_t v = to_int(tok, what);
  if (v < 0 || v > INT_MAX) fail_here(what, " must lie in 0..", INT_MAX, ", found ", v);
  return int(v);
}

double TextReader::to_double(std::string_view tok, std::string_view what) const {
  double v;
  if (!parse_double(tok, v)) fail_here("expected a number for ", what, ", found '", shown(tok), "'");
  return v;
}

double TextReader::to_coord(std::string_view tok, std::string_view what) const {
  const double v = to_double(tok, what);
  if (!std::isfinite(v)) fail_here(what, " is not finite (", shown(tok), "); fix or remove that node");
  return v;
}

}  // namespace softcut::mesh::io
