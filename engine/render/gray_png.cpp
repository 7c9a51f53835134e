#include "render/gray_png.hpp"

#include <png.h>
#include <stb_image.h>

#include <csetjmp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/error.hpp"
#include "render/renderer.hpp"

namespace softcut::render {

namespace {

struct Sink {
  std::string bytes;
};

extern "C" void png_sink_write(png_structp png, png_bytep data, png_size_t size) {
  static_cast<Sink*>(png_get_io_ptr(png))->bytes.append(reinterpret_cast<const char*>(data), size);
}
extern "C" void png_sink_flush(png_structp) {}

// Rows are big-endian in the file: libpng swaps 16-bit samples with
// png_set_swap. Runs in a frame of its own: libpng reports errors by
// longjmp, which must not cross a frame holding C++ objects.
bool write_gray(Sink& sink, const void* pixels, int width, int height, int depth, char* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    std::strncpy(error, "libpng failed while encoding", 63);
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_set_write_fn(png, &sink, png_sink_write, png_sink_flush);
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), depth, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  png_write_info(png, info);
  if (depth == 16) png_set_swap(png);
  const std::size_t row = std::size_t(width) * std::size_t(depth / 8);
  for (int y = 0; y < height; ++y)
    png_write_row(png, static_cast<png_const_bytep>(pixels) + std::size_t(y) * row);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

template <class Image>
std::string encode(const Image& image, int depth) {
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
    fail("PNG: a ", image.width, " x ", image.height, " image with ", image.pixels.size(), " pixels");
  Sink sink;
  char error[64] = {};
  if (!write_gray(sink, image.pixels.data(), image.width, image.height, depth, error))
    fail("PNG: ", error[0] ? error : "libpng could not start");
  return std::move(sink.bytes);
}

}  // namespace

GrayImage16 depth_image(const LabelImages& aux) {
  GrayImage16 img;
  img.width = aux.width, img.height = aux.height;
  img.pixels.resize(aux.depth.size());
  for (std::size_t i = 0; i < aux.depth.size(); ++i) {
    const double units = double(aux.depth[i]) * 1000.0 * kDepthUnitsPerMm;
    img.pixels[i] = !(units > 0) ? 0 : units >= 65534.5 ? 65535 : std::uint16_t(std::lround(units));
  }
  return img;
}

GrayImage8 label_image(const LabelImages& aux) {
  GrayImage8 img;
  img.width = aux.width, img.height = aux.height;
  img.pixels = aux.labels;
  return img;
}

std::string encode_png(const GrayImage16& image) { return encode(image, 16); }
std::string encode_png(const GrayImage8& image) { return encode(image, 8); }

GrayImage16 decode_gray_png(std::string_view bytes, const std::string& what) {
  // stb_image: a decoder independent of the encoder above.
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int len = int(std::min<std::size_t>(bytes.size(), std::size_t(INT32_MAX)));
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(data, len, &w, &h, &comp) || comp != 1)
    fail(what, ": not a single-channel PNG");
  GrayImage16 out;
  out.width = w, out.height = h;
  out.pixels.resize(std::size_t(w) * std::size_t(h));
  if (stbi_is_16_bit_from_memory(data, len)) {
    stbi_us* p = stbi_load_16_from_memory(data, len, &w, &h, &comp, 1);
    if (!p) fail(what, ": ", stbi_failure_reason());
    std::memcpy(out.pixels.data(), p, out.pixels.size() * 2);
    stbi_image_free(p);
  } else {
    stbi_uc* p = stbi_load_from_memory(data, len, &w, &h, &comp, 1);
    if (!p) fail(what, ": ", stbi_failure_reason());
    for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = p[i];
    stbi_image_free(p);
  }
  return out;
}

}  // namespace softcut::render
