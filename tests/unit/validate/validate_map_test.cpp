// Labels of a built map: one per grasp, the same for any thread count, stored and read back;
// force-closure jaw grasps of a box mostly hold; the wrong hand is refused.
#include "taskmap/validate/validate_map.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "build_fixtures.hpp"
#include "error_matchers.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

const TaskMapData& boxMap() {
  static const TaskMapData map = [] {
    BuildOptions o;
    o.valid_target = 12;
    o.seed = 3;
    o.threads = 1;
    return buildMap(testing::boxObject(), testing::pandaHand(), o).map;
  }();
  return map;
}

TEST(ValidateMap, LabelsDoNotDependOnThreads) {
  TaskMapData one = boxMap(), two = boxMap();
  ValidateOptions o;
  o.threads = 1;
  const ValidationSummary a = validateMap(&one, testing::pandaHand(), o);
  o.threads = 2;
  const ValidationSummary b = validateMap(&two, testing::pandaHand(), o);
  ASSERT_TRUE(one.validation && two.validation);
  EXPECT_EQ(one.validation->hold, two.validation->hold);
  EXPECT_EQ(one.validation->translation, two.validation->translation);
  EXPECT_EQ(one.validation->rotation, two.validation->rotation);
  EXPECT_EQ(one.validation->direction, two.validation->direction);
  EXPECT_EQ(a.holding, b.holding);
  EXPECT_EQ(a.tested, boxMap().grasps.size());
  // Jaws pressing 70 N each on a 0.1 kg box: most force-closure grasps hold.
  EXPECT_GE(a.fc_holding * 2, a.fc_tested) << a.message;
}

TEST(ValidateMap, KeepHoldingKeepsTheHoldingRowsWithTheirContacts) {
  TaskMapData map = boxMap();
  ValidateOptions o;
  o.threads = 1;
  o.grasps = 6;  // 6 tested, the rest not tested (dropped too)
  validateMap(&map, testing::pandaHand(), o);
  std::vector<std::size_t> holding;
  for (std::size_t i = 0; i < map.grasps.size(); ++i)
    if (map.validation->hold[i] == 1) holding.push_back(i);
  ASSERT_FALSE(holding.empty());
  map.validation->hold[holding.front()] = 0;  // one more that does not hold
  map.validation->status[holding.front()] = 3;
  holding.erase(holding.begin());
  const TaskMapData before = map;
  EXPECT_EQ(keepHoldingGrasps(&map), holding.size());
  ASSERT_EQ(map.grasps.size(), holding.size());
  EXPECT_NO_THROW(map.validate());
  for (std::size_t k = 0; k < holding.size(); ++k) {
    const std::size_t i = holding[k];
    EXPECT_EQ(map.grasps.pose.row(static_cast<Eigen::Index>(k)),
              before.grasps.pose.row(static_cast<Eigen::Index>(i)));
    EXPECT_EQ(map.grasps.epsilon[k], before.grasps.epsilon[i]);
    EXPECT_EQ(map.validation->hold[k], 1);
    const auto n = before.grasps.contact_offsets[i + 1] - before.grasps.contact_offsets[i];
    ASSERT_EQ(map.grasps.contact_offsets[k + 1] - map.grasps.contact_offsets[k], n);
    EXPECT_EQ(map.grasps.contact_points.row(map.grasps.contact_offsets[k]),
              before.grasps.contact_points.row(before.grasps.contact_offsets[i]));
  }
  EXPECT_EQ(map.clustering.has_value(), holding.size() >= 2);
  if (map.clustering) {
    EXPECT_EQ(map.clustering->labels.size(), holding.size());
  }
  TaskMapData unlabelled = boxMap();
  EXPECT_TRUE(testing::throwsError([&] { keepHoldingGrasps(&unlabelled); },
                                   {"no hold labels", "validate it first"}));
}

// A map grasp's trace is the label validateMap gives it; an index past the grasps is refused.
TEST(ValidateMap, TraceOfAGraspIsItsLabelWithThePath) {
  TaskMapData map = boxMap();
  ValidateOptions o;
  o.threads = 1;
  o.grasps = 2;
  validateMap(&map, testing::pandaHand(), o);
  for (std::size_t i = 0; i < 2; ++i) {
    const HoldTrace t = traceGrasp(map, testing::pandaHand(), i);
    EXPECT_EQ(t.result.holds ? 1 : 0, map.validation->hold[i]);
    EXPECT_EQ(t.result.max_translation, map.validation->translation[i]);
    EXPECT_FALSE(t.samples.empty());
    const std::string json = traceJson(t, testing::pandaHand());
    EXPECT_NE(json.find("\"samples\""), std::string::npos);
    EXPECT_NE(traceText(t, testing::pandaHand()).find(holdStatusName(t.result.status)),
              std::string::npos);
  }
  EXPECT_TRUE(
      testing::throwsError([&] { traceGrasp(map, testing::pandaHand(), map.grasps.size()); },
                           {"grasp " + std::to_string(map.grasps.size()), "is not in the map"}));
}

TEST(ValidateMap, LabelsRoundTripThroughTheMapFile) {
  TaskMapData map = boxMap();
  ValidateOptions o;
  o.grasps = 4;
  const ValidationSummary s = validateMap(&map, testing::pandaHand(), o);
  EXPECT_EQ(s.tested, 4u);
  ASSERT_TRUE(map.validation);
  EXPECT_EQ(map.validation->tested(), 4u);
  EXPECT_EQ(map.validation->hold[5], MapValidation::kNotTested);
  EXPECT_EQ(map.validation->engine, "MuJoCo 2.2.2");
  const std::string path = ::testing::TempDir() + "validated_map.h5";
  writeMap(path, map);
  const TaskMapData back = readMap(path);
  ASSERT_TRUE(back.validation);
  EXPECT_EQ(back.validation->hold, map.validation->hold);
  EXPECT_EQ(back.validation->status, map.validation->status);
  EXPECT_EQ(back.validation->translation, map.validation->translation);
  EXPECT_EQ(back.validation->direction, map.validation->direction);
  EXPECT_EQ(back.validation->params_json, map.validation->params_json);
  std::remove(path.c_str());
}

TEST(ValidateMap, AMapWithoutLabelsReadsWithout) {
  const std::string path = ::testing::TempDir() + "plain_map.h5";
  writeMap(path, boxMap());
  EXPECT_FALSE(readMap(path).validation.has_value());
  std::remove(path.c_str());
}

TEST(ValidateMap, InconsistentLabelsAreRefused) {
  TaskMapData map = boxMap();
  ValidateOptions o;
  o.grasps = 2;
  validateMap(&map, testing::pandaHand(), o);
  map.validation->status[0] = map.validation->hold[0] == 1 ? 3 : 0;  // disagrees with hold
  EXPECT_TRUE(testing::throwsError([&] { map.validate(); }, {"/grasps/hold_status"}));
}

TEST(ValidateMap, RefusesAnotherHand) {
  TaskMapData map = boxMap();
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  EXPECT_TRUE(testing::throwsError([&] { validateMap(&map, barrett, ValidateOptions{}); },
                                   {"actuated joints", "the hand the map was built with"}));
}

TEST(ValidateMap, StopLeavesTheMapUnchanged) {
  TaskMapData map = boxMap();
  std::atomic<bool> stop{true};
  ValidateControl control;
  control.stop = &stop;
  const ValidationSummary s = validateMap(&map, testing::pandaHand(), ValidateOptions{}, control);
  EXPECT_EQ(s.status, ValidationSummary::Status::kInterrupted);
  EXPECT_FALSE(map.validation.has_value());
}

TEST(ValidateMap, ACallbackThatThrowsStopsTheRunAndLeavesTheMapUnchanged) {
  TaskMapData map = boxMap();
  ValidateOptions o;
  o.threads = 1;
  ValidateControl control;
  control.interval_seconds = 1e-3;
  int calls = 0;
  control.progress = [&calls](const ValidateProgress&) {
    ++calls;
    throw std::runtime_error("stop from the callback");
  };
  EXPECT_THROW(validateMap(&map, testing::pandaHand(), o, control), std::runtime_error);
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(map.validation.has_value());
}

TEST(ValidateMap, RefusesANonPositiveReportInterval) {
  TaskMapData map = boxMap();
  ValidateControl control;
  control.interval_seconds = 0.0;
  EXPECT_TRUE(testing::throwsError(
      [&] { validateMap(&map, testing::pandaHand(), ValidateOptions{}, control); },
      {"interval_seconds must be positive"}));
}

}  // namespace
}  // namespace taskmap
