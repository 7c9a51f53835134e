#pragma once
// A contact sheet: frames shrunk into a grid with optional labels (frame
// numbers), one PNG for a quick look at a whole run.
#include <filesystem>
#include <string>
#include <vector>

#include "render/image.hpp"

namespace softcut::render {

struct ContactSheetOptions {
  int columns = 0;          // 0: about square (ceil(sqrt(n)))
  int tile_width = 240;     // pixels; tile height keeps the first frame's aspect ratio
  int gap = 4;              // pixels between tiles and around the sheet
  std::uint32_t background = 0x101010ffu;  // 0xRRGGBBAA
  bool labels = true;       // draw each label in the tile's top-left corner
};

// Frames may differ in size (each is scaled into its tile, aspect kept).
// `labels` is empty or one per frame. Throws softcut::Error for no frames or
// bad options.
Image contact_sheet(const std::vector<Image>& frames, const std::vector<std::string>& labels,
                    const ContactSheetOptions& options = {});

// Reads the PNGs and labels each with the number in its name
// ("frame_000123.png" -> "123"; the file stem when there is none).
Image contact_sheet(const std::vector<std::filesystem::path>& pngs, const ContactSheetOptions& options = {});

// Every PNG in `frames_dir` whose name starts with "frame_", in name order,
// taking every `stride`-th one; written atomically to `out`.
void write_contact_sheet(const std::filesystem::path& frames_dir, const std::filesystem::path& out, int stride = 1,
                         const ContactSheetOptions& options = {});

}  // namespace softcut::render
