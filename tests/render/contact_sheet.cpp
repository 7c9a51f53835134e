#include "render/contact_sheet.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"
#include "test_support.hpp"

using namespace softcut;
using render::Image;

namespace {

bool is(const Image& img, int x, int y, std::uint32_t rgba) {
  const std::uint8_t* p = img.at(x, y);
  return p[0] == (rgba >> 24) && p[1] == ((rgba >> 16) & 255) && p[2] == ((rgba >> 8) & 255) && p[3] == (rgba & 255);
}

}  // namespace

TEST_SUITE("render/contact_sheet") {
  TEST_CASE("frames land in a grid scaled into their tiles") {
    const std::uint32_t colors[5] = {0xff0000ffu, 0x00ff00ffu, 0x0000ffffu, 0xffff00ffu, 0x00ffffffu};
    std::vector<Image> frames;
    for (auto c : colors) frames.emplace_back(80, 60, c);
    render::ContactSheetOptions o;
    o.tile_width = 40;
    o.gap = 2;
    o.labels = false;
    const Image sheet = render::contact_sheet(frames, {}, o);
    // 5 frames: 3 columns, 2 rows of 40 x 30 tiles.
    CHECK(sheet.width == 2 + 3 * 42);
    CHECK(sheet.height == 2 + 2 * 32);
    for (int i = 0; i < 5; ++i) {
      const int x0 = 2 + (i % 3) * 42, y0 = 2 + (i / 3) * 32;
      CHECK(is(sheet, x0, y0, colors[i]));
      CHECK(is(sheet, x0 + 39, y0 + 29, colors[i]));
      CHECK(is(sheet, x0 + 40, y0 + 30, o.background));
    }
    CHECK(is(sheet, 2 + 2 * 42 + 10, 2 + 32 + 10, o.background));  // the empty sixth tile
  }

  TEST_CASE("scaling averages so a fine checkerboard turns grey") {
    Image board(64, 64);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const std::uint8_t v = (x + y) % 2 ? 255 : 0;
        std::uint8_t* p = board.at(x, y);
        p[0] = p[1] = p[2] = v;
        p[3] = 255;
      }
    render::ContactSheetOptions o;
    o.tile_width = 16;
    o.gap = 0;
    const Image sheet = render::contact_sheet({board}, {}, o);
    REQUIRE(sheet.width == 16);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) CHECK(std::abs(int(sheet.at(x, y)[0]) - 127) <= 1);
  }

  TEST_CASE("labels show frame numbers and the sheet of a folder is written") {
    const auto dir = test::scratch_dir("contact_sheet");
    for (int f : {0, 5, 10, 15, 20}) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.png", f);
      render::write_png(dir / name, Image(64, 48, 0x202020ffu));
    }
    render::write_png(dir / "other.png", Image(8, 8, 0xff0000ffu));  // not a frame: ignored
    render::ContactSheetOptions o;
    o.tile_width = 64;
    o.gap = 0;
    o.columns = 5;
    render::write_contact_sheet(dir, dir / "sheet.png", 2, o);  // frames 0, 10, 20
    const Image sheet = render::read_png(dir / "sheet.png");
    CHECK(sheet.width == 3 * 64);
    CHECK(sheet.height == 48);
    // Each tile has white label pixels in its top-left corner only.
    for (int t = 0; t < 3; ++t) {
      int white_corner = 0, white_elsewhere = 0;
      for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
          const bool white = is(sheet, 64 * t + x, y, 0xffffffffu);
          (x < 40 && y < 20 ? white_corner : white_elsewhere) += white;
        }
      CHECK(white_corner > 10);
      CHECK(white_elsewhere == 0);
    }
    // "frame_000010" is labelled "10": wider than the "0" of frame 0.
    int w0 = 0, w10 = 0;
    for (int y = 0; y < 20; ++y)
      for (int x = 0; x < 64; ++x) {
        w0 += is(sheet, x, y, 0xffffffffu);
        w10 += is(sheet, 64 + x, y, 0xffffffffu);
      }
    CHECK(w10 > w0);
    o.labels = false;
    render::write_contact_sheet(dir, dir / "plain.png", 2, o);
    const Image plain = render::read_png(dir / "plain.png");
    CHECK(is(plain, 5, 5, 0x202020ffu));
    CHECK_THROWS_WITH_AS(render::write_contact_sheet(dir / "nope", dir / "s.png"), doctest::Contains("nope"), Error);
    CHECK_THROWS_WITH_AS(render::contact_sheet(std::vector<Image>{}, {}), doctest::Contains("no frames"), Error);
  }
}
