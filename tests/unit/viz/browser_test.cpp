// Each kind of page in a real browser: headless Chromium (software WebGL) opens it offline,
// the page marks itself drawn (data-ready) with no error, and a screenshot shows the hand where
// the grasp's pose puts it. Skipped without chromium, except under CI=true where it fails.
#include <cairo.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>

#include "taskmap/viz/hand_page.hpp"
#include "taskmap/viz/map_page.hpp"
#include "taskmap/viz/reach_page.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

class Browser : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::chromiumPath().empty()) return;
    const char* ci = std::getenv("CI");
    if (ci != nullptr && std::string(ci) == "true")
      FAIL() << "CI=true but chromium is not installed (tools/dev.sh deps installs it)";
    GTEST_SKIP() << "chromium is not installed (apt-get install chromium): browser test skipped";
  }
  fs::path dir = fs::temp_directory_path() / ("viz_browser_" + std::to_string(::getpid()));
  void TearDown() override { fs::remove_all(dir); }

  /// The page's DOM after its scripts ran; checks data-ready = ready and an empty #tm-error.
  std::string drawnDom(const fs::path& page, const std::string& hash, int ready) {
    const testing::CliRun r = testing::runChromium("file://" + page.string() + hash, "--dump-dom",
                                                   (dir / "profile").string());
    EXPECT_EQ(r.code, 0) << r.out.substr(0, 2000);
    // The <body> tag (the scripts' text mentions data-ready too).
    const auto open = r.out.find("<body");
    EXPECT_NE(open, std::string::npos) << r.out.substr(0, 400);
    const std::string body =
        open == std::string::npos ? "" : r.out.substr(open, r.out.find('>', open) - open + 1);
    EXPECT_NE(body.find("data-ready=\"" + std::to_string(ready) + "\""), std::string::npos) << body;
    EXPECT_NE(r.out.find("<div id=\"tm-error\"></div>"), std::string::npos)
        << r.out.substr(r.out.find("tm-error"), 2000);
    return r.out;
  }
  /// Screenshot of the page, width x height, as a cairo image (caller destroys it).
  cairo_surface_t* screenshot(const fs::path& page, const std::string& hash, int w, int h) {
    const fs::path png = dir / "shot.png";
    fs::remove(png);
    testing::runChromium("file://" + page.string() + hash,
                         "--screenshot=" + png.string() + " --window-size=" + std::to_string(w) +
                             "," + std::to_string(h),
                         (dir / "profile").string());
    cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
    EXPECT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS) << png;
    return s;
  }
};

/// Count and mean x of the pixels right of x0 that `pick(r, g, b)` accepts.
template <typename Pick>
std::pair<int, double> pixels(cairo_surface_t* s, int x0, Pick pick) {
  cairo_surface_flush(s);
  const int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
  const int stride = cairo_image_surface_get_stride(s);
  const unsigned char* data = cairo_image_surface_get_data(s);
  int count = 0;
  double sum = 0;
  for (int y = 0; y < h; ++y)
    for (int x = x0; x < w; ++x) {
      const unsigned char* p = data + y * stride + 4 * x;  // B G R A (native endian ARGB32)
      if (pick(p[2], p[1], p[0])) {
        ++count;
        sum += x;
      }
    }
  return {count, count > 0 ? sum / count : 0.0};
}

bool blueish(int r, int g, int b) {
  return b > r + 50 && b > g + 15;
}

TEST_F(Browser, MapPageDrawsTheHandWhereTheGraspPutsIt) {
  const auto start = std::chrono::steady_clock::now();
  fs::create_directories(dir);
  const HandModel hand = testing::humanoidHand();
  const int width = 1200, height = 700, side = 300;  // #tm-side is 300 px wide
  for (const double x : {0.13, -0.13}) {
    const TaskMapData map = testing::oneGraspMap(hand, Eigen::Vector3d(x, 0, 0));
    MapPageInput in;
    in.map = &map;
    in.hand = &hand;
    const fs::path page = dir / "one.html";
    writeMapPage(in, page.string());
    const std::string dom = drawnDom(page, "#view=front&details=0", 1);
    // data-palm="X Y": the selected palm in the view, fractions of its size.
    const auto at = dom.find("data-palm=\"");
    ASSERT_NE(at, std::string::npos);
    const double palm_px = side + std::stod(dom.substr(at + 11)) * (width - side);
    cairo_surface_t* shot = screenshot(page, "#view=front&details=0", width, height);
    const auto [count, mean_x] = pixels(shot, side + 5, blueish);
    const auto background = [](int r, int g, int b) {  // #f4f4f2, not black
      return std::abs(r - 244) < 6 && std::abs(g - 244) < 6 && std::abs(b - 242) < 6;
    };
    EXPECT_GT(pixels(shot, side + 5, background).first, (width - side) * height / 3);
    cairo_surface_destroy(shot);
    const double centre = side + 0.5 * (width - side);
    EXPECT_GT(count, 2000) << "too few hand pixels";
    // Front view: the object frame's +x points right. The hand lies on the palm's side of the
    // cube, and its pixels gather around the palm's projection.
    if (x > 0) {
      EXPECT_GT(palm_px, centre + 50);
      EXPECT_GT(mean_x, centre + 30);
    } else {
      EXPECT_LT(palm_px, centre - 50);
      EXPECT_LT(mean_x, centre - 30);
    }
    EXPECT_NEAR(mean_x, palm_px, 0.15 * (width - side));
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
}

TEST_F(Browser, HandPageIsDrawn) {
  fs::create_directories(dir);
  const fs::path page = dir / "hand.html";
  writeHandPage(testing::humanoidHand(), page.string());
  drawnDom(page, "#pose=closed", 1);
  cairo_surface_t* shot = screenshot(page, "", 900, 600);
  EXPECT_GT(pixels(shot, 305, blueish).first, 2000);
  cairo_surface_destroy(shot);
}

TEST_F(Browser, ReachPageIsDrawn) {
  fs::create_directories(dir);
  const fs::path page = dir / "reach.html";
  writeReachPage(testing::smallTrajectory(), page.string());
  drawnDom(page, "#step=3", 1);
  cairo_surface_t* shot = screenshot(page, "", 900, 600);
  const auto orange = [](int r, int g, int b) { return r > 150 && r > g + 40 && g > b + 20; };
  EXPECT_GT(pixels(shot, 305, orange).first, 500);  // the robot's arm
  cairo_surface_destroy(shot);
}

}  // namespace
}  // namespace taskmap
