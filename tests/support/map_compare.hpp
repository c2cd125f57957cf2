#pragma once
// GoogleTest comparison of two task maps, value by value.
#include <gtest/gtest.h>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap::testing {

/// Every stored value of two maps; created_utc only when asked (it is the wall clock unless the
/// build asked for a reproducible time).
inline void expectSameMapContent(const TaskMapData& a, const TaskMapData& b,
                                 bool compare_created_utc = false) {
  EXPECT_EQ(a.generator, b.generator);
  if (compare_created_utc) {
    EXPECT_EQ(a.created_utc, b.created_utc);
  }
  EXPECT_EQ(a.object.name, b.object.name);
  EXPECT_EQ(a.object.source_sha256, b.object.source_sha256);
  EXPECT_EQ(a.object.scale, b.object.scale);
  EXPECT_EQ(a.object.volume, b.object.volume);
  EXPECT_EQ(a.object.center_of_mass, b.object.center_of_mass);
  EXPECT_EQ(a.object.torque_scale, b.object.torque_scale);
  EXPECT_EQ(a.object.vertices, b.object.vertices);
  EXPECT_EQ(a.object.faces, b.object.faces);
  EXPECT_EQ(a.hand.name, b.hand.name);
  EXPECT_EQ(a.hand.urdf_sha256, b.hand.urdf_sha256);
  EXPECT_EQ(a.hand.joint_names, b.hand.joint_names);
  EXPECT_EQ(a.sampling.sampler, b.sampling.sampler);
  EXPECT_EQ(a.sampling.seed, b.sampling.seed);
  EXPECT_EQ(a.sampling.trials, b.sampling.trials);
  EXPECT_EQ(a.sampling.outcomes, b.sampling.outcomes);
  EXPECT_EQ(a.sampling.params_json, b.sampling.params_json);
  EXPECT_EQ(a.quality.friction, b.quality.friction);
  EXPECT_EQ(a.quality.cone_edges, b.quality.cone_edges);
  EXPECT_EQ(a.quality.contact_model, b.quality.contact_model);
  const MapGrasps &g = a.grasps, &h = b.grasps;
  EXPECT_EQ(g.pose, h.pose);
  EXPECT_EQ(g.joints, h.joints);
  EXPECT_EQ(g.joints.cols(), h.joints.cols());
  EXPECT_EQ(g.force_closure, h.force_closure);
  EXPECT_EQ(g.epsilon, h.epsilon);
  EXPECT_EQ(g.volume, h.volume);
  EXPECT_EQ(g.contact_offsets, h.contact_offsets);
  EXPECT_EQ(g.contact_points, h.contact_points);
  EXPECT_EQ(g.contact_normals, h.contact_normals);
  EXPECT_EQ(g.contact_depths, h.contact_depths);
  EXPECT_EQ(g.contact_links, h.contact_links);
  EXPECT_EQ(g.contacts_available, h.contacts_available);
  EXPECT_EQ(g.rotation_scale, h.rotation_scale);
  ASSERT_EQ(a.clustering.has_value(), b.clustering.has_value());
  if (!a.clustering) return;
  const ClusteringResult &c = *a.clustering, &d = *b.clustering;
  EXPECT_EQ(c.labels, d.labels);
  EXPECT_EQ(c.linkage, d.linkage);
  EXPECT_EQ(c.method, d.method);
  EXPECT_EQ(c.rotation_scale, d.rotation_scale);
  EXPECT_EQ(c.threshold, d.threshold);
  EXPECT_EQ(c.min_size, d.min_size);
  ASSERT_EQ(c.clusters.size(), d.clusters.size());
  for (std::size_t j = 0; j < c.clusters.size(); ++j) {
    EXPECT_EQ(c.clusters[j].size, d.clusters[j].size);
    EXPECT_EQ(c.clusters[j].representative, d.clusters[j].representative);
    EXPECT_EQ(c.clusters[j].mean_pose.toVector7(), d.clusters[j].mean_pose.toVector7());
    EXPECT_EQ(c.clusters[j].mean_epsilon, d.clusters[j].mean_epsilon);
    EXPECT_EQ(c.clusters[j].best_epsilon, d.clusters[j].best_epsilon);
    EXPECT_EQ(c.clusters[j].bounds_min, d.clusters[j].bounds_min);
    EXPECT_EQ(c.clusters[j].bounds_max, d.clusters[j].bounds_max);
  }
}

}  // namespace taskmap::testing
