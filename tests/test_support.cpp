#include "test_support.hpp"

#include <unistd.h>

#include <cstdlib>
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

ForeignArrays read_vtu_with_meshio(const std::filesystem::path& vtu) {
  // Debian's interpreter, where python3-meshio installs (a python3 earlier
  // on PATH, e.g. pyenv's, would not see it).
  const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const auto out = scratch_dir("meshio") / (vtu.stem().string() + ".txt");
  const std::string cmd = python + " '" + (data_dir() / "read_vtu_meshio.py").string() + "' '" + vtu.string() +
                          "' > '" + out.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  const std::string text = slurp(out);
  if (rc != 0) {
    if (text.find("No module named 'meshio'") != std::string::npos)
      throw std::runtime_error("python3-meshio is not installed: run scripts/install-deps.sh --test "
                               "(or apt-get install python3-meshio)");
    throw std::runtime_error("meshio could not read " + vtu.string() + ": " + text);
  }
  ForeignArrays r;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string name, kind;
    words >> name;
    if (name == "cell_blocks") {
      std::string t;
      words >> r.cell_blocks >> t >> r.tetra_blocks;
      continue;
    }
    std::size_t n = 0;
    words >> kind >> n;
    std::vector<double>& v = r.arrays[name];
    for (std::size_t i = 0; i < n; ++i) {
      std::string w;
      words >> w;
      v.push_back(kind == "f" ? std::strtod(w.c_str(), nullptr) : double(std::stoll(w)));  // strtod reads C99 hex floats
    }
    if (v.size() != n) throw std::runtime_error("meshio dump: array " + name + " cut short");
  }
  return r;
}

std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("softcut-test-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace softcut::test
