#pragma once
// 8-bit RGBA images: what the renderer reads back, PNG encoding (stb_image_write)
// and decoding (stb_image), atomic PNG files, and pixel comparison for tests
// and golden images.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace softcut::render {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // (height x width x 4) rows top to bottom, 8 bits per channel

  Image() = default;
  Image(int w, int h, std::uint32_t fill_rgba = 0x000000ffu);  // fill as 0xRRGGBBAA
  std::uint8_t* at(int x, int y) { return rgba.data() + 4 * (size_t(y) * size_t(width) + size_t(x)); }
  const std::uint8_t* at(int x, int y) const { return rgba.data() + 4 * (size_t(y) * size_t(width) + size_t(x)); }
};

// PNG bytes (zlib level 6; frames of a few hundred kB at 640x480).
std::string encode_png(const Image& image);
// Encodes and writes with write_file_atomic: readers never see a partial file.
void write_png(const std::filesystem::path& path, const Image& image);
// Decodes PNG bytes to RGBA; throws softcut::Error naming `what` if they are not a PNG.
Image decode_png(std::string_view bytes, const std::string& what);
Image read_png(const std::filesystem::path& path);

struct ImageDiff {
  bool same_size = false;
  long differing = 0;        // pixels with some channel off by more than the tolerance
  double fraction = 1.0;     // differing / pixels
  int max_channel_diff = 0;  // largest |a - b| over all channels, 0..255
  Image diff;                // the reference dimmed to grey, differing pixels red
};

// Per-pixel comparison with a per-channel tolerance (0..255). Images of
// different sizes compare as entirely different (same_size false, empty diff).
ImageDiff compare_images(const Image& actual, const Image& reference, int tolerance);

}  // namespace softcut::render
