#pragma once
// Single-channel PNG images: 16-bit depth maps and 8-bit label maps
// (libpng: stb_image_write writes 8 bits per channel only). Written without
// row filters at zlib level 1: these maps are mostly flat and each frame is
// encoded on the frame writer's thread.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace softcut::render {

// Values in a depth PNG per millimetre of distance along the view axis:
// 0.1 mm steps, up to 6553.5 mm (camera.json "depth_scale").
inline constexpr double kDepthUnitsPerMm = 10.0;

// (height x width) values, rows top to bottom.
struct GrayImage16 {
  int width = 0, height = 0;
  std::vector<std::uint16_t> pixels;
};
struct GrayImage8 {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

struct LabelImages;
// The depth image of `aux`: round(mm x kDepthUnitsPerMm), 0 for background,
// 65535 for anything farther (it cannot be written).
GrayImage16 depth_image(const LabelImages& aux);
GrayImage8 label_image(const LabelImages& aux);

// PNG bytes, colour type grey, bit depth 16 or 8. Throws softcut::Error on a
// size that does not match the pixels.
std::string encode_png(const GrayImage16& image);
std::string encode_png(const GrayImage8& image);
// Decodes a single-channel PNG (8 or 16 bits; 8-bit values come back as is);
// throws softcut::Error naming `what` for anything else.
GrayImage16 decode_gray_png(std::string_view bytes, const std::string& what);

}  // namespace softcut::render
