// `taskmap inspect`, `taskmap export` and `taskmap import` through the command line.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cairo.h>
#include <gtest/gtest.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "synthetic_map.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

using testing::CliRun;

CliRun run(const std::string& args) {
  return testing::runTaskmap(args);
}

// The JSON of `inspect --json --png` without the warning lines (stderr is merged into the
// output; maps whose hand is not found draw no hand and say so).
nlohmann::json jsonOf(const std::string& out) {
  std::string json;
  std::size_t at = 0;
  while (at < out.size()) {
    const std::size_t end = std::min(out.find('\n', at), out.size());
    const std::string line = out.substr(at, end - at);
    if (line.find(": warning: ") == std::string::npos) json += line + "\n";
    at = end + 1;
  }
  return nlohmann::json::parse(json);
}

class InspectCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("inspect_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    map_ = testing::clusteredBasketMap();
    map_path_ = (dir_ / "basket.h5").string();
    writeMap(map_path_, map_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
  TaskMapData map_;
  std::string map_path_;
};

std::vector<double> forceClosureEpsilons(const TaskMapData& m) {
  std::vector<double> e;
  for (std::size_t i = 0; i < m.grasps.size(); ++i)
    if (m.grasps.force_closure[i]) e.push_back(m.grasps.epsilon[i]);
  std::sort(e.begin(), e.end());
  return e;
}

TEST_F(InspectCliTest, TextSummaryNamesEverything) {
  const CliRun r = run("inspect " + map_path_);
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* s : {"basket: 32 vertices, 48 faces", "three_finger (3 joints)",
                        "volume sampler, seed 11, 306 trials", "no_contact 204, ok 102",
                        "102 stored, 99 in force closure, valid rate 32.4% of trials",
                        "clusters   3 (single linkage", "6 outliers"}) {
    EXPECT_NE(r.out.find(s), std::string::npos) << "missing '" << s << "' in\n" << r.out;
  }
  // Epsilon statistics against a sorted copy.
  const std::vector<double> e = forceClosureEpsilons(map_);
  ASSERT_EQ(e.size(), 99u);
  char line[128];
  std::snprintf(line, sizeof(line), "min %.4g  median %.4g  max %.4g", e.front(), e[49], e.back());
  EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  // One table row per cluster, with its size and representative.
  for (const auto& c : map_.clustering->clusters) {
    std::snprintf(line, sizeof(line), "%6d %6d", c.size, c.representative);
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
}

TEST_F(InspectCliTest, JsonMatchesTheMap) {
  const CliRun r = run("inspect --json " + map_path_);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["object"]["name"], "basket");
  EXPECT_EQ(j["hand"]["name"], "three_finger");
  EXPECT_EQ(j["sampling"]["seed"], 11);
  EXPECT_EQ(j["sampling"]["outcomes"]["ok"], 102);
  EXPECT_EQ(j["grasps"]["count"], 102);
  EXPECT_EQ(j["grasps"]["force_closure"], 99);
  EXPECT_DOUBLE_EQ(j["grasps"]["valid_rate"].get<double>(), 99.0 / 306.0);
  const std::vector<double> e = forceClosureEpsilons(map_);
  EXPECT_DOUBLE_EQ(j["epsilon"]["min"].get<double>(), e.front());
  EXPECT_DOUBLE_EQ(j["epsilon"]["median"].get<double>(), e[49]);
  EXPECT_DOUBLE_EQ(j["epsilon"]["max"].get<double>(), e.back());
  const auto& clusters = j["clustering"]["clusters"];
  ASSERT_EQ(clusters.size(), 3u);
  EXPECT_EQ(j["clustering"]["outliers"], 6);
  std::set<std::string> colors;
  for (std::size_t k = 0; k < 3; ++k) {
    const ClusterSummary& c = map_.clustering->clusters[k];
    EXPECT_EQ(clusters[k]["size"], c.size);
    EXPECT_EQ(clusters[k]["representative"], c.representative);
    EXPECT_DOUBLE_EQ(clusters[k]["best_epsilon"].get<double>(), c.best_epsilon);
    const Pose rep = map_.grasps.poseAt(static_cast<std::size_t>(c.representative));
    const Eigen::Vector3d axis = rep.orientation.toRotationMatrix().col(2);
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(clusters[k]["pose"][d].get<double>(), rep.position[d], 1e-15);
      EXPECT_NEAR(clusters[k]["approach"][d].get<double>(), axis[d], 1e-12);
    }
    colors.insert(clusters[k]["color"].get<std::string>());
  }
  EXPECT_EQ(colors.size(), 3u);
}

// Reads a PNG with cairo; counts pixels per exact RGB colour.
struct Png {
  int width = 0, height = 0;
  std::map<std::uint32_t, int> counts;
  int count(std::uint32_t rgb) const {
    const auto it = counts.find(rgb);
    return it == counts.end() ? 0 : it->second;
  }
};

Png readPng(const std::string& file) {
  Png png;
  cairo_surface_t* s = cairo_image_surface_create_from_png(file.c_str());
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    png.width = cairo_image_surface_get_width(s);
    png.height = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    for (int y = 0; y < png.height; ++y) {
      const auto* row = reinterpret_cast<const std::uint32_t*>(data + y * stride);
      for (int x = 0; x < png.width; ++x) ++png.counts[row[x] & 0xffffffu];
    }
  }
  cairo_surface_destroy(s);
  return png;
}

std::uint32_t hexColor(const std::string& hex) {
  return static_cast<std::uint32_t>(std::stoul(hex.substr(1), nullptr, 16));
}

TEST_F(InspectCliTest, PictureHasEveryClusterColour) {
  const std::string png_path = path("map.png");
  const CliRun r = run("inspect --json --png " + png_path + " " + map_path_);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = jsonOf(r.out);
  const Png png = readPng(png_path);
  EXPECT_EQ(png.width, 1600);
  EXPECT_EQ(png.height, 1100);
  // Not blank: many colours, a large light-grey silhouette.
  EXPECT_GT(png.counts.size(), 50u);
  EXPECT_GT(png.count(0xcccccc), 20000);
  // Every cluster's colour covers more than its legend swatch (16 x 16): dots, markers, bars.
  int distinct = 0;
  for (const auto& c : j["clustering"]["clusters"]) {
    const int count = png.count(hexColor(c["color"]));
    EXPECT_GT(count, 1000) << c["color"];
    distinct += count > 0;
  }
  EXPECT_GE(distinct, static_cast<int>(map_.clustering->clusters.size()));
  EXPECT_GT(png.count(0x969696), 0);  // outliers grey
  // Written atomically: no temporary file left beside it.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.path().extension() != ".h5";
  EXPECT_EQ(files, 1);

  ASSERT_EQ(run("inspect --png " + png_path + " --width 900 --height 650 " + map_path_).code, 0);
  const Png small = readPng(png_path);
  EXPECT_EQ(small.width, 900);
  EXPECT_EQ(small.height, 650);
}

TEST_F(InspectCliTest, PictureNamesTheFileNotItsDirectory) {
  // The same map in two directories of different depth draws the same pixels: the caption is
  // the file name only (a picture checked into docs/ must not show a build directory).
  const fs::path deep = dir_ / "a_long_build_directory" / "nested";
  fs::create_directories(deep);
  fs::copy_file(map_path_, deep / "basket.h5");
  ASSERT_EQ(run("inspect --png " + path("top.png") + " " + map_path_).code, 0);
  ASSERT_EQ(run("inspect --png " + path("deep.png") + " " + (deep / "basket.h5").string()).code, 0);
  const Png top = readPng(path("top.png"));
  const Png nested = readPng(path("deep.png"));
  ASSERT_GT(top.counts.size(), 50u);
  EXPECT_EQ(top.counts, nested.counts);
  // A different file name does change the caption (the comparison can fail).
  fs::copy_file(map_path_, deep / "basket_with_a_much_longer_name.h5");
  ASSERT_EQ(run("inspect --png " + path("other.png") + " " +
                (deep / "basket_with_a_much_longer_name.h5").string())
                .code,
            0);
  EXPECT_NE(top.counts, readPng(path("other.png")).counts);
}

TEST_F(InspectCliTest, ManyClustersKeepDistinctColours) {
  // 24 clusters (one per grasp group) from the same grasps, re-labelled round robin.
  TaskMapData m = map_;
  ClusteringResult& c = *m.clustering;
  const int k_count = 24;
  c.clusters.assign(k_count, ClusterSummary{});
  for (std::size_t i = 0; i < c.labels.size(); ++i) c.labels[i] = static_cast<int>(i % k_count);
  for (int k = 0; k < k_count; ++k) {
    ClusterSummary& s = c.clusters[static_cast<std::size_t>(k)];
    for (std::size_t i = static_cast<std::size_t>(k); i < c.labels.size(); i += k_count) {
      ++s.size;
      if (s.representative < 0) s.representative = static_cast<int>(i);
    }
    s.mean_pose = m.grasps.poseAt(static_cast<std::size_t>(s.representative));
  }
  const std::string file = path("many.h5");
  writeMap(file, m);
  const std::string png_path = path("many.png");
  const CliRun r = run("inspect --json --png " + png_path + " " + file);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = jsonOf(r.out);
  const Png png = readPng(png_path);
  std::set<std::uint32_t> colors;
  for (const auto& cl : j["clustering"]["clusters"]) {
    colors.insert(hexColor(cl["color"]));
    EXPECT_GT(png.count(hexColor(cl["color"])), 300) << cl["color"];
  }
  EXPECT_EQ(colors.size(), static_cast<std::size_t>(k_count));
  EXPECT_EQ(colors.count(0x969696), 0u);
}

TEST_F(InspectCliTest, UnclusteredMapInspectsAndDraws) {
  TaskMapData m = map_;
  m.clustering.reset();
  const std::string file = path("plain.h5");
  writeMap(file, m);
  CliRun r = run("inspect " + file);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("clusters   none"), std::string::npos) << r.out;
  r = run("inspect --json --png " + path("plain.png") + " " + file);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(jsonOf(r.out)["clustering"].is_null());
  const Png png = readPng(path("plain.png"));
  EXPECT_EQ(png.width, 1600);
  EXPECT_GT(png.count(0x969696), 0);  // every grasp drawn as an outlier
  EXPECT_EQ(png.count(0x1f77b4), 0);  // no cluster colour
  ASSERT_EQ(run("export " + file + " --format glb -o " + path("plain.glb")).code, 0);
}

int countFaces(const aiMesh& mesh, unsigned indices) {
  int n = 0;
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) n += mesh.mFaces[f].mNumIndices == indices;
  return n;
}

TEST_F(InspectCliTest, PlyAndGlbReadBackWithObjectAndGraspCounts) {
  const auto nv = static_cast<unsigned>(map_.object.vertices.rows());
  const auto n = static_cast<unsigned>(map_.grasps.size());
  const unsigned glyph_vertices = 3 * 32;  // one glyph per cluster
  ASSERT_EQ(run("export " + map_path_ + " --format ply -o " + path("m.ply")).code, 0);
  Assimp::Importer ply;
  const aiScene* s = ply.ReadFile(path("m.ply"), 0);
  ASSERT_NE(s, nullptr) << ply.GetErrorString();
  ASSERT_EQ(s->mNumMeshes, 1u);
  EXPECT_EQ(s->mMeshes[0]->mNumVertices, nv + n + glyph_vertices);
  EXPECT_EQ(countFaces(*s->mMeshes[0], 1), static_cast<int>(n));
  EXPECT_EQ(countFaces(*s->mMeshes[0], 3), static_cast<int>(map_.object.faces.rows()) + 3 * 48);
  // The object's vertices come first.
  for (unsigned i = 0; i < nv; ++i) {
    EXPECT_NEAR(s->mMeshes[0]->mVertices[i].z, map_.object.vertices(i, 2), 1e-6);
  }

  ASSERT_EQ(run("export " + map_path_ + " --format glb -o " + path("m.glb")).code, 0);
  Assimp::Importer glb;
  s = glb.ReadFile(path("m.glb"), 0);
  ASSERT_NE(s, nullptr) << glb.GetErrorString();
  std::map<std::string, const aiMesh*> meshes;
  for (unsigned i = 0; i < s->mNumMeshes; ++i) meshes[s->mMeshes[i]->mName.C_Str()] = s->mMeshes[i];
  ASSERT_EQ(meshes.size(), 3u);
  // glTF export joins identical vertices: the object keeps its distinct vertices (all of them
  // for a repaired mesh; the synthetic basket's bars share a few corners).
  std::set<std::array<double, 3>> distinct;
  for (unsigned i = 0; i < nv; ++i) {
    distinct.insert(
        {map_.object.vertices(i, 0), map_.object.vertices(i, 1), map_.object.vertices(i, 2)});
  }
  ASSERT_LT(distinct.size(), nv);
  EXPECT_EQ(meshes["object"]->mNumVertices, distinct.size());
  EXPECT_EQ(meshes["object"]->mNumFaces, static_cast<unsigned>(map_.object.faces.rows()));
  EXPECT_EQ(meshes["grasps"]->mNumFaces, n);
  EXPECT_EQ(countFaces(*meshes["grasps"], 1), static_cast<int>(n));
  EXPECT_EQ(meshes["glyphs"]->mNumVertices, glyph_vertices);
}

TEST_F(InspectCliTest, AcronymExportThenImportKeepsPosesAndFlags) {
  const std::string acr = path("basket_acronym.h5");
  CliRun r = run("export " + map_path_ + " --format acronym -o " + acr);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string imported = path("imported.h5");
  r = run("import --acronym " + acr + " --object " + TASKMAP_OBJECTS_DIR + "/box.obj -o " +
          imported);
  ASSERT_EQ(r.code, 0) << r.out;
  const TaskMapData back = readMap(imported);
  ASSERT_EQ(back.grasps.size(), map_.grasps.size());
  for (std::size_t i = 0; i < back.grasps.size(); ++i) {
    const Pose a = back.grasps.poseAt(i), b = map_.grasps.poseAt(i);
    EXPECT_LT((a.position - b.position).cwiseAbs().maxCoeff(), 1e-12) << i;
    EXPECT_LT(std::min((a.orientation.coeffs() - b.orientation.coeffs()).cwiseAbs().maxCoeff(),
                       (a.orientation.coeffs() + b.orientation.coeffs()).cwiseAbs().maxCoeff()),
              1e-12)
        << i;
    EXPECT_EQ(back.grasps.force_closure[i], map_.grasps.force_closure[i]) << i;
  }
  EXPECT_FALSE(back.grasps.contacts_available);
  ASSERT_TRUE(back.clustering.has_value());
  EXPECT_EQ(back.clustering->labels.size(), back.grasps.size());
  EXPECT_EQ(back.object.name, "box");
  // The imported map inspects like any other.
  r = run("inspect " + imported);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("contacts absent (imported map)"), std::string::npos) << r.out;
}

TEST_F(InspectCliTest, BadInputGivesClearErrorsAndNonZeroExit) {
  CliRun r = run("inspect " + path("missing.h5"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("taskmap: error: map file '" + path("missing.h5") + "' does not exist"),
            std::string::npos)
      << r.out;

  const std::string corrupt = path("corrupt.h5");
  {
    std::ifstream in(map_path_, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(bytes.size() / 3);  // truncated
    std::ofstream(corrupt, std::ios::binary) << bytes;
  }
  for (const std::string& cmd :
       {"inspect " + corrupt, "export " + corrupt + " --format ply -o " + path("x.ply")}) {
    r = run(cmd);
    EXPECT_EQ(r.code, 1) << cmd << "\n" << r.out;
    EXPECT_NE(r.out.find("taskmap: error:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(corrupt), std::string::npos) << r.out;
  }
  const std::string text = path("text.h5");
  std::ofstream(text) << "hello\n";
  r = run("inspect " + text);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find(text), std::string::npos) << r.out;

  r = run("export " + map_path_ + " --format stl -o " + path("x.stl"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("unknown format 'stl'; use ply, glb or acronym"), std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(path("x.stl")));

  r = run("inspect --png /nonexistent/dir/x.png " + map_path_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("cannot write picture '/nonexistent/dir/x.png'"), std::string::npos)
      << r.out;
  r = run("inspect --png " + path("x.png") + " --width 10 " + map_path_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("--width 10 is out of range"), std::string::npos) << r.out;

  r = run("import --acronym " + path("none.h5") + " --object " + TASKMAP_OBJECTS_DIR +
          "/box.obj -o " + path("y.h5"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  r = run("import --acronym " + map_path_ + " --object " + TASKMAP_OBJECTS_DIR + "/box.obj -o " +
          path("y.h5"));
  EXPECT_EQ(r.code, 1);  // a task map is not an ACRONYM file
  EXPECT_NE(r.out.find("grasps/transforms is missing"), std::string::npos) << r.out;
  const std::string acr = path("a.h5");
  ASSERT_EQ(run("export " + map_path_ + " --format acronym -o " + acr).code, 0);
  r = run("import --acronym " + acr + " --object " + path("nomesh.obj") + " -o " + path("y.h5"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("object mesh '" + path("nomesh.obj") + "' does not exist"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(path("y.h5")));
}

// A map of the humanoid hand with one grasp per palm position (each grasp a cluster of its
// own, its representative), the hand closed in its preshape and approaching the origin.
TaskMapData handMap(const HandModel& hand, const std::vector<Eigen::Vector3d>& palms) {
  TaskMapData m = testing::oneGraspMap(hand, palms[0]);
  const auto n = static_cast<Eigen::Index>(palms.size());
  MapGrasps& g = m.grasps;
  g.pose.conservativeResize(n, 7);
  g.joints.conservativeResize(n, g.joints.cols());
  ClusteringResult c;
  c.method = Linkage::kSingle;
  c.rotation_scale = 0.1;
  c.threshold = 0.01;
  c.min_size = 1;
  c.linkage = testing::chainLinkage(n, 0.5);
  for (Eigen::Index i = 0; i < n; ++i) {
    const TaskMapData one = testing::oneGraspMap(hand, palms[static_cast<std::size_t>(i)]);
    g.pose.row(i) = one.grasps.pose.row(0);
    g.joints.row(i) = one.grasps.joints.row(0);
    if (i > 0) {
      g.force_closure.push_back(1);
      g.epsilon.push_back(0.125);
      g.volume.push_back(0.001);
      g.contact_offsets.push_back(g.contact_offsets.back());  // no contacts
    }
    c.labels.push_back(static_cast<int>(i));
    ClusterSummary s;
    s.size = 1;
    s.representative = static_cast<int>(i);
    s.mean_pose = g.poseAt(static_cast<std::size_t>(i));
    s.bounds_min = s.bounds_max = s.mean_pose.position;
    s.mean_epsilon = s.best_epsilon = 0.125;
    c.clusters.push_back(s);
  }
  m.clustering = c;
  return m;
}

// The pixels of a PNG as 0xRRGGBB.
struct Pixels {
  int width = 0, height = 0;
  std::vector<std::uint32_t> rgb;
  std::uint32_t at(int x, int y) const {
    return rgb[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(x)];
  }
};

Pixels readPixels(const std::string& file) {
  Pixels p;
  cairo_surface_t* s = cairo_image_surface_create_from_png(file.c_str());
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    p.width = cairo_image_surface_get_width(s);
    p.height = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    for (int y = 0; y < p.height; ++y) {
      const auto* row = reinterpret_cast<const std::uint32_t*>(data + y * stride);
      for (int x = 0; x < p.width; ++x) p.rgb.push_back(row[x] & 0xffffffu);
    }
  }
  cairo_surface_destroy(s);
  return p;
}

// Pixels of one colour class in a rectangle: how many and their mean x.
struct Blob {
  int count = 0;
  double mean_x = 0;
};

template <class Pred>
Blob blob(const Pixels& p, int x0, int y0, int x1, int y1, Pred pred) {
  Blob b;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      if (pred(p.at(x, y))) {
        ++b.count;
        b.mean_x += x;
      }
  if (b.count > 0) b.mean_x /= b.count;
  return b;
}

// colour c at 30 % over white, as the hand outlines are filled (+-3 per channel).
bool handTint(std::uint32_t px, std::uint32_t c) {
  for (int shift : {0, 8, 16}) {
    const double ch = (c >> shift) & 0xff;
    const double expect = 0.3 * ch + 0.7 * 255.0;
    if (std::abs(static_cast<double>((px >> shift) & 0xff) - expect) > 3.0) return false;
  }
  return true;
}

// inspect --png draws the hand, posed by the representative, where the pose puts it: a palm on
// the +x side of the cube puts hand pixels right of the object's silhouette in the top view
// (x right) and the front view (x right), a palm on the -x side left of it. A map whose hand
// is not found draws no hand.
TEST_F(InspectCliTest, PictureOutlinesTheHandAtEachRepresentative) {
  const HandModel hand = testing::humanoidHand();
  // Cells of the 1600 x 1100 picture: top view x in [20, 639), front view x in [651, 1270),
  // both y in [72, 570) (map_picture.cpp's layout).
  const int cells[2][2] = {{20, 639}, {651, 1270}};
  for (double side : {+1.0, -1.0}) {
    SCOPED_TRACE(side > 0 ? "palm at +x" : "palm at -x");
    const std::string file = path("hand.h5"), png_path = path("hand.png");
    writeMap(file, handMap(hand, {Eigen::Vector3d(side * 0.12, 0, 0)}));
    const CliRun r = run("inspect --json --png " + png_path + " " + file);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::uint32_t color = hexColor(jsonOf(r.out)["clustering"]["clusters"][0]["color"]);
    const Pixels png = readPixels(png_path);
    ASSERT_EQ(png.width, 1600);
    for (const auto& cell : cells) {
      const Blob object =
          blob(png, cell[0], 72, cell[1], 570, [](std::uint32_t px) { return px == 0xcccccc; });
      const Blob hand_px = blob(png, cell[0], 72, cell[1], 570,
                                [&](std::uint32_t px) { return handTint(px, color); });
      ASSERT_GT(object.count, 500);
      EXPECT_GT(hand_px.count, 300) << "hand pixels in the view at x " << cell[0];
      EXPECT_GT(side * (hand_px.mean_x - object.mean_x), 20.0)
          << "hand at x " << hand_px.mean_x << ", object at x " << object.mean_x;
    }
  }
  // No hand found by the map's SHA-256: a warning, no hand pixels.
  TaskMapData unknown = handMap(hand, {Eigen::Vector3d(0.12, 0, 0)});
  unknown.hand.urdf_sha256 = std::string(64, '0');
  writeMap(path("unknown.h5"), unknown);
  const CliRun r = run("inspect --png " + path("plain.png") + " " + path("unknown.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("warning"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("drawing no hand"), std::string::npos) << r.out;
  const Pixels plain = readPixels(path("plain.png"));
  const Blob none =
      blob(plain, 20, 72, 1270, 570, [](std::uint32_t px) { return handTint(px, 0x1f77b4); });
  EXPECT_EQ(none.count, 0);
}

// The GLB's JSON chunk (glTF 2.0 binary: 12-byte header, then the JSON chunk).
nlohmann::json glbJson(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || bytes.compare(16, 4, "JSON") != 0)
    return nullptr;
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  if (20 + static_cast<std::size_t>(length) > bytes.size()) return nullptr;
  return nlohmann::json::parse(bytes.substr(20, length));
}

// export --format glb carries the hand at the representatives: one mesh (and node) per link
// with collision shapes per representative, beside object, grasps and glyphs, each link where
// its representative's pose puts it; assimp and three.js's GLTFLoader read the file.
TEST_F(InspectCliTest, GlbCarriesTheHandLinksAtEachRepresentative) {
  const HandModel hand = testing::humanoidHand();
  std::size_t links = 0;
  for (const HandLink& l : hand.links()) links += l.shapes.empty() ? 0 : 1;
  ASSERT_GT(links, 5u);
  const std::string file = path("two.h5"), glb = path("two.glb");
  writeMap(file, handMap(hand, {Eigen::Vector3d(0.12, 0, 0), Eigen::Vector3d(-0.12, 0, 0)}));
  const CliRun r = run("export " + file + " --format glb -o " + glb);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = glbJson(glb);
  ASSERT_TRUE(j.is_object()) << "not a GLB";
  const std::size_t expected = 3 + 2 * links;  // object, grasps, glyphs + links x reps
  EXPECT_EQ(j["meshes"].size(), expected);
  std::size_t with_mesh = 0;
  double centre[2] = {0, 0};
  std::size_t parts[2] = {0, 0};
  for (const auto& node : j["nodes"]) {
    if (!node.contains("mesh")) continue;
    ++with_mesh;
    const std::string name = node.value("name", "");
    for (int k = 0; k < 2; ++k) {
      if (name.rfind("cluster" + std::to_string(k) + "_", 0) != 0) continue;
      const auto& mesh = j["meshes"][node["mesh"].get<std::size_t>()];
      const auto& acc = j["accessors"][mesh["primitives"][0]["attributes"]["POSITION"].get<int>()];
      centre[k] += 0.5 * (acc["min"][0].get<double>() + acc["max"][0].get<double>());
      ++parts[k];
    }
  }
  EXPECT_EQ(with_mesh, expected);
  ASSERT_EQ(parts[0], links);
  ASSERT_EQ(parts[1], links);
  // glTF nodes hold the object frame as is (no node transforms): cluster 0's hand is on the
  // +x side of the cube, cluster 1's on the -x side.
  EXPECT_GT(centre[0] / links, 0.04);
  EXPECT_LT(centre[1] / links, -0.04);

  Assimp::Importer importer;
  const aiScene* s = importer.ReadFile(glb, aiProcess_ValidateDataStructure);
  ASSERT_NE(s, nullptr) << importer.GetErrorString();
  EXPECT_EQ(s->mNumMeshes, expected);
  const std::string three = "/usr/share/javascript/three";
  if (::access("/usr/bin/node", X_OK) == 0 &&
      fs::exists(three + "/examples/js/loaders/GLTFLoader.js")) {
    const CliRun probe = testing::runShell("/usr/bin/node " + std::string(TASKMAP_SOURCE_DIR) +
                                           "/tests/cli/gltf_probe.js " + glb + " " + three);
    ASSERT_EQ(probe.code, 0) << probe.out;
    EXPECT_EQ(nlohmann::json::parse(probe.out)["names"].size(), expected) << probe.out;
  } else {
    std::printf("three.js GLTFLoader check skipped: no /usr/bin/node or libjs-three\n");
  }
  // PLY: one vertex list with the parts after object, points and glyphs.
  ASSERT_EQ(run("export " + file + " --format ply -o " + path("two.ply")).code, 0);
}

}  // namespace
}  // namespace taskmap
