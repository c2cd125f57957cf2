// The pictures: PNG bytes decoded again with cairo (the picture's size, its background, every
// cluster colour present in the map picture), the written file equal to the bytes, and the
// errors for bad sizes and unwritable paths (nothing left behind).
#include <cairo.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "synthetic_map.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "taskmap/picture/cost_picture.hpp"
#include "taskmap/picture/hand_picture.hpp"
#include "taskmap/picture/map_picture.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

using testing::clusteredBasketMap;
using testing::throwsError;

/// A decoded PNG: width, height and 0xRRGGBB per pixel.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint32_t> rgb;
  std::array<std::uint8_t, 3> at(int x, int y) const {
    const std::uint32_t v = rgb[static_cast<std::size_t>(y * width + x)];
    return {static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
            static_cast<std::uint8_t>(v)};
  }
};

Image decode(const std::string& png) {
  struct Reader {
    const std::string* bytes;
    std::size_t at = 0;
  } reader{&png};
  cairo_surface_t* s = cairo_image_surface_create_from_png_stream(
      [](void* closure, unsigned char* data, unsigned int length) {
        auto* r = static_cast<Reader*>(closure);
        if (r->at + length > r->bytes->size()) return CAIRO_STATUS_READ_ERROR;
        std::memcpy(data, r->bytes->data() + r->at, length);
        r->at += length;
        return CAIRO_STATUS_SUCCESS;
      },
      &reader);
  Image image;
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    image.width = cairo_image_surface_get_width(s);
    image.height = cairo_image_surface_get_height(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    const int stride = cairo_image_surface_get_stride(s);
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        std::uint32_t v = 0;
        std::memcpy(&v, data + y * stride + 4 * x, 4);
        image.rgb.push_back(v & 0xffffffu);
      }
  }
  cairo_surface_destroy(s);
  return image;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(MapPicture, BytesDecodeToThePictureWithEveryClusterColour) {
  ASSERT_TRUE(pictureSupported());
  const TaskMapData map = clusteredBasketMap();
  const MapSummary summary = summarizeMap(map, "basket.h5");
  PictureOptions options;
  options.width = 1000;
  options.height = 700;
  const std::string png = mapPicturePng(map, summary, options);
  const Image image = decode(png);
  ASSERT_EQ(image.width, 1000);
  ASSERT_EQ(image.height, 700);
  // Background (0.96, 0.96, 0.95) in the top-left corner, to cairo's rounding (one level).
  const std::array<double, 3> background{0.96, 0.96, 0.95};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(image.at(2, 2)[i], 255 * background[i], 1.0) << i;
  std::set<std::uint32_t> colours(image.rgb.begin(), image.rgb.end());
  for (std::size_t k = 0; k < summary.clusters.size(); ++k) {
    const auto c = clusterColor(static_cast<int>(k));
    EXPECT_TRUE(colours.count((std::uint32_t{c[0]} << 16) | (std::uint32_t{c[1]} << 8) | c[2]))
        << "cluster " << k << " colour " << clusterColorHex(static_cast<int>(k)) << " not drawn";
  }
  // The file is the same picture.
  testing::ScratchDir dir("map_picture");
  writeMapPicture(map, summary, dir.path("m.png"), options);
  EXPECT_EQ(fileBytes(dir.path("m.png")), png);
}

TEST(MapPicture, BadSizesAndUnwritablePathsAreNamed) {
  const TaskMapData map = clusteredBasketMap();
  const MapSummary summary = summarizeMap(map, "basket.h5");
  PictureOptions options;
  options.width = 10;
  EXPECT_TRUE(throwsError([&] { mapPicturePng(map, summary, options); },
                          {"--width 10 is out of range", "800 to 8000"}));
  options = PictureOptions{};
  options.height = 9000;
  EXPECT_TRUE(throwsError([&] { options.validate(); }, {"--height 9000", "600 to 8000"}));
  testing::ScratchDir dir("map_picture_bad");
  const std::string path = dir.path("missing/m.png");
  EXPECT_TRUE(throwsError([&] { writeMapPicture(map, summary, path); },
                          {"cannot write picture '" + path + "'"}));
  EXPECT_FALSE(std::filesystem::exists(dir.path("missing")));
}

TEST(HandPicture, IsFifteenHundredByAThousand) {
  testing::ScratchDir dir("hand_picture");
  writeHandPicture(testing::humanoidHand(), dir.path("h.png"));
  const Image image = decode(fileBytes(dir.path("h.png")));
  EXPECT_EQ(image.width, 1500);
  EXPECT_EQ(image.height, 1000);
}

TEST(CostPicture, OnePanelWidthPerPanel) {
  testing::ScratchDir dir("cost_picture");
  CostPanel a{"cost", "iteration", 1.0, {{"total", {3, 2, 1.5}}, {"path", {1, 0.8, 0.7}}}};
  CostPanel b{"map terms", "time [s]", 0.01, {{"proximity", {1, 0.5, 0}}}};
  writeCostPicture({a, b}, dir.path("c.png"));
  const Image image = decode(fileBytes(dir.path("c.png")));
  EXPECT_EQ(image.width, 2 * 640);
  EXPECT_EQ(image.height, 480);
}

}  // namespace
}  // namespace taskmap
