#include "app/json_input.hpp"

#include <sys/stat.h>

#include "core/checked_file.hpp"
#include "core/error.hpp"

namespace softcut::app {

namespace {

// Counts values and depth; stops (returns false) past either bound.
struct Counter : nlohmann::json_sax<nlohmann::json> {
  std::size_t max_values, max_depth;
  std::size_t values = 0, depth = 0;
  std::string error;  // set: why it stopped

  Counter(std::size_t v, std::size_t d) : max_values(v), max_depth(d) {}
  bool value() {
    if (++values <= max_values) return true;
    error = cat("more than ", max_values, " values");
    return false;
  }
  bool open() {
    if (++depth <= max_depth) return value();
    error = cat("nested deeper than ", max_depth, " levels");
    return false;
  }
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(); }
  bool key(string_t&) override { return true; }
  bool end_object() override { return --depth, true; }
  bool start_array(std::size_t) override { return open(); }
  bool end_array() override { return --depth, true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    error = e.what();
    return false;
  }
};

}  // namespace

std::string read_file_below(const std::filesystem::path& root, const std::filesystem::path& rel,
                            const std::string& what, std::size_t max_bytes) {
  const UniqueFd fd = open_below(root, rel, Access::read, what);
  struct stat st {};
  if (::fstat(fd.get(), &st) == 0 && std::uint64_t(st.st_size) > max_bytes)
    fail((root / rel).string(), ": ", what, " holds ", std::uint64_t(st.st_size), " bytes, more than the ", max_bytes,
         " softcut reads (not a file softcut wrote)");
  return read_whole(fd, what, (root / rel).string(), max_bytes);
}

nlohmann::json parse_bounded_json(std::string_view text, const std::string& file, std::size_t max_values,
                                  std::size_t max_depth) {
  Counter count(max_values, max_depth);
  if (!nlohmann::json::sax_parse(text, &count) || !count.error.empty())
    fail(file, ": not valid JSON of a size softcut writes (", count.error.empty() ? "malformed" : count.error, ")");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    fail(file, ": not valid JSON (", e.what(), ")");
  }
}

std::string field_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string field_path(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

}  // namespace softcut::app
