#include "sim/output_folder.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

namespace softcut::sim {

namespace fs = std::filesystem;

namespace {

// True for the names softcut gives its own files in an output folder: the
// fixed ones in `fixed`, `<prefix>NNNNNN<ext>` (6 or more digits), and the
// temporary files write_file_atomic() makes for either (".<name>.<pid>.<n>.tmp").
bool softcut_output_name(std::string name, std::initializer_list<std::string_view> fixed, std::string_view prefix,
                         std::string_view ext) {
  if (name.size() > 5 && name[0] == '.' && name.ends_with(".tmp")) {
    name = name.substr(1, name.size() - 5);  // "<name>.<pid>.<n>"
    for (int k = 0; k < 2; ++k) {
      const size_t dot = name.find_last_of('.');
      if (dot == std::string::npos || dot + 1 == name.size() ||
          name.find_first_not_of("0123456789", dot + 1) != std::string::npos)
        return false;
      name.resize(dot);
    }
  }
  for (std::string_view f : fixed)
    if (name == f) return true;
  if (prefix.empty() || !name.starts_with(prefix) || !name.ends_with(ext)) return false;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - ext.size());
  return digits.size() >= 6 && digits.find_first_not_of("0123456789") == std::string::npos;
}

// Unlinks (never follows) the entries of `dir` that softcut names; a
// subfolder that is a link or not a folder is left alone (the recorder
// refuses it later). Returns how many were removed.
int remove_softcut_files(const fs::path& dir, std::initializer_list<std::string_view> fixed, std::string_view prefix,
                         std::string_view ext) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return 0;
  int removed = 0;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::file_status st = it->symlink_status(ec);
    if (ec || fs::is_directory(st)) continue;
    if (softcut_output_name(it->path().filename().string(), fixed, prefix, ext) && fs::remove(it->path(), ec))
      ++removed;
  }
  return removed;
}

}  // namespace

int clear_earlier_outputs(const fs::path& dir) {
  int n = remove_softcut_files(dir, {"displacements.csv", "displacements.csv.partial", "tools.csv", "tools.csv.partial",
                                     "validity.csv", "validity.csv.partial", "summary.json", "series.pvd", "contact_sheet.png", "camera.json", "video.mp4",
                                     "render_record.bin", "render_record.bin.partial"},
                               {}, {});
  for (const auto& [sub, prefix, ext] : {std::tuple{"frames", "frame_", ".png"}, std::tuple{"frames", "depth_", ".png"},
                                         std::tuple{"frames", "labels_", ".png"}, std::tuple{"vtu", "frame_", ".vtu"}}) {
    n += remove_softcut_files(dir / sub, {}, prefix, ext);
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(dir / sub, ec))) fs::remove(dir / sub, ec);  // only when now empty
  }
  return n;
}

int remove_stale_video_folders(const fs::path& dir) {
  constexpr std::string_view prefix = ".softcut-video-";
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return 0;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() != prefix.size() + 6 || !name.starts_with(prefix) ||
        !std::all_of(name.begin() + long(prefix.size()), name.end(), [](char c) { return std::isalnum((unsigned char)c); }))
      continue;
    if (!fs::is_directory(it->symlink_status(ec))) continue;
    bool only_video = true;
    for (fs::directory_iterator in(it->path(), ec), stop; !ec && in != stop && only_video; in.increment(ec))
      only_video = in->path().filename() == "video.mp4" && fs::is_regular_file(in->symlink_status(ec));
    if (!ec && only_video) stale.push_back(it->path());
  }
  int removed = 0;
  for (const fs::path& folder : stale) {
    fs::remove(folder / "video.mp4", ec);
    removed += fs::remove(folder, ec) ? 1 : 0;
  }
  return removed;
}

}  // namespace softcut::sim
