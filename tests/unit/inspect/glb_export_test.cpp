// The GLB bytes of a trajectory (`taskmap export-glb`): the container layout of glTF 2.0
// (header, JSON chunk, BIN chunk, lengths and 4-byte alignment), one node per body, one
// animation key per step, and the atomic write.
#include "taskmap/inspect/glb_export.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

std::uint32_t u32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

TEST(GlbExport, ContainerAndContentFollowTheRecord) {
  const TrajectoryRecord r = testing::smallTrajectory();
  const std::string b = glbBytes(r);
  ASSERT_GE(b.size(), 28u);
  EXPECT_EQ(b.substr(0, 4), "glTF");
  EXPECT_EQ(u32(b, 4), 2u);        // version
  EXPECT_EQ(u32(b, 8), b.size());  // total length
  const std::uint32_t json_len = u32(b, 12);
  EXPECT_EQ(b.substr(16, 4), "JSON");
  EXPECT_EQ(json_len % 4, 0u);
  const std::size_t bin_at = 20 + json_len;
  EXPECT_EQ(b.substr(bin_at + 4, 4), std::string("BIN\0", 4));
  EXPECT_EQ(bin_at + 8 + u32(b, bin_at), b.size());
  const nlohmann::json j = nlohmann::json::parse(b.substr(20, json_len));
  EXPECT_EQ(j["asset"]["version"], "2.0");
  std::size_t bodies = 0;
  for (const auto& n : j["nodes"])
    for (const std::string& name : r.body_names) bodies += n.value("name", "") == name;
  EXPECT_EQ(bodies, r.body_names.size());
  ASSERT_EQ(j["animations"].size(), 1u);
  const int input = j["animations"][0]["samplers"][0]["input"].get<int>();
  EXPECT_EQ(j["accessors"][input]["count"].get<Eigen::Index>(), r.rows());
}

TEST(GlbExport, WritesAtomicallyAndNamesABadPath) {
  testing::ScratchDir dir("glb_export");
  const TrajectoryRecord r = testing::smallTrajectory();
  const std::string path = dir.path("t.glb");
  writeGlb(r, path);
  EXPECT_EQ(std::filesystem::file_size(path), glbBytes(r).size());
  EXPECT_TRUE(testing::throwsError([&] { writeGlb(r, "/nonexistent/dir/t.glb"); },
                                   {"/nonexistent/dir/t.glb"}));
}

}  // namespace
}  // namespace taskmap
