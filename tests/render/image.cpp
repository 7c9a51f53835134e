#include "render/image.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <random>

#include "core/error.hpp"
#include "test_support.hpp"

using namespace softcut;
using render::Image;

namespace {

Image random_image(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  Image img(w, h);
  for (auto& b : img.rgba) b = std::uint8_t(rng());
  return img;
}

}  // namespace

TEST_SUITE("render/image") {
  TEST_CASE("PNG encoding is lossless for any content and size") {
    for (auto [w, h] : {std::pair{1, 1}, std::pair{3, 7}, std::pair{64, 48}, std::pair{257, 3}}) {
      const Image img = random_image(w, h, unsigned(w * 1000 + h));
      const std::string png = render::encode_png(img);
      CHECK(png.substr(1, 3) == "PNG");
      const Image back = render::decode_png(png, "memory");
      CHECK(back.width == w);
      CHECK(back.height == h);
      CHECK(back.rgba == img.rgba);
    }
    // Opaque images are stored as RGB (IHDR colour type 2, at byte 25), others
    // as RGBA (6); both decode to the same RGBA.
    for (const bool opaque : {true, false}) {
      Image img = random_image(33, 17, opaque ? 5u : 6u);
      for (size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = opaque ? 255 : img.rgba[i] | 1;
      const std::string png = render::encode_png(img);
      CHECK(int(png[25]) == (opaque ? 2 : 6));
      CHECK(render::decode_png(png, "memory").rgba == img.rgba);
    }
    // Flat frames (most of a render) compress well.
    const Image flat(640, 480, 0x334455ffu);
    CHECK(render::encode_png(flat).size() < 640 * 480 * 4 / 100);
  }

  TEST_CASE("write_png is atomic and replaces the old file which decodes to the expected size") {
    const auto dir = test::scratch_dir("image_png");
    const auto path = dir / "frame_000123.png";
    render::write_png(path, random_image(20, 10, 1));
    const Image second = random_image(30, 15, 2);
    render::write_png(path, second);
    const Image back = render::read_png(path);
    CHECK(back.width == 30);
    CHECK(back.height == 15);
    CHECK(back.rgba == second.rgba);
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
    CHECK(files == 1);
    CHECK_THROWS_WITH_AS(render::write_png(dir / "missing" / "f.png", second), doctest::Contains("missing/f.png"),
                         Error);
  }

  TEST_CASE("bad images are refused naming the source") {
    CHECK_THROWS_WITH_AS(render::decode_png("not a png", "frames/x.png"), doctest::Contains("frames/x.png: not a"),
                         Error);
    CHECK_THROWS_WITH_AS(render::read_png("/nonexistent/y.png"), doctest::Contains("/nonexistent/y.png"), Error);
    Image broken(4, 4);
    broken.rgba.resize(10);
    CHECK_THROWS_AS(render::encode_png(broken), Error);
  }

  TEST_CASE("comparison counts exactly the pixels beyond the tolerance") {
    const Image a = random_image(50, 40, 3);
    Image b = a;
    std::mt19937 rng(4);
    int moved = 0;
    for (int i = 0; i < 300; ++i) {
      const int x = int(rng() % 50), y = int(rng() % 40), c = int(rng() % 4);
      std::uint8_t* p = b.at(x, y);
      if (p[c] < 128) p[c] = std::uint8_t(p[c] + 5 + rng() % 100);
      else p[c] = std::uint8_t(p[c] - 5 - rng() % 100);
    }
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 50; ++x) {
        int worst = 0;
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c])));
        moved += worst > 4;
      }
    const auto d = render::compare_images(b, a, 4);
    CHECK(d.same_size);
    CHECK(d.differing == moved);
    CHECK(d.fraction == doctest::Approx(moved / 2000.0));
    CHECK(d.max_channel_diff >= 5);
    int red = 0;
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 50; ++x) red += d.diff.at(x, y)[0] == 255 && d.diff.at(x, y)[1] == 0;
    CHECK(red == moved);
    CHECK(render::compare_images(b, a, 255).differing == 0);
    CHECK_FALSE(render::compare_images(Image(3, 3), Image(3, 4), 0).same_size);
  }
}
