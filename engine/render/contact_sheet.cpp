#include "render/contact_sheet.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include "core/error.hpp"

namespace softcut::render {
namespace {

// Area-averaging resample of `src` into the w x h rectangle at (x0, y0) of `dst`.
void blit_scaled(const Image& src, Image& dst, int x0, int y0, int w, int h) {
  const double sx = double(src.width) / w, sy = double(src.height) / h;
  for (int y = 0; y < h; ++y) {
    const int ya = int(y * sy), yb = std::max(ya + 1, int(std::ceil((y + 1) * sy)));
    for (int x = 0; x < w; ++x) {
      const int xa = int(x * sx), xb = std::max(xa + 1, int(std::ceil((x + 1) * sx)));
      int sum[4] = {0, 0, 0, 0}, n = 0;
      for (int v = ya; v < std::min(yb, src.height); ++v)
        for (int u = xa; u < std::min(xb, src.width); ++u, ++n)
          for (int c = 0; c < 4; ++c) sum[c] += src.at(u, v)[c];
      std::uint8_t* o = dst.at(x0 + x, y0 + y);
      for (int c = 0; c < 4; ++c) o[c] = std::uint8_t(n ? sum[c] / n : 0);
    }
  }
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const std::uint8_t (&c)[4]) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, img.width), y1 = std::min(y1, img.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) std::copy(c, c + 4, img.at(x, y));
}

// stb_easy_font emits axis-aligned quads; drawn at 2x over a dark backing box.
void draw_label(Image& img, int x0, int y0, const std::string& text, int clip_w) {
  constexpr int kScale = 2;
  const int tw = stb_easy_font_width(const_cast<char*>(text.c_str())) * kScale + 6;
  const int th = stb_easy_font_height(const_cast<char*>(text.c_str())) * kScale + 4;
  fill_rect(img, x0, y0, x0 + std::min(tw, clip_w), y0 + th, {0, 0, 0, 255});
  static thread_local std::vector<char> buf(64 * 1024);
  const int quads = stb_easy_font_print(0, 0, const_cast<char*>(text.c_str()), nullptr, buf.data(), int(buf.size()));
  const float* v = reinterpret_cast<const float*>(buf.data());  // 4 vertices per quad, 16 bytes each
  for (int q = 0; q < quads; ++q) {
    const float* a = v + q * 16;  // vertex 0 (x, y) ...
    const float* c = a + 8;       // vertex 2, the opposite corner
    const int qx0 = x0 + 3 + int(a[0]) * kScale, qy0 = y0 + 2 + int(a[1]) * kScale;
    const int qx1 = x0 + 3 + int(c[0]) * kScale, qy1 = y0 + 2 + int(c[1]) * kScale;
    fill_rect(img, qx0, qy0, std::min(qx1, x0 + clip_w), qy1, {255, 255, 255, 255});
  }
}

std::string label_of(const std::filesystem::path& p) {
  const std::string stem = p.stem().string();
  const size_t last = stem.find_last_of("0123456789");
  if (last == std::string::npos) return stem;
  size_t first = last;
  while (first > 0 && std::isdigit(static_cast<unsigned char>(stem[first - 1]))) --first;
  const size_t nz = stem.find_first_not_of('0', first);
  return nz != std::string::npos && nz <= last ? stem.substr(nz, last + 1 - nz) : "0";
}

}  // namespace

Image contact_sheet(const std::vector<Image>& frames, const std::vector<std::string>& labels,
                    const ContactSheetOptions& opt) {
  if (frames.empty()) fail("contact sheet: no frames given");
  if (!labels.empty() && labels.size() != frames.size())
    fail("contact sheet: ", labels.size(), " labels for ", frames.size(), " frames (give one per frame or none)");
  if (opt.tile_width < 8 || opt.gap < 0 || opt.columns < 0)
    fail("contact sheet: tile_width must be >= 8 and gap, columns >= 0");
  for (size_t i = 0; i < frames.size(); ++i)
    if (frames[i].width < 1 || frames[i].height < 1) fail("contact sheet: frame ", i, " is empty");
  const int n = int(frames.size());
  const int cols = opt.columns ? std::min(opt.columns, n) : int(std::ceil(std::sqrt(double(n))));
  const int rows = (n + cols - 1) / cols;
  const int tw = opt.tile_width;
  const int th = std::max(1, int(std::lround(double(tw) * frames[0].height / frames[0].width)));
  Image sheet(opt.gap + cols * (tw + opt.gap), opt.gap + rows * (th + opt.gap), opt.background);
  for (int i = 0; i < n; ++i) {
    const Image& f = frames[size_t(i)];
    const int x0 = opt.gap + (i % cols) * (tw + opt.gap), y0 = opt.gap + (i / cols) * (th + opt.gap);
    // Fit inside the tile, aspect kept, centred.
    const double s = std::min(double(tw) / f.width, double(th) / f.height);
    const int w = std::max(1, int(std::lround(f.width * s))), h = std::max(1, int(std::lround(f.height * s)));
    blit_scaled(f, sheet, x0 + (tw - w) / 2, y0 + (th - h) / 2, w, h);
    if (opt.labels && !labels.empty() && !labels[size_t(i)].empty()) draw_label(sheet, x0, y0, labels[size_t(i)], tw);
  }
  return sheet;
}

Image contact_sheet(const std::vector<std::filesystem::path>& pngs, const ContactSheetOptions& opt) {
  std::vector<Image> frames;
  std::vector<std::string> labels;
  for (const auto& p : pngs) {
    frames.push_back(read_png(p));
    labels.push_back(label_of(p));
  }
  return contact_sheet(frames, labels, opt);
}

void write_contact_sheet(const std::filesystem::path& frames_dir, const std::filesystem::path& out, int stride,
                         const ContactSheetOptions& opt) {
  if (stride < 1) fail("contact sheet: stride = ", stride, " must be >= 1");
  std::error_code ec;
  if (!std::filesystem::is_directory(frames_dir, ec))
    fail(frames_dir.string(), ": no such folder of frames");
  std::vector<std::filesystem::path> all;
  for (const auto& e : std::filesystem::directory_iterator(frames_dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.rfind("frame_", 0) == 0 && e.path().extension() == ".png")
      all.push_back(e.path());
  }
  std::sort(all.begin(), all.end());
  std::vector<std::filesystem::path> picked;
  for (size_t i = 0; i < all.size(); i += size_t(stride)) picked.push_back(all[i]);
  if (picked.empty()) fail(frames_dir.string(), ": no frame_*.png files to put on a contact sheet");
  write_png(out, contact_sheet(picked, opt));
}

}  // namespace softcut::render
