// Bounded mesh loading (meshes/src/mesh_bounds.cpp): a hostile header of every format is
// refused at once, naming the file and the impossible count, and the load's peak memory stays
// within a small multiple of the file's size. Each load runs in a child process with an
// address-space limit, so a regression shows as a failed test instead of a machine out of
// memory.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "child_probe.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string tempFile(const std::string& name, const std::string& bytes) {
  const fs::path dir =
      fs::temp_directory_path() / ("taskmap_mesh_bounds_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

std::string le32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i)
    s[static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xff);
  return s;
}

struct Hostile {
  std::string name;      // file name (its extension picks the format)
  std::string bytes;     // the file
  std::string expected;  // part of the refusal ("" when assimp's own error is fine)
  std::string honest;    // an honest file of the same format (tests/data/meshes/fuzz/)
};

// Peak memory growth (KiB) of loading path in a fresh child.
long peakOfLoad(const std::string& path) {
  return test::runInChild(
             [&path] {
               try {
                 ObjectModel::load(path);
               } catch (const std::exception&) {
               }
               return std::string();
             },
             60.0)
      .peak_rss_delta_kib;
}

std::vector<Hostile> hostileFiles() {
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 4000000000\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string ply_binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 2000000000\n"
      "property list uchar int vertex_indices\nend_header\n" +
      std::string(36, '\0') + "\x03" + std::string(12, '\0');
  // Honest header, hostile list count in the body (assimp reserves the count).
  const std::string ply_list =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n2147483648 0 1 2\n";
  const std::string ply_binary_list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uint int vertex_indices\n"
      "end_header\n" +
      std::string(36, '\0') + le32(0x7fffffffu) + std::string(12, '\0');
  std::string stl(80, ' ');
  stl += le32(0xfffffff0u) + std::string(50, '\0');
  return {
      {"huge.off", "OFF\n353535235358 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "declares 353535235358 vertices", "box.off"},
      {"huge_faces.off", "OFF\n3 99999999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "declares 99999999999 faces", "box.off"},
      {"huge_ascii.ply", ply_head, "declares 4000000000 'vertex' elements", "box_ascii.ply"},
      {"huge_binary.ply", ply_binary, "declares 2000000000 'face' elements", "box_binary.ply"},
      {"huge_list.ply", ply_list, "face 0: list of 2147483648 values", "box_ascii.ply"},
      {"huge_list_binary.ply", ply_binary_list, "face 0: list of 2147483647 values",
       "box_binary.ply"},
      {"huge.stl", stl, "declares 4294967280 triangles", "box_binary.stl"},
      // Line-based formats declare nothing; assimp's memory follows the content.
      {"huge_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 999999999999\n", "", "box.obj"},
      {"truncated_ascii.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "",
       "box_ascii.stl"},
  };
}

TEST(MeshBoundsTest, HostileHeadersAreRefusedWithinASmallMultipleOfTheFileSize) {
  for (const Hostile& h : hostileFiles()) {
    SCOPED_TRACE(h.name);
    const std::string path = tempFile(h.name, h.bytes);
    // 1 GiB of address space beyond the parent's: without the bound, assimp's reservation of
    // the declared counts fails (bad_alloc) or the child is killed, and the test fails.
    const test::ChildOutcome out = test::runInChild(
        [&path] {
          try {
            ObjectModel::load(path);
            return std::string("accepted");
          } catch (const std::exception& e) {
            return std::string(e.what());
          }
        },
        60.0, 1ull << 30);
    ASSERT_EQ(out.kind, test::ChildOutcome::Kind::kReturned) << "signal " << out.signal;
    EXPECT_NE(out.reply, "accepted");
    EXPECT_NE(out.reply.find(path), std::string::npos) << out.reply;
    EXPECT_EQ(out.reply.find("bad_alloc"), std::string::npos) << out.reply;
    if (!h.expected.empty()) {
      EXPECT_NE(out.reply.find(h.expected), std::string::npos) << out.reply;
    }
    // Peak memory: the fixed cost of loading an honest file of the format (the importer's
    // tables, ~20 MiB for assimp's first OBJ import) plus a small multiple of the file size.
    const long honest = peakOfLoad(std::string(TEST_DATA_DIR) + "/meshes/fuzz/" + h.honest);
    const long limit_kib = honest + 1024 + static_cast<long>(16 * h.bytes.size() / 1024);
    EXPECT_LE(out.peak_rss_delta_kib, limit_kib) << out.reply;
    std::printf("[ mesh-bounds ] %-20s %4zu bytes  peak +%ld KiB (honest %s: +%ld KiB)  %s\n",
                h.name.c_str(), h.bytes.size(), out.peak_rss_delta_kib, h.honest.c_str(), honest,
                out.reply.c_str());
  }
}

TEST(MeshBoundsTest, HonestFilesOfEveryFormatStillLoad) {
  // The same triangle soup (a tetrahedron) in each bounded format loads as a solid.
  const std::string off =
      "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"tetra.off", off},
                                    std::pair<std::string, std::string>{"tetra.ply", ply}}) {
    SCOPED_TRACE(name);
    const ObjectModel m = ObjectModel::load(tempFile(name, bytes));
    EXPECT_NEAR(m.massProperties().volume, 1.0 / 6.0, 1e-12);
  }
}

}  // namespace
}  // namespace taskmap
