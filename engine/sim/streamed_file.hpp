#pragma once
// A log a run writes while it goes on (displacements.csv, tools.csv): rows
// are appended to <name>.partial, made new (never opened through a link),
// and renamed to <name> by finish(), also after Ctrl-C, a script's stop or an
// error; a file that exists is therefore complete. Without finish() (the
// process is dying) the partial file is removed.
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace softcut {
class OutputBudget;
}

namespace softcut::sim {

class StreamedFile {
 public:
  // Creates <dir>/<name>.partial and writes `header`. `budget` (optional,
  // outlives the file) is charged for every byte.
  StreamedFile(const std::filesystem::path& dir, std::string name, std::string_view header,
               OutputBudget* budget = nullptr);
  ~StreamedFile();
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;

  void write(std::string_view text);  // throws naming the file when the disk is full
  // Flushes and renames the file into place (once; later calls do nothing).
  void finish();
  const std::string& name() const { return name_; }

 private:
  std::filesystem::path dir_, tmp_;
  std::string name_;
  std::FILE* file_ = nullptr;
  OutputBudget* budget_ = nullptr;
};

}  // namespace softcut::sim
