#pragma once
// GoogleTest comparison of two task maps, value by value.
#include <gtest/gtest.h>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap::testing {

/// Every stored value of two maps except created_utc (wall clock unless the build asked for a
/// reproducible time).
inline void expectSameMapContent(const TaskMapData& a, const TaskMapData& b) {
  EXPECT_EQ(a.generator, b.generator);
  EXPECT_EQ(a.object.name, b.object.name);
  EXPECT_EQ(a.object.source_sha256, b.object.source_sha256);
  EXPECT_EQ(a.object.vertices, b.object.vertices);
  EXPECT_EQ(a.object.faces, b.object.faces);
  EXPECT_EQ(a.hand.urdf_sha256, b.hand.urdf_sha256);
  EXPECT_EQ(a.hand.joint_names, b.hand.joint_names);
  EXPECT_EQ(a.sampling.seed, b.sampling.seed);
  EXPECT_EQ(a.sampling.trials, b.sampling.trials);
  EXPECT_EQ(a.sampling.outcomes, b.sampling.outcomes);
  EXPECT_EQ(a.sampling.params_json, b.sampling.params_json);
  EXPECT_EQ(a.grasps.pose, b.grasps.pose);
  EXPECT_EQ(a.grasps.joints, b.grasps.joints);
  EXPECT_EQ(a.grasps.force_closure, b.grasps.force_closure);
  EXPECT_EQ(a.grasps.epsilon, b.grasps.epsilon);
  EXPECT_EQ(a.grasps.volume, b.grasps.volume);
  EXPECT_EQ(a.grasps.contact_offsets, b.grasps.contact_offsets);
  EXPECT_EQ(a.grasps.contact_points, b.grasps.contact_points);
  EXPECT_EQ(a.grasps.contact_normals, b.grasps.contact_normals);
  EXPECT_EQ(a.grasps.contact_depths, b.grasps.contact_depths);
  EXPECT_EQ(a.grasps.contact_links, b.grasps.contact_links);
  ASSERT_EQ(a.clustering.has_value(), b.clustering.has_value());
  if (!a.clustering) return;
  EXPECT_EQ(a.clustering->labels, b.clustering->labels);
  EXPECT_EQ(a.clustering->linkage, b.clustering->linkage);
  EXPECT_EQ(a.clustering->threshold, b.clustering->threshold);
  ASSERT_EQ(a.clustering->clusters.size(), b.clustering->clusters.size());
  for (std::size_t k = 0; k < a.clustering->clusters.size(); ++k) {
    EXPECT_EQ(a.clustering->clusters[k].representative, b.clustering->clusters[k].representative);
    EXPECT_EQ(a.clustering->clusters[k].mean_epsilon, b.clustering->clusters[k].mean_epsilon);
  }
}

}  // namespace taskmap::testing
