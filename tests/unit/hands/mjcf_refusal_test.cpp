// What the MJCF reader refuses (issue 52): every element taskmap cannot use, named with its line
// (and its file when included); hostile files (docs/HOSTILE_INPUTS.md): nesting, element
// counts, link counts, include cycles, chains and paths outside the model's folder, each refused
// quickly and before TinyXML recurses into the text.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cpu_time.hpp"
#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/hands/mjcf_model.hpp"

namespace taskmap {
namespace {

const testing::ScratchDir kScratch("mjcf_refusal");

/// Writes `xml` to <scratch>/<folder>/<file>; returns the path.
std::string write(const std::string& folder, const std::string& file, const std::string& xml) {
  const std::filesystem::path dir = kScratch.path(folder);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / file) << xml;
  return (dir / file).string();
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A hand: a palm box and a finger on hinge j; `inner` goes inside the finger body, `before` and
/// `after` around <worldbody>.
std::string hand(const std::string& inner, const std::string& before = "",
                 const std::string& after = "") {
  return "<mujoco model=\"t\">\n" + before + "<worldbody>\n<body name=\"palm\">\n" +
         "<geom type=\"box\" size=\"0.01 0.01 0.01\"/>\n<body name=\"finger\">\n" +
         "<joint name=\"j\" range=\"0 1\"/>\n<geom type=\"box\" size=\"0.01 0.01 0.01\"/>\n" +
         inner + "</body>\n</body>\n</worldbody>\n" + after + "</mujoco>\n";
}

/// "line N": the line of the first `needle` in xml.
std::string lineOf(const std::string& xml, const std::string& needle) {
  const auto at = xml.find(needle);
  return "line " +
         std::to_string(1 + std::count(xml.begin(), xml.begin() + static_cast<long>(at), '\n'));
}

std::string refusal(const std::string& path) {
  return testing::errorMessage([&] { readMjcfModel(fileText(path), path); });
}

struct Case {
  const char* name;
  std::string xml;
  std::string needle;  // the refused element (its line is named)
  std::string says;    // what the message says
};

TEST(MjcfRefusal, EveryUnusableElementIsNamedWithItsLine) {
  const std::string mesh_asset = "<asset><mesh name=\"m\" file=\"gone.stl\"/></asset>\n";
  const std::vector<Case> cases = {
      {"ball", hand("<body name=\"b\"><joint name=\"k\" type=\"ball\"/></body>\n"),
       "<joint name=\"k\"", "ball joints"},
      {"plane", hand("<geom type=\"plane\" size=\"1 1 1\"/>\n"), "type=\"plane\"", "plane geom"},
      {"hfield", hand("<geom type=\"hfield\"/>\n"), "type=\"hfield\"", "hfield geom"},
      {"connect",
       hand("", "",
            "<equality><connect body1=\"palm\" body2=\"finger\" anchor=\"0 0 0\"/></equality>\n"),
       "<connect", "close kinematic loops"},
      {"nonlinear",
       hand("<body name=\"b\"><joint name=\"k\" range=\"0 1\"/></body>\n", "",
            "<equality><joint joint1=\"k\" joint2=\"j\" polycoef=\"0 1 0.5 0 0\"/></equality>\n"),
       "polycoef", "non-linear"},
      {"lock", hand("", "", "<equality><joint joint1=\"j\"/></equality>\n"),
       "joint1=", "locks joint1"},
      {"section", hand("", "<robot/>\n"), "<robot", "not an MJCF section"},
      {"class", hand("<geom class=\"nope\" size=\"0.01\"/>\n"), "class=\"nope\"", "'nope'"},
      {"mesh", hand("<geom type=\"mesh\" mesh=\"m\"/>\n", mesh_asset), "type=\"mesh\"", "gone.stl"},
      {"fitted", hand("<geom type=\"box\" mesh=\"m\"/>\n", mesh_asset), "type=\"box\" mesh",
       "fitted"},
      {"slide", hand("<body name=\"b\"><joint name=\"s\" type=\"slide\"/></body>\n"), "name=\"s\"",
       "slide joint needs limits"},
      {"ref", hand("<body name=\"b\"><joint name=\"r\" ref=\"0.2\" range=\"0 1\"/></body>\n"),
       "name=\"r\"", "ref"},
      {"autolimits", hand("", "<compiler autolimits=\"false\"/>\n"), "<joint name=\"j\"",
       "autolimits"},
      {"size", hand("<geom type=\"box\" size=\"0.01 0 0.01\"/>\n"), "size=\"0.01 0 0.01\"",
       "positive"},
      {"actuator", hand("", "", "<actuator><position joint=\"nope\"/></actuator>\n"),
       "joint=\"nope\"", "names no hinge or slide joint"},
      {"tendon",
       hand("<body name=\"b\"><joint name=\"k\" range=\"0 1\"/></body>\n", "",
            "<tendon><fixed name=\"t\"><joint joint=\"j\" coef=\"1\"/><joint joint=\"k\" "
            "coef=\"1\"/></fixed></tendon>\n"
            "<actuator><position joint=\"k\"/><position tendon=\"t\"/></actuator>\n"),
       "tendon=\"t\"", "has its own actuator"},
      {"composite", hand("<composite type=\"grid\" count=\"2 2 1\"/>\n"), "<composite",
       "not supported"},
      {"top joint",
       "<mujoco>\n<worldbody>\n<body name=\"p\">\n<joint "
       "name=\"z\"/>\n</body>\n</worldbody>\n</mujoco>\n",
       "<joint", "top body has a joint"},
      {"two tops",
       "<mujoco>\n<worldbody>\n<body name=\"a\"/>\n<body name=\"b\"/>\n</worldbody>\n</mujoco>\n",
       "name=\"b\"", "a second body"},
      {"floor",
       "<mujoco>\n<worldbody>\n<geom type=\"plane\" size=\"1 1 1\"/>\n<body "
       "name=\"a\"/>\n</worldbody>\n</mujoco>\n",
       "<geom", "not part of a hand"},
      {"root", "<robot name=\"r\">\n</robot>\n", "<robot", "not <mujoco>"},
      {"malformed", "<mujoco>\n<worldbody>\n<body>\n</worldbody>\n</mujoco>\n", "</worldbody>",
       "malformed XML"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = write(std::string("case_") + c.name, "hand.xml", c.xml);
    const std::string e = refusal(path);
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
    EXPECT_NE(e.find(lineOf(c.xml, c.needle)), std::string::npos)
        << lineOf(c.xml, c.needle) << ": " << e;
  }
}

TEST(MjcfRefusal, IncludesStayInsideTheModelsFolderAndAreReadOnce) {
  // Outside the folder (also through a symbolic link).
  write("outside", "other.xml", "<mujoco/>");
  const std::string out =
      write("outside/model", "hand.xml", hand("", "<include file=\"../other.xml\"/>\n"));
  EXPECT_TRUE(testing::throwsError([&] { readMjcfModel(fileText(out), out); },
                                   {"outside the model's folder", "line 2"}));
  std::filesystem::create_symlink(
      "../other.xml", std::filesystem::path(kScratch.path("outside/model")) / "link.xml");
  const std::string via =
      write("outside/model", "via.xml", hand("", "<include file=\"link.xml\"/>\n"));
  EXPECT_TRUE(testing::throwsError([&] { readMjcfModel(fileText(via), via); },
                                   {"outside the model's folder"}));
  // A cycle: hand.xml -> a.xml -> b.xml -> a.xml; the error names b.xml's line.
  write("cycle", "a.xml", "<mujoco>\n<include file=\"b.xml\"/>\n</mujoco>\n");
  write("cycle", "b.xml", "<mujoco>\n\n<include file=\"a.xml\"/>\n</mujoco>\n");
  const std::string cyc = write("cycle", "hand.xml", hand("", "<include file=\"a.xml\"/>\n"));
  EXPECT_TRUE(testing::throwsError([&] { readMjcfModel(fileText(cyc), cyc); },
                                   {"included a second time", "line 3 of", "b.xml"}));
  // The model including itself.
  const std::string self = write("self", "hand.xml", hand("", "<include file=\"hand.xml\"/>\n"));
  EXPECT_TRUE(testing::throwsError([&] { readMjcfModel(fileText(self), self); },
                                   {"included a second time"}));
  // A missing include.
  const std::string gone = write("gone", "hand.xml", hand("", "<include file=\"nope.xml\"/>\n"));
  EXPECT_TRUE(
      testing::throwsError([&] { readMjcfModel(fileText(gone), gone); }, {"nope.xml", "line 2"}));
  // A chain of more files than the limit.
  for (std::size_t i = 0; i < kMaxMjcfFiles + 2; ++i)
    write("chain", "c" + std::to_string(i) + ".xml",
          "<mujoco><include file=\"c" + std::to_string(i + 1) + ".xml\"/></mujoco>");
  const std::string chain = write("chain", "hand.xml", hand("", "<include file=\"c0.xml\"/>\n"));
  EXPECT_TRUE(
      testing::throwsError([&] { readMjcfModel(fileText(chain), chain); }, {"more than 64 files"}));
}

TEST(MjcfRefusal, HostileSizesAreRefusedQuickly) {
  struct Hostile {
    const char* name;
    std::string xml;
    const char* says;
  };
  std::string deep = "<mujoco><worldbody>", wide, many = "<mujoco><worldbody><body name=\"p\">";
  for (int i = 0; i < 100000; ++i) deep += "<body>";
  std::string sites;
  for (int i = 0; i < 30000; ++i) sites += "<site/>";
  wide = hand(sites);
  for (int i = 0; i < 300; ++i)
    many += "<body name=\"b" + std::to_string(i) + "\"><joint range=\"0 1\"/></body>";
  many += "</body></worldbody></mujoco>";
  const std::vector<Hostile> cases = {{"deep", deep, "nested more than 64"},
                                      {"wide", wide, "more than 20000 XML elements"},
                                      {"many", many, "more than 256 links"}};
  for (const Hostile& h : cases) {
    SCOPED_TRACE(h.name);
    const std::string path = write(std::string("hostile_") + h.name, "hand.xml", h.xml);
    const double t0 = testing::cpuSeconds();
    const std::string e = refusal(path);
    EXPECT_LT(testing::cpuSeconds() - t0, 1.0);
    EXPECT_NE(e.find(h.says), std::string::npos) << e;
    EXPECT_NE(e.find(path), std::string::npos) << e;
  }
  // Nesting across files: 40 levels in the model, 40 in its include.
  std::string inner = "<mujoco>", outer = "<mujoco><worldbody><body name=\"p\">";
  for (int i = 0; i < 40; ++i) inner += "<body>";
  for (int i = 0; i < 40; ++i) inner += "</body>";
  inner += "</mujoco>";
  for (int i = 0; i < 40; ++i) outer += "<body>";
  outer += "<include file=\"inner.xml\"/>";
  for (int i = 0; i < 40; ++i) outer += "</body>";
  outer += "</body></worldbody></mujoco>";
  write("across", "inner.xml", inner);
  const std::string across = write("across", "hand.xml", outer);
  EXPECT_TRUE(testing::throwsError([&] { readMjcfModel(fileText(across), across); },
                                   {"nested more than 64", "inner.xml"}));
}

TEST(MjcfRefusal, AMissingCollisionMeshIsAnErrorAndAMissingVisualOneAWarning) {
  const std::string assets =
      "<asset><mesh name=\"v\" file=\"visual.obj\"/><mesh name=\"c\" "
      "file=\"collision.obj\"/></asset>\n";
  const std::string visual =
      write("meshes", "visual.xml",
            hand("<geom type=\"mesh\" mesh=\"v\" contype=\"0\" conaffinity=\"0\"/>\n", assets));
  const MjcfModel m = readMjcfModel(fileText(visual), visual);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("visual.obj"), std::string::npos) << m.warnings[0];
  const std::string xml = hand("<geom type=\"mesh\" mesh=\"c\"/>\n", assets);
  const std::string collision = write("meshes", "collision.xml", xml);
  EXPECT_TRUE(testing::throwsError(
      [&] { HandModel::loadKinematics(collision); },
      {"collision.xml", "collision.obj", "does not exist", lineOf(xml, "mesh=\"c\"")}));
}

}  // namespace
}  // namespace taskmap
