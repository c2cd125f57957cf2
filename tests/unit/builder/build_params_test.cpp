// The build parameters (builder/src/build_params.cpp): every stored field written and read
// back, a built map's params_json read back into its options, the bytes of a checked-in map
// written again unchanged, and the errors on values of the wrong type.
#include "taskmap/builder/build_params.hpp"

#include <string>

#include <gtest/gtest.h>

#include "build_fixtures.hpp"
#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

// Every field a map stores, compared one by one (the oracle: a field missing from the JSON
// comes back as its default and fails here, since allChanged() sets none to its default).
void expectSameParams(const BuildParams& a, const BuildParams& b) {
  const BuildOptions& x = a.options;
  const BuildOptions& y = b.options;
  EXPECT_EQ(a.object, b.object);
  EXPECT_EQ(a.scale, b.scale);
  EXPECT_EQ(a.hand, b.hand);
  EXPECT_EQ(x.sampler.kind, y.sampler.kind);
  EXPECT_EQ(x.sampler.standoff_min, y.sampler.standoff_min);
  EXPECT_EQ(x.sampler.standoff_max, y.sampler.standoff_max);
  EXPECT_EQ(x.sampler.approach_axis, y.sampler.approach_axis);
  EXPECT_EQ(x.seed, y.seed);
  EXPECT_EQ(x.valid_target, y.valid_target);
  EXPECT_EQ(x.max_trials, y.max_trials);
  EXPECT_EQ(x.stored, y.stored);
  EXPECT_EQ(x.cluster, y.cluster);
  EXPECT_EQ(x.quality.friction, y.quality.friction);
  EXPECT_EQ(x.quality.cone_edges, y.quality.cone_edges);
  EXPECT_EQ(x.quality.contact_model, y.quality.contact_model);
  EXPECT_EQ(x.quality.torsional_friction, y.quality.torsional_friction);
  EXPECT_EQ(x.quality.norm, y.quality.norm);
  const HoldFilterOptions& h = x.hold_filter;
  const HoldFilterOptions& k = y.hold_filter;
  EXPECT_EQ(h.enabled, k.enabled);
  EXPECT_EQ(h.kp_revolute, k.kp_revolute);
  EXPECT_EQ(h.kp_prismatic, k.kp_prismatic);
  EXPECT_EQ(h.jaw_force, k.jaw_force);
  EXPECT_EQ(h.revolute_gripper_force, k.revolute_gripper_force);
  EXPECT_EQ(h.squeeze_fraction, k.squeeze_fraction);
  EXPECT_EQ(h.balance.friction, k.balance.friction);
  EXPECT_EQ(h.balance.cone_edges, k.balance.cone_edges);
  EXPECT_EQ(h.balance.squeeze_tolerance, k.balance.squeeze_tolerance);
  EXPECT_EQ(h.balance.push_force, k.balance.push_force);
  EXPECT_EQ(h.balance.push_tolerance, k.balance.push_tolerance);
  EXPECT_EQ(h.balance.push_joint_weight, k.balance.push_joint_weight);
  const ClosingCheckOptions& cc = x.closing_check;
  const ClosingCheckOptions& cd = y.closing_check;
  EXPECT_EQ(cc.mode, cd.mode);
  EXPECT_EQ(cc.object_mass, cd.object_mass);
  EXPECT_EQ(cc.friction, cd.friction);
  EXPECT_EQ(cc.kp_revolute, cd.kp_revolute);
  EXPECT_EQ(cc.damping_revolute, cd.damping_revolute);
  EXPECT_EQ(cc.kp_prismatic, cd.kp_prismatic);
  EXPECT_EQ(cc.damping_prismatic, cd.damping_prismatic);
  EXPECT_EQ(cc.jaw_force, cd.jaw_force);
  EXPECT_EQ(cc.revolute_gripper_force, cd.revolute_gripper_force);
  EXPECT_EQ(cc.push_order, cd.push_order);
  EXPECT_EQ(cc.push_free_bound, cd.push_free_bound);
  EXPECT_EQ(cc.push_bound_creep, cd.push_bound_creep);
  EXPECT_EQ(cc.link_density, cd.link_density);
  EXPECT_EQ(cc.pregrasp_fraction, cd.pregrasp_fraction);
  EXPECT_EQ(cc.squeeze_fraction, cd.squeeze_fraction);
  EXPECT_EQ(cc.closing_time, cd.closing_time);
  EXPECT_EQ(cc.interpolation_stages, cd.interpolation_stages);
  EXPECT_EQ(cc.timestep, cd.timestep);
  EXPECT_EQ(cc.substeps, cd.substeps);
  EXPECT_EQ(cc.solver_iterations, cd.solver_iterations);
  EXPECT_EQ(cc.contact_erp, cd.contact_erp);
  EXPECT_EQ(cc.max_settle_steps, cd.max_settle_steps);
  EXPECT_EQ(cc.push_force, cd.push_force);
  EXPECT_EQ(cc.push_duration, cd.push_duration);
  EXPECT_EQ(cc.max_translation, cd.max_translation);
  EXPECT_EQ(cc.max_rotation, cd.max_rotation);
  EXPECT_EQ(cc.max_penetration, cd.max_penetration);
  EXPECT_EQ(cc.object_max_pieces, cd.object_max_pieces);
  EXPECT_EQ(cc.margin, cd.margin);
  const GraspSimOptions& s = x.simulation;
  const GraspSimOptions& t = y.simulation;
  EXPECT_EQ(s.contact_tolerance, t.contact_tolerance);
  EXPECT_EQ(s.max_retraction, t.max_retraction);
  EXPECT_EQ(s.squeeze, t.squeeze);
  EXPECT_EQ(s.require_palm_contact, t.require_palm_contact);
  EXPECT_EQ(s.grasp_mode, t.grasp_mode);
  EXPECT_EQ(s.standoff, t.standoff);
  EXPECT_EQ(s.centre_coupled, t.centre_coupled);
  EXPECT_EQ(s.check_self_collision, t.check_self_collision);
  EXPECT_EQ(s.max_closing_steps, t.max_closing_steps);
  const ClusteringOptions& c = x.clustering;
  const ClusteringOptions& d = y.clustering;
  EXPECT_EQ(c.method, d.method);
  EXPECT_EQ(c.fallback_to_single, d.fallback_to_single);
  EXPECT_EQ(c.outlier_budget, d.outlier_budget);
  EXPECT_EQ(c.min_size_fraction, d.min_size_fraction);
  EXPECT_EQ(c.min_size, d.min_size);
  EXPECT_EQ(c.threshold, d.threshold);
  EXPECT_EQ(c.num_clusters, d.num_clusters);
  EXPECT_EQ(x.extra_params_json, y.extra_params_json);
}

// Options with every stored field away from its default (fingertip grasps, hold filter on).
BuildOptions allChanged() {
  BuildOptions o;
  o.sampler.kind = SamplerKind::kSurface;
  o.sampler.standoff_min = 0.001;
  o.sampler.standoff_max = 0.03;
  o.seed = 77;
  o.valid_target = 12;
  o.max_trials = 3456;
  o.stored = StoredGrasps::kAllCompleted;
  o.cluster = false;
  o.quality.friction = 0.7;
  o.quality.cone_edges = 11;
  o.quality.contact_model = ContactModel::kSoftFinger;
  o.quality.torsional_friction = 0.002;
  o.quality.norm = WrenchNorm::kLInf;
  HoldFilterOptions& h = o.hold_filter;
  h.enabled = true;
  h.kp_revolute = 6.5;
  h.kp_prismatic = 21000.0;
  h.jaw_force = 65.0;
  h.revolute_gripper_force = true;
  h.squeeze_fraction = 1.2;
  h.balance.friction = 0.55;
  h.balance.cone_edges = 9;
  h.balance.squeeze_tolerance = 0.35;
  h.balance.push_force = 1.5;
  h.balance.push_tolerance = 0.25;
  h.balance.push_joint_weight = 0.3;
  ClosingCheckOptions& cc = o.closing_check;
  cc.mode = ClosingCheckMode::kPushes;
  cc.object_mass = 0.2;
  cc.friction = 0.5;
  cc.kp_revolute = 6.0;
  cc.damping_revolute = 0.2;
  cc.kp_prismatic = 15000.0;
  cc.damping_prismatic = 90.0;
  cc.jaw_force = 60.0;
  cc.revolute_gripper_force = false;
  cc.link_density = 700.0;
  cc.pregrasp_fraction = 0.8;
  cc.squeeze_fraction = 1.2;
  cc.closing_time = 0.6;
  cc.interpolation_stages = 8;
  cc.timestep = 0.003;
  cc.substeps = 3;
  cc.solver_iterations = 12;
  cc.contact_erp = 0.3;
  cc.max_settle_steps = 40;
  cc.push_force = 2.0;
  cc.push_duration = 0.3;
  cc.max_translation = 0.02;
  cc.max_rotation = 0.2;
  cc.max_penetration = 0.005;
  cc.object_max_pieces = 32;
  cc.margin = 4e-4;
  cc.push_order = {5, 4, 3, 2, 1, 0};
  cc.push_free_bound = true;
  cc.push_bound_creep = 0.025;
  GraspSimOptions& s = o.simulation;
  s.contact_tolerance = 7e-4;
  s.max_retraction = 0.05;
  s.squeeze = 0.005;
  s.require_palm_contact = false;
  s.grasp_mode = GraspMode::kFingertip;
  s.standoff = 0.0125;
  s.centre_coupled = false;
  s.check_self_collision = false;
  s.max_closing_steps = 3210;
  ClusteringOptions& c = o.clustering;
  c.method = Linkage::kComplete;
  c.fallback_to_single = false;
  c.outlier_budget = 0.07;
  c.min_size_fraction = 0.03;
  c.min_size = 4;
  c.threshold = 0.042;
  o.extra_params_json = R"({"hand":"panda","object":"box.obj","repair":false,"scale":0.01})";
  return o;
}

TEST(BuildParamsTest, EveryFieldRoundTrips) {
  const BuildParams p = buildParamsOf(allChanged(), testing::pandaHand());
  EXPECT_EQ(p.object, "box.obj");
  EXPECT_EQ(p.scale, 0.01);
  EXPECT_EQ(p.hand, "panda");
  EXPECT_EQ(p.options.extra_params_json, R"({"repair":false})");  // the keys it does not name
  EXPECT_EQ(p.options.sampler.approach_axis, testing::pandaHand().approachAxis());
  expectSameParams(p, buildParamsFromJson(buildParamsJson(p)));
  // Each field really was stored: none came back as its default.
  const BuildParams defaults = buildParamsFromJson("{}");
  EXPECT_NE(p.options.seed, defaults.options.seed);
  EXPECT_NE(p.options.hold_filter.balance.push_joint_weight,
            defaults.options.hold_filter.balance.push_joint_weight);
  EXPECT_NE(p.options.simulation.standoff, defaults.options.simulation.standoff);
  EXPECT_NE(p.options.closing_check.margin, defaults.options.closing_check.margin);
  EXPECT_NE(p.options.clustering.threshold, defaults.options.clustering.threshold);
  // The exclusive cut, the palm mode (no standoff stored) and the filter off.
  BuildOptions o = allChanged();
  o.clustering.threshold.reset();
  o.clustering.num_clusters = 5;
  o.simulation.grasp_mode = GraspMode::kPalm;
  o.hold_filter.enabled = false;
  const BuildParams q = buildParamsOf(o, testing::pandaHand());
  EXPECT_EQ(q.options.simulation.standoff, GraspSimOptions().standoff);
  EXPECT_FALSE(q.options.hold_filter.enabled);
  EXPECT_EQ(q.options.hold_filter.kp_revolute, HoldFilterOptions().kp_revolute);
  EXPECT_EQ(buildParamsJson(q).find("hold_filter"), std::string::npos);
  o.closing_check.mode = ClosingCheckMode::kOff;
  const BuildParams off = buildParamsOf(o, testing::pandaHand());
  EXPECT_EQ(buildParamsJson(off).find("\"closing_"), std::string::npos);
  EXPECT_EQ(buildParamsFromJson(buildParamsJson(off)).options.closing_check.mode,
            ClosingCheckMode::kOff);
  expectSameParams(q, buildParamsFromJson(buildParamsJson(q)));
}

/// `text` without the JSON member `"key":value` (compact JSON, the member not the last).
std::string withoutKey(std::string text, const std::string& key) {
  const std::size_t at = text.find("\"" + key + "\":");
  EXPECT_NE(at, std::string::npos) << key;
  if (at == std::string::npos) return text;
  return text.erase(at, text.find(',', at) + 1 - at);
}

// The closing check's revolute gripper drive (on by default) reads back off from a map written
// before the key existed; the hold filter's (off by default) round-trips in EveryFieldRoundTrips.
TEST(BuildParamsTest, TheRevoluteGripperDriveIsRecordedAndOffForOlderMaps) {
  BuildOptions o = allChanged();
  o.closing_check.revolute_gripper_force = true;
  const std::string text = buildParamsJson(buildParamsOf(o, testing::pandaHand()));
  const BuildParams now = buildParamsFromJson(text);
  EXPECT_TRUE(now.options.closing_check.revolute_gripper_force);
  // A map written before the keys existed was built with kp_revolute for every revolute joint.
  const BuildParams before =
      buildParamsFromJson(withoutKey(text, "closing_revolute_gripper_force"));
  EXPECT_FALSE(before.options.closing_check.revolute_gripper_force);
  EXPECT_EQ(before.options.closing_check.jaw_force, o.closing_check.jaw_force);
}

TEST(BuildParamsTest, ABuiltMapReadsBackIntoItsOptions) {
  BuildOptions o;
  o.seed = 5;
  o.valid_target = 3;
  o.max_trials = 2000;
  o.threads = 2;
  o.quality.friction = 0.6;
  o.clustering.min_size = 1;
  o.extra_params_json = R"({"object":"box.obj","scale":0.5,"hand":"panda"})";
  const BuildResult r = buildMap(testing::boxObject(), testing::pandaHand(), o);
  ASSERT_EQ(r.status, BuildStatus::kComplete) << r.message;
  const std::string path = ::testing::TempDir() + "/build_params_test.h5";
  writeMap(path, r.map);
  const TaskMapData back = readMap(path);
  const BuildParams read = buildParamsFromJson(back.sampling.params_json);
  expectSameParams(buildParamsOf(o, testing::pandaHand()), read);
  EXPECT_EQ(read.options.seed, 5U);
  EXPECT_EQ(read.scale, 0.5);
  EXPECT_EQ(read.options.simulation.grasp_mode, testing::pandaHand().graspMode());
  // No sampler named: the hand's, antipodal_palm for the panda's jaws, written as the one run;
  // mixed for a hand without jaws.
  EXPECT_EQ(back.sampling.sampler, "antipodal_palm");
  EXPECT_EQ(read.options.sampler.kind, SamplerKind::kAntipodalPalm);
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const BuildOptions defaults;
  EXPECT_EQ(buildParamsOf(defaults, barrett).options.sampler.kind, SamplerKind::kMixed);
  o.sampler.kind = SamplerKind::kVolume;
  EXPECT_EQ(buildParamsOf(o, testing::pandaHand()).options.sampler.kind, SamplerKind::kVolume);
  EXPECT_EQ(buildParamsJson(read), back.sampling.params_json);  // the same bytes again
}

TEST(BuildParamsTest, TheReferenceMapsParametersAreWrittenAgainByteForByte) {
  const TaskMapData map =
      readMap(std::string(TASKMAP_SOURCE_DIR) + "/meshes/maps/basket_humanoid.h5");
  const BuildParams p = buildParamsFromJson(map.sampling.params_json);
  EXPECT_FALSE(p.hand.empty());
  EXPECT_EQ(buildParamsJson(p), map.sampling.params_json);
}

TEST(BuildParamsTest, NamesAKeyOfTheWrongTypeAndKeepsUnknownKeys) {
  EXPECT_TRUE(testing::throwsError([] { buildParamsFromJson(R"({"seed": "seven"})"); },
                                   {"build parameter 'seed' has the wrong type"}));
  EXPECT_TRUE(testing::throwsError([] { buildParamsFromJson(R"({"sampler": "spiral"})"); },
                                   {"build parameter 'sampler' is not a sampler"}));
  EXPECT_TRUE(testing::throwsError([] { buildParamsFromJson(R"({"grasp_mode": "pinch"})"); },
                                   {"'grasp_mode' must be \"palm\" or \"fingertip\""}));
  const BuildParams imported = buildParamsFromJson(R"({"imported_from":"acronym","seed":3})");
  EXPECT_EQ(imported.options.seed, 3U);
  EXPECT_EQ(imported.options.extra_params_json, R"({"imported_from":"acronym"})");
  EXPECT_EQ(buildParamsFromJson("not json").options.seed, BuildOptions().seed);
}

// The hold test's integrator (docs/VALIDATION.md, "The integrator"): written only when it is not
// the default, so maps built with `implicit` keep their bytes; read back; a wrong name refused.
TEST(BuildParamsTest, TheHoldTestsIntegratorIsRecordedWhenNotTheDefault) {
  BuildOptions o;
  o.hold_test = BuildHoldTest::kRobust;
  EXPECT_EQ(buildParamsJson(buildParamsOf(o, testing::pandaHand())).find("hold_integrator"),
            std::string::npos);
  o.hold_test_options.hold.integrator = HoldTestOptions::Integrator::kImplicitFast;
  const std::string text = buildParamsJson(buildParamsOf(o, testing::pandaHand()));
  EXPECT_NE(text.find(R"("hold_integrator":"implicitfast")"), std::string::npos) << text;
  EXPECT_EQ(buildParamsFromJson(text).options.hold_test_options.hold.integrator,
            HoldTestOptions::Integrator::kImplicitFast);
  EXPECT_EQ(buildParamsJson(buildParamsFromJson(text)), text);
  EXPECT_TRUE(testing::throwsError(
      [] { buildParamsFromJson(R"({"hold_test":"robust","hold_integrator":"rk4"})"); },
      {"build parameter 'hold_integrator' is not a hold test integrator", "not 'rk4'"}));
}

}  // namespace
}  // namespace taskmap
