#pragma once
/// @file squeeze_balance.hpp
/// Squeeze balance: can the forces a position-controlled hand presses with hold a free object
/// in equilibrium, and resist test pushes? (docs/METHOD.md §4b, equations and sources there.)
/// Contact forces are cone-edge combinations (friction mu, m edges) found by non-negative least
/// squares; the test is the relative residual of the equilibrium equations. Thread-safe.

#include <vector>

#include <Eigen/Core>

#include "taskmap/core/contact.hpp"

namespace taskmap {

/// Options of the squeeze-balance test.
struct SqueezeBalanceOptions {
  double friction = 0.6;  ///< Coulomb friction coefficient mu of the test (DexGraspBench: 0.6)
  int cone_edges = 8;     ///< linearised friction-cone edges, >= 3
  /// Weight of the joint equations of the squeeze relative to the object's (in (0, 1]): below 1
  /// the efforts may drift as the object settles against the compliant fingers.
  double squeeze_joint_weight = 1.0;
  /// Largest relative residual of the squeeze equilibrium that counts as balanced, in [0, 1].
  double squeeze_tolerance = 0.4;
  /// Test pushes: force at the centre of mass along +-x, +-y, +-z of the object frame, newtons
  /// (DexGraspBench: 10 x 0.1 kg = 1 N); 0 skips the push test.
  double push_force = 1.0;
  /// Largest relative residual of a push equilibrium that counts as resisted, in [0, 1].
  double push_tolerance = 0.2;
  /// Weight of the joint equations under a push relative to the squeeze (in (0, 1]): position
  /// control lets joints give under a push, so their torques may drift from the squeeze's.
  double push_joint_weight = 0.25;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// How the hand drives the contacts: for contact i, generalised force on the actuated joints per
/// newton of force the hand applies to the object at the contact point,
/// `jacobians[i]` (joints x 3, object-frame force in, N m or N out: J_i = dp_i/dq transposed),
/// and the effort `effort[j]` the actuator of joint j applies at the grasp (N m or N, along
/// increasing q). `lever[j]` (metres, > 0; 1 for prismatic joints) turns joint equations into
/// newtons. Joints that no contact loads are unconstrained.
struct SqueezeDrive {
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 3>> jacobians;  ///< one per contact
  Eigen::VectorXd effort;                                           ///< per actuated joint
  Eigen::VectorXd lever;                                            ///< per actuated joint
};

/// Outcome of the squeeze-balance test.
struct SqueezeBalanceResult {
  bool balanced = false;          ///< squeeze residual and every push residual within tolerance
  double squeeze_residual = 1.0;  ///< relative residual of the squeeze equilibrium, [0, 1]
  double push_residual = 0.0;     ///< largest relative residual over the six pushes, [0, 1]
  int failed_push = -1;           ///< first push (-x, +x, -y, +y, -z, +z) over tolerance, or -1
};

/// Tests a grasp: contacts in the object frame (points in metres, outward unit normals; every
/// contact may carry force), the drive of its links, the object's centre of mass and torque
/// scale r (metres, > 0). Throws Error on sizes that do not match.
SqueezeBalanceResult squeezeBalance(const std::vector<Contact>& contacts, const SqueezeDrive& drive,
                                    const Eigen::Vector3d& center_of_mass, double torque_scale,
                                    const SqueezeBalanceOptions& options = {});

/// Non-negative least squares (Lawson and Hanson 1974, ch. 23): x >= 0 minimising |A x - b|.
/// Returns x; `residual` (if given) receives |A x - b|.
Eigen::VectorXd nonNegativeLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                        double* residual = nullptr);

}  // namespace taskmap
