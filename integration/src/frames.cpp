#include "taskmap/integration/frames.hpp"

#include "taskmap/core/error.hpp"

namespace taskmap {

Pose handInObject(const Pose& hand_world, const Pose& object_world) {
  const Eigen::Quaterniond qo = object_world.orientation.normalized();
  Pose x;
  x.position = qo.conjugate() * (hand_world.position - object_world.position);
  x.orientation = (qo.conjugate() * hand_world.orientation.normalized()).normalized();
  return x;
}

Twist handGradientToWorld(const Twist& gradient_object, const Pose& object_world) {
  // x = (R_wo^T (p_wh - p_wo), R_wo^T R_wh): a world perturbation (dp, dw) of the hand gives
  // dp_x = R_wo^T dp and R_wo^T exp(dw) R_wh = exp(R_wo^T dw) R_x, so g_world = R_wo g.
  const Eigen::Matrix3d r = object_world.orientation.normalized().toRotationMatrix();
  Twist g;
  g.head<3>() = r * gradient_object.head<3>();
  g.tail<3>() = r * gradient_object.tail<3>();
  return g;
}

Twist objectGradientToWorld(const Twist& gradient_object, const Pose& hand_world,
                            const Pose& object_world) {
  // Object perturbed by (a, b): p_wo <- p_wo + a, R_wo <- exp(b) R_wo. Then
  // dp_x = -R_wo^T a + R_wo^T (d x b), d = p_wh - p_wo, and R_x <- exp(-R_wo^T b) R_x.
  const Eigen::Matrix3d r = object_world.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d d = hand_world.position - object_world.position;
  const Eigen::Vector3d gl = r * gradient_object.head<3>();
  Twist g;
  g.head<3>() = -gl;
  g.tail<3>() = gl.cross(d) - r * gradient_object.tail<3>();
  return g;
}

Eigen::VectorXd chainToJoints(const Twist& gradient_world, const Eigen::MatrixXd& jacobian) {
  if (jacobian.rows() != 6)
    throw Error("Jacobian has " + std::to_string(jacobian.rows()) +
                " rows; expected 6 (linear then angular, world frame)");
  return jacobian.transpose() * gradient_world;
}

Eigen::VectorXd jointGradient(const Twist& gradient_object, const Pose& hand_world,
                              const Pose& object_world, const Eigen::MatrixXd& hand_jacobian,
                              const Eigen::MatrixXd& object_jacobian) {
  Eigen::VectorXd g =
      chainToJoints(handGradientToWorld(gradient_object, object_world), hand_jacobian);
  if (object_jacobian.cols() > 0) {
    if (object_jacobian.cols() != hand_jacobian.cols())
      throw Error("object Jacobian has " + std::to_string(object_jacobian.cols()) +
                  " columns but the hand Jacobian has " + std::to_string(hand_jacobian.cols()) +
                  "; both must span the same joints");
    g += chainToJoints(objectGradientToWorld(gradient_object, hand_world, object_world),
                       object_jacobian);
  }
  return g;
}

}  // namespace taskmap
