#include "test_support.hpp"

#include <unistd.h>

#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace softcut::test {

nlohmann::ordered_json parse_json(const std::string& text) {
  std::vector<std::set<std::string>> keys;  // of each object being read, innermost last
  const nlohmann::ordered_json::parser_callback_t strict = [&](int, nlohmann::ordered_json::parse_event_t event, nlohmann::ordered_json& v) {
    using E = nlohmann::ordered_json::parse_event_t;
    if (event == E::object_start) keys.emplace_back();
    if (event == E::object_end && !keys.empty()) keys.pop_back();
    if (event == E::key && !keys.empty() && !keys.back().insert(v.get<std::string>()).second)
      throw std::runtime_error("duplicate key \"" + v.get<std::string>() + "\" in one object");
    return true;
  };
  try {
    return nlohmann::ordered_json::parse(text, strict);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(e.what());
  }
}

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::ordered_json read_json(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw std::runtime_error("cannot read " + file.string());
  return parse_json(slurp(file));
}

std::filesystem::path data_dir() { return SOFTCUT_TEST_DATA; }

std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("softcut-test-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace softcut::test
