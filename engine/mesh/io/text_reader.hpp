#pragma once
// Whitespace tokenizer over a whole file held in memory, shared by the mesh
// readers. It keeps line numbers so every error can say `file:line: what`.
// Two ways to read that can be mixed: line mode (next_line: one line's tokens
// at a time, for formats whose lines have a fixed shape) and token mode
// (token: the next token wherever it is, for free-form formats). Raw bytes can
// be taken after a fully read line (binary blocks of legacy VTK).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace softcut::mesh::io {

// ASCII lower case (keywords of case-insensitive formats).
std::string lower(std::string_view s);

// Parses a whole string as a number; false if it is not one.
bool parse_int(std::string_view s, std::int64_t& v);
bool parse_double(std::string_view s, double& v);

class TextReader {
 public:
  // `first_line` numbers the first line of `text` (for text cut from a larger file).
  TextReader(std::string source, std::string_view text, int first_line = 1);

  // Characters from `c` to the end of a line are ignored ('\0': none).
  void set_comment(char c) { comment_ = c; }

  // Line mode: moves to the next line holding a token (blank lines skipped);
  // false at the end of the text. Its tokens count as consumed for token mode.
  bool next_line();
  // Like next_line but also stops at blank lines (free-text header lines).
  bool next_raw_line();
  const std::vector<std::string_view>& tokens() const { return tokens_; }
  std::string_view line_text() const { return line_text_; }

  // Token mode: the next unconsumed token, moving on to later lines as needed.
  // token() fails at the end of the text, saying it expected `what`.
  bool next_token(std::string_view& tok);
  std::string_view token(std::string_view what);
  // Puts the last token back (one level).
  void unget_token();

  // Raw mode: `n` bytes starting right after the current line (which must be
  // fully consumed); fails if the file holds fewer. Line counting continues
  // after them.
  std::string_view take_bytes(std::size_t n, std::string_view what);
  // (pos_ stands one past the end after a last line without a newline.)
  std::size_t bytes_left() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

  int line() const { return line_; }
  const std::string& source() const { return source_; }

  // `source:line: ` followed by the arguments.
  template <class... Args>
  [[noreturn]] void fail_here(const Args&... args) const {
    fail(source_, ":", line_, ": ", args...);
  }

  // Whole-token conversions; failures name the token and `what` it should be.
  std::int64_t to_int(std::string_view tok, std::string_view what) const;
  int to_index(std::string_view tok, std::string_view what) const;  // fits int, >= 0
  double to_double(std::string_view tok, std::string_view what) const;
  double to_coord(std::string_view tok, std::string_view what) const;  // finite
  // Same, for hot loops: `what()` builds the item description only on failure.
  template <class What>
  std::int64_t to_int_lazy(std::string_view tok, const What& what) const {
    std::int64_t v;
    return parse_int(tok, v) ? v : to_int(tok, what());
  }
  template <class What>
  double to_double_lazy(std::string_view tok, const What& what) const {
    double v;
    return parse_double(tok, v) ? v : to_double(tok, what());
  }
  template <class What>
  double to_coord_lazy(std::string_view tok, const What& what) const {
    double v;
    return parse_double(tok, v) && v - v == 0 ? v : to_coord(tok, what());
  }
  // token() with a lazily built description.
  template <class What>
  std::string_view token_lazy(const What& what) {
    std::string_view tok;
    if (!next_token(tok)) token(what());
    return tok;
  }
  // Token-mode shortcuts.
  std::int64_t int_token(std::string_view what) { return to_int(token(what), what); }
  double double_token(std::string_view what) { return to_double(token(what), what); }

 private:
  bool read_line();

  std::string source_;
  std::string_view text_;
  std::size_t pos_ = 0;  // start of the next unread line
  int line_ = 0;
  char comment_ = '\0';
  std::string_view line_text_;
  std::vector<std::string_view> tokens_;
  std::size_t next_tok_ = 0;  // token mode cursor into tokens_
};

// Upper bound on how many items of at least `min_bytes` bytes each fit in
// `bytes` bytes; used to cap reservations announced by untrusted headers.
inline std::size_t reserve_cap(std::int64_t announced, std::size_t bytes, std::size_t min_bytes) {
  const std::size_t fit = bytes / (min_bytes ? min_bytes : 1) + 1;
  return announced < 0 ? 0 : std::min<std::size_t>(std::size_t(announced), fit);
}

}  // namespace softcut::mesh::io
