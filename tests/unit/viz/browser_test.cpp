// Each kind of page in a real browser: headless Chromium (software WebGL) opens it offline,
// the page marks itself drawn (data-ready) with no error, and a screenshot shows the hand where
// the grasp's pose puts it. Skipped without chromium, except under CI=true where it fails.
#include <cairo.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

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

/// The value of attribute `name` of the dumped page's <body>, "" when absent.
std::string bodyAttribute(const std::string& dom, const std::string& name) {
  const auto open = dom.find("<body");
  const auto end = dom.find('>', open);
  const auto at = dom.find(" " + name + "=\"", open);
  if (open == std::string::npos || at == std::string::npos || at > end) return "";
  const auto from = at + name.size() + 3;
  return dom.substr(from, dom.find('"', from) - from);
}

TEST_F(Browser, ReachPageDrawsTheMapsHandClosingOnTheObject) {
  fs::create_directories(dir);
  const HandModel hand = testing::humanoidHand();
  const TrajectoryRecord r = testing::smallTrajectory();
  ReachPageInput in;
  in.trajectory = &r;
  in.hand = &hand;
  in.grasp_joints = hand.preshape() + 0.7 * (hand.upperLimits() - hand.preshape());
  const fs::path page = dir / "reach_hand.html";
  writeReachPage(in, page.string());
  std::size_t shapes = 0;
  for (const HandLink& l : hand.links()) shapes += l.shapes.size();
  ASSERT_GT(shapes, 5u);
  for (const std::string step : {"0", "10"}) {
    const std::string dom = drawnDom(page, "#step=" + step, 1);
    EXPECT_EQ(bodyAttribute(dom, "data-hand-meshes"), std::to_string(shapes)) << "step " << step;
    EXPECT_NE(dom.find("closing to grasp #"), std::string::npos);
  }
  // The hand (blue) is drawn near the palm's path; the envelope primitive (blue too) is hidden.
  cairo_surface_t* shot = screenshot(page, "#view=front", 900, 600);
  EXPECT_GT(pixels(shot, 305, blueish).first, 500);
  cairo_surface_destroy(shot);
  // Without the hand: the planner's primitives, no hand meshes, and the page says why.
  writeReachPage(r, page.string());
  const std::string dom = drawnDom(page, "", 1);
  EXPECT_EQ(bodyAttribute(dom, "data-hand-meshes"), "0");
  EXPECT_NE(dom.find("the map's hand is not drawn: no hand model given"), std::string::npos);
}

/// A trajectory whose cost terms are those of `reach --map`, at the scale of the issue's report
/// (the quality term near -10^6 .. -4 10^6).
TrajectoryRecord largeCostTrajectory() {
  TrajectoryRecord r = testing::smallTrajectory();
  r.cost_terms = {"total",    "path_length", "end_velocity", "collision",         "joint_limit",
                  "terminal", "proximity",   "quality",      "nearest_distance_m"};
  r.cost_history.resize(41, 9);
  for (Eigen::Index i = 0; i <= 40; ++i)
    r.cost_history.row(i) << -984899.1234 - 70000.5 * i, 1.151, 0.0, 0.0477, 0.1486,
        -984899.1234 - 70000.5 * i, 123456.789, -984899.1234 - 70000.5 * i, 0.000123;
  return r;
}

// The side panel's cost table shows every column inside the panel and the window: the right edge
// of each row's last cell, the panel's inner right edge and its overflow, measured by a script
// appended to the page after it is drawn.
TEST_F(Browser, ReachPageCostTableIsNotCutOff) {
  fs::create_directories(dir);
  const fs::path page = dir / "reach_costs.html";
  std::string html = reachPageHtml(largeCostTrajectory());
  const std::string probe = R"(<script>
const side = document.getElementById('tm-side'), rows = document.querySelectorAll('#tm-costs tr');
let right = 0, empty = 0;
rows.forEach((tr) => { const c = tr.lastElementChild; right = Math.max(right, c.getBoundingClientRect().right);
  if (!c.textContent) ++empty; });
const s = side.getBoundingClientRect();
document.body.setAttribute('data-costs', [rows.length, right, s.left + side.clientLeft + side.clientWidth,
  window.innerWidth, side.scrollWidth - side.clientWidth, empty].join(' '));
</script>
</body>)";
  html.replace(html.rfind("</body>"), 7, probe);
  std::ofstream(page) << html;
  for (const auto& [w, h] : {std::pair{1200, 750}, std::pair{800, 600}}) {
    const testing::CliRun run = testing::runChromium(
        "file://" + page.string(),
        "--window-size=" + std::to_string(w) + "," + std::to_string(h) + " --dump-dom",
        (dir / "profile").string());
    std::istringstream m(bodyAttribute(run.out, "data-costs"));
    double rows = 0, right = 0, inner = 0, window = 0, overflow = 0, empty = 0;
    ASSERT_TRUE(m >> rows >> right >> inner >> window >> overflow >> empty)
        << run.out.substr(0, 600);
    EXPECT_EQ(rows, 10) << w << "x" << h;
    EXPECT_LE(right, inner + 0.5) << w << "x" << h << ": the final column ends outside the panel";
    EXPECT_LE(right, window) << w << "x" << h;
    EXPECT_LE(overflow, 0) << w << "x" << h << ": the panel scrolls sideways";
    EXPECT_EQ(empty, 0);
  }
}

}  // namespace
}  // namespace taskmap
