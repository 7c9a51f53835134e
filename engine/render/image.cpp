#include "render/image.hpp"

#include <stb_image.h>
#include <zlib.h>

#include "core/error.hpp"

// stb_image_write is compiled here, private to this file (STB_IMAGE_WRITE_STATIC,
// so it cannot clash with libstb's copy), to give it zlib as its compressor:
// on a 640x480 frame stb's own deflate with its per-row filter search costs
// 50-90 ms, zlib level 3 without row filters about 9 ms and makes smaller
// files (rendered frames are mostly flat colour). Measured in docs/rendering.md.
namespace {
unsigned char* zlib_compress(unsigned char* data, int len, int* out_len, int /*stb quality*/) {
  uLongf n = compressBound(uLong(len));
  auto* out = static_cast<unsigned char*>(std::malloc(n));  // stb frees it with free()
  if (!out || compress2(out, &n, data, uLong(len), 3) != Z_OK) {
    std::free(out);
    return nullptr;
  }
  *out_len = int(n);
  return out;
}
}  // namespace
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBIW_ZLIB_COMPRESS zlib_compress
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace {
// No PNG row filter (see above); set once at start-up, private to this file.
[[maybe_unused]] const bool no_png_filter = (stbi_write_force_png_filter = 0, true);
}  // namespace

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/atomic_file.hpp"

namespace softcut::render {

Image::Image(int w, int h, std::uint32_t fill) : width(w), height(h), rgba(size_t(w) * size_t(h) * 4) {
  const std::uint8_t c[4] = {std::uint8_t(fill >> 24), std::uint8_t(fill >> 16), std::uint8_t(fill >> 8),
                             std::uint8_t(fill)};
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = c[i % 4];
}

std::string encode_png(const Image& image) {
  if (image.width < 1 || image.height < 1 || image.rgba.size() != size_t(image.width) * size_t(image.height) * 4)
    fail("encode_png: image of ", image.width, " x ", image.height, " with ", image.rgba.size(),
         " bytes is inconsistent (need width * height * 4 > 0)");
  std::string out;
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), size_t(size));
  };
  // Opaque images (every rendered frame) go out as RGB: a quarter less to
  // deflate (about 20% faster) and smaller files; decoding gives alpha 255 back.
  const size_t npx = size_t(image.width) * size_t(image.height);
  bool opaque = true;
  for (size_t i = 0; i < npx && opaque; ++i) opaque = image.rgba[4 * i + 3] == 255;
  std::vector<std::uint8_t> rgb;
  if (opaque) {
    rgb.resize(3 * npx);
    for (size_t i = 0; i < npx; ++i)
      for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = image.rgba[4 * i + size_t(c)];
  }
  const int channels = opaque ? 3 : 4;
  if (!stbi_write_png_to_func(sink, &out, image.width, image.height, channels, opaque ? rgb.data() : image.rgba.data(),
                              image.width * channels))
    fail("encode_png: stb_image_write failed for a ", image.width, " x ", image.height, " image");
  return out;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  write_file_atomic(path, encode_png(image));
}

Image decode_png(std::string_view bytes, const std::string& what) {
  int w = 0, h = 0, n = 0;
  stbi_uc* px = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h,
                                      &n, 4);
  if (!px) fail(what, ": not a readable image (", stbi_failure_reason(), ")");
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.assign(px, px + size_t(w) * size_t(h) * 4);
  stbi_image_free(px);
  return img;
}

Image read_png(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string(), ": cannot open the image (does it exist?)");
  std::stringstream ss;
  ss << in.rdbuf();
  return decode_png(ss.str(), path.string());
}

ImageDiff compare_images(const Image& a, const Image& b, int tolerance) {
  ImageDiff d;
  if (a.width != b.width || a.height != b.height || a.rgba.size() != b.rgba.size()) return d;
  d.same_size = true;
  d.differing = 0;
  d.diff = Image(b.width, b.height);
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      const std::uint8_t *p = a.at(x, y), *q = b.at(x, y);
      int worst = 0;
      for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(p[c]) - int(q[c])));
      d.max_channel_diff = std::max(d.max_channel_diff, worst);
      std::uint8_t* o = d.diff.at(x, y);
      if (worst > tolerance) {
        ++d.differing;
        o[0] = 255, o[1] = 0, o[2] = 0;
      } else {
        const std::uint8_t grey = std::uint8_t((int(q[0]) + int(q[1]) + int(q[2])) / 6);
        o[0] = o[1] = o[2] = grey;
      }
      o[3] = 255;
    }
  d.fraction = double(d.differing) / double(std::max<long>(1, long(b.width) * b.height));
  return d;
}

}  // namespace softcut::render
