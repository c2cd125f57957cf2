// The hand report (`taskmap hand-info`): its JSON against the loaded model, the text against the
// JSON, the closed configuration against the joint limits, and the options' errors.
#include "taskmap/inspect/hand_info.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "error_matchers.hpp"

namespace taskmap {
namespace {

using testing::throwsError;

std::string bundled(const std::string& name) {
  return std::string(TASKMAP_HANDS_DIR) + "/" + name + "/" + name + ".urdf";
}

TEST(HandInfo, JsonDescribesTheLoadedModel) {
  for (const char* name : {"barrett", "humanoid", "panda"}) {
    HandInfoOptions options;
    options.hand = bundled(name);
    const HandInfo info = handInfo(options);
    const HandModel hand = HandModel::load(options.hand);
    const nlohmann::json j = nlohmann::json::parse(info.json);
    EXPECT_EQ(j["name"], hand.name()) << name;
    EXPECT_EQ(j["urdf_sha256"], hand.urdfSha256());
    EXPECT_EQ(j["joints"].size(), hand.joints().size());
    EXPECT_EQ(j["rotation_scale"].get<double>(), hand.rotationScale());
    EXPECT_EQ(j["warnings"].size(), info.report.warnings.size());
    EXPECT_EQ(info.status,
              info.report.warnings.empty() ? HandInfo::Status::kOk : HandInfo::Status::kWarnings);
    // The text prints the same fields: the name line and one line per joint.
    EXPECT_EQ(info.text.rfind("hand:           " + hand.name() + " (URDF robot '", 0), 0u)
        << info.text;
    for (const auto& joint : j["joints"])
      EXPECT_NE(info.text.find("  " + joint["name"].get<std::string>() + " "), std::string::npos);
  }
}

TEST(HandInfo, ClosedConfigurationIsWithinTheLimits) {
  const HandModel hand = HandModel::load(bundled("barrett"));
  const Eigen::VectorXd closed = closedConfiguration(hand);
  const nlohmann::json j = nlohmann::json::parse(handInfo(hand).json);
  int actuated = 0;
  for (const auto& joint : j["joints"]) {
    if (!joint.contains("actuated")) continue;
    ++actuated;
    EXPECT_GE(joint["closed"].get<double>(), joint["lower"].get<double>() - 1e-12);
    EXPECT_LE(joint["closed"].get<double>(), joint["upper"].get<double>() + 1e-12);
  }
  EXPECT_EQ(actuated, closed.size());
}

TEST(HandInfo, MissingHandIsNamed) {
  HandInfoOptions options;
  options.hand = "/nonexistent/hand.urdf";
  EXPECT_TRUE(throwsError([&] { handInfo(options); },
                          {"hand '/nonexistent/hand.urdf' does not exist", "URDF"}));
}

}  // namespace
}  // namespace taskmap
