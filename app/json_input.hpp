#pragma once
// JSON files softcut reads back (a sweep's plan, its runs' summaries) come
// from folders someone else may have prepared: the text is first walked by
// nlohmann's SAX reader, which keeps nothing, to bound the number of values
// and the nesting; only then is the document built. Memory is then bounded
// by those counts, not by what the text claims.
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace softcut::app {

// The regular file `rel` below `root` (opened without following a link, see
// core/checked_file.hpp), refused past `max_bytes` with a message naming
// `what` and the size.
std::string read_file_below(const std::filesystem::path& root, const std::filesystem::path& rel,
                            const std::string& what, std::size_t max_bytes);

// Parses `text` (from `file`, for messages). Throws softcut::Error naming
// the file for malformed JSON, more than `max_values` values or nesting
// deeper than `max_depth`.
nlohmann::json parse_bounded_json(std::string_view text, const std::string& file, std::size_t max_values,
                                  std::size_t max_depth);

// "a.b[3].c" for messages about a field.
std::string field_path(const std::string& parent, const std::string& key);
std::string field_path(const std::string& parent, std::size_t index);

}  // namespace softcut::app
