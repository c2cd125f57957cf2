#pragma once
/// @file robust_hold.hpp
/// Does a grasp hold for a robot? The hold test (hold_test.hpp) at the grasp's pose and under the
/// errors a robot and a mesh bring: the palm moved and turned a little, lower friction, the
/// object as another convex decomposition; each with a margin (under the pushes the object stays
/// close to where the closing left it). Variants, thresholds and what they measured:
/// docs/VALIDATION.md, "The robust label". Units: metres, radians.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap {

/// One way a grasp is perturbed for the robust test.
struct HoldVariant {
  /// What the variant changes.
  enum class Kind : std::uint8_t {
    kNominal,        ///< nothing: the protocol at the stored pose (with the margin)
    kPalmShift,      ///< the palm moved by `amount` metres along palm axis `axis`
    kPalmTurn,       ///< the palm turned by `amount` radians about palm axis `axis`
    kFriction,       ///< every geom's sliding friction `amount` instead of the protocol's
    kDecomposition,  ///< the object as its second convex decomposition (RobustHoldOptions)
  };
  Kind kind = Kind::kNominal;  ///< see Kind
  int axis = 0;                ///< palm axis 0, 1, 2 (x, y, z) of a shift or turn
  double amount = 0.0;         ///< metres (shift, signed), radians (turn, signed) or friction
  /// Short name: "nominal", "shift+x", "shift-z", "turn+y", "friction", "decomposition".
  std::string name() const;
  /// The palm pose this variant tests for a grasp at `palm` (object frame): `palm` moved or
  /// turned in its own frame; `palm` itself for the other kinds.
  Pose apply(const Pose& palm) const;
};

/// The variants, the margin and how far to test.
struct RobustHoldOptions {
  /// The protocol (docs/VALIDATION.md); its margin fields are replaced by the ones below.
  HoldTestOptions hold;
  double palm_shift = 0.001;  ///< m: variants with the palm moved +- this along each palm axis
  double palm_turn = 0.03490658503988659;  ///< rad (2 deg): turned +- this about each palm axis
  double friction = 0.5;  ///< sliding friction of the friction variant (0: no such variant)
  /// The second decomposition: the object simplified to this many faces and merged into at most
  /// decomposition_pieces pieces (0: no such variant). Skipped when it gives the same pieces as
  /// the protocol's (a convex object is its hull both times).
  int decomposition_faces = 300;
  int decomposition_pieces = 16;                 ///< see decomposition_faces, in [1, 64]
  double margin_translation = 0.01;              ///< m, from the closed state under a push
  double margin_rotation = 0.08726646259971647;  ///< rad (5 deg), from the closed state
  /// Test every variant, also after one failed (the share of variants held is exact); false:
  /// stop at the first failure (a build needs only the verdict).
  bool all_variants = false;
  /// When the nominal variant fails by the margin only, run it again without the margin, so
  /// that RobustHoldResult::nominal is the protocol's label (`taskmap validate --robust`);
  /// false (builds, which keep robust grasps only): `nominal` is the run with the margin.
  bool protocol_label = true;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// Outcome of the robust test of one grasp.
struct RobustHoldResult {
  /// The protocol at the stored pose, without the margin: what `taskmap validate` labels.
  HoldResult nominal;
  bool robust = false;  ///< every variant held within the protocol's thresholds and the margin
  int tested = 0;       ///< variants tested (the nominal one included)
  int held = 0;         ///< of them, variants that held with the margin
  /// Per variant (RobustHoldTester::variants() order): 1 held, 0 failed, 255 not tested.
  std::vector<std::uint8_t> variant_held;
  /// Largest displacement of the object from its closed state under the pushes, over the
  /// variants tested, metres (the margin it used).
  double push_translation = 0.0;
  double push_rotation = 0.0;  ///< same for the rotation, radians
  long long steps = 0;         ///< simulation steps of all variants
  /// held / tested (0 when none was tested).
  double share() const;
};

/// Runs the robust test for one hand and one object: one HoldTester per model the variants need
/// (the protocol's, the friction variant's, the second decomposition's). test() is const and
/// thread-safe, and its result depends on its arguments only.
class RobustHoldTester {
 public:
  /// Throws Error when the options are invalid or MuJoCo refuses a model.
  RobustHoldTester(const HandModel& hand, const ObjectModel& object,
                   const RobustHoldOptions& options = {});
  ~RobustHoldTester();
  RobustHoldTester(RobustHoldTester&&) noexcept;
  RobustHoldTester& operator=(RobustHoldTester&&) noexcept;

  /// Tests the grasp (palm frame in the object frame, actuated joints in
  /// HandModel::jointNames() order): the nominal variant first (without the margin, for its
  /// protocol label, then with it), then the others in variants() order.
  RobustHoldResult test(const Pose& palm, const Eigen::VectorXd& joints) const;

  /// The variants in test order (nominal first); the decomposition variant only when its
  /// pieces differ from the protocol's.
  const std::vector<HoldVariant>& variants() const;
  /// The protocol's tester (the nominal variant's model).
  const HoldTester& nominal() const;
  /// The options in force.
  const RobustHoldOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The variants of `options` in test order (nominal first), the second decomposition's last
/// when `with_decomposition` (RobustHoldTester::variants() gives the list a tester runs).
std::vector<HoldVariant> robustVariants(const RobustHoldOptions& options, bool with_decomposition);

/// The variants and thresholds as a JSON object (what /validation robust_json stores): variants
/// (their names), palm_shift (m), palm_turn (rad), friction, decomposition_faces,
/// decomposition_pieces, margin_translation (m), margin_rotation (rad).
std::string robustParamsJson(const RobustHoldOptions& options,
                             const std::vector<HoldVariant>& variants);

}  // namespace taskmap
