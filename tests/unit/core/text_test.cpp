// core/text.hpp: printf into strings of any length, numbers and poses parsed from text, with
// messages that name the option.
#include "taskmap/core/text.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {
namespace {

using testing::throwsError;

TEST(FormattedTest, MatchesSnprintfAndHasNoLengthLimit) {
  char expected[64];
  std::snprintf(expected, sizeof expected, "%-4d|%.3f|%s|%zu", 7, 3.14159, "x", std::size_t{9});
  EXPECT_EQ(formatted("%-4d|%.3f|%s|%zu", 7, 3.14159, "x", std::size_t{9}), expected);
  const std::string long_word(5000, 'a');
  const std::string s = formatted("<%s>", long_word.c_str());
  ASSERT_EQ(s.size(), 5002u);
  EXPECT_EQ(s.substr(1, 5000), long_word);
  EXPECT_EQ(formatted("%s", ""), "");
}

TEST(ParseNumbersTest, ReadsWhiteSpaceSeparatedNumbers) {
  const Eigen::VectorXd v = parseNumbers(" 0.5 -1e-3\t2 ", -1, "--start");
  ASSERT_EQ(v.size(), 3);
  EXPECT_EQ(v[0], 0.5);
  EXPECT_EQ(v[1], -1e-3);
  EXPECT_EQ(v[2], 2.0);
  EXPECT_EQ(parseNumbers("", -1, "--start").size(), 0);
}

TEST(ParseNumbersTest, RefusesWordsCountsAndNonFiniteValuesNamingTheOption) {
  EXPECT_TRUE(throwsError([] { parseNumbers("1 2x 3", -1, "--start"); }, {"--start", "'2x'"}));
  EXPECT_TRUE(
      throwsError([] { parseNumbers("1 2", 3, "--start"); }, {"--start needs 3 numbers, got 2"}));
  EXPECT_TRUE(throwsError([] { parseNumbers("1 inf", -1, "--via"); }, {"--via", "finite"}));
}

TEST(ParsePoseTextTest, ReadsPositionAndNormalisedQuaternion) {
  const Eigen::Isometry3d t = parsePoseText("0.1 0.2 0.3 2 0 0 0", "--target");
  EXPECT_TRUE(t.translation().isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE(t.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_TRUE(throwsError([] { parsePoseText("0 0 0 1 0 0", "--target"); },
                          {"--target needs 7 numbers, got 6"}));
  EXPECT_TRUE(throwsError([] { parsePoseText("0 0 0 0 0 0 0", "--mount"); },
                          {"--mount \"x y z qw qx qy qz\""}));
}

TEST(ParseXyzYawTest, TurnsAboutZAndNeedsExactlyFourNumbers) {
  const Eigen::Isometry3d t = parseXyzYaw("0.5 -0.2 0.1 1.5707963267948966", "--object-pose");
  EXPECT_TRUE(t.translation().isApprox(Eigen::Vector3d(0.5, -0.2, 0.1)));
  EXPECT_TRUE((t.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE(throwsError([] { parseXyzYaw("1 2 3", "--object-pose"); },
                          {"--object-pose needs 4 finite numbers"}));
  EXPECT_TRUE(throwsError([] { parseXyzYaw("1 2 3 4 5", "--object-pose"); },
                          {"--object-pose needs exactly 4 numbers"}));
  EXPECT_TRUE(throwsError([] { parseXyzYaw("1 2 nan 4", "--object-pose"); }, {"finite"}));
}

}  // namespace
}  // namespace taskmap
