#include "test_support.hpp"

#include <unistd.h>

namespace softcut::test {

std::filesystem::path data_dir() { return SOFTCUT_TEST_DATA; }

std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("softcut-test-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace softcut::test
