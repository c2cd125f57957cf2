// Squeeze balance (docs/METHOD.md §4b). Unknowns: non-negative weights a_ik of the cone edges
// d_ik = -n_i + mu (cos(2 pi k / m) t1_i + sin(2 pi k / m) t2_i) of each contact, so the force
// the hand applies at contact i is f_i = sum_k a_ik d_ik (inside the linearised cone).
// Equations, all in newtons:
//   object:  sum_i f_i = -w_f,   sum_i (p_i - c) x f_i / r = -w_t        (6 rows)
//   joints:  s_j (sum_i J_ij . f_i - e_j) / l_j = 0  for every joint j some contact loads
// w = 0 and s_j = 1 for the squeeze; w = a test push and s_j = push_joint_weight for a push.
// Non-negative least squares gives the closest equilibrium; the relative residual
// |A a - b| / |b| is 0 when the efforts are balanced exactly and 1 when no contact force helps.
#include "taskmap/quality/squeeze_balance.hpp"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Unit tangents t1, t2 orthogonal to unit n (any fixed choice: the cone is symmetric).
void tangents(const Eigen::Vector3d& n, Eigen::Vector3d* t1, Eigen::Vector3d* t2) {
  Eigen::Index k = 0;
  n.cwiseAbs().minCoeff(&k);
  *t1 = n.cross(Eigen::Vector3d::Unit(k)).normalized();
  *t2 = n.cross(*t1);
}

/// The equation system's columns: rows 0..5 the object wrench of each edge, then one row per
/// loaded joint (J . d / lever); `loaded` lists those joints.
struct System {
  Eigen::MatrixXd a;
  std::vector<Eigen::Index> loaded;
};

System buildSystem(const std::vector<Contact>& contacts, const SqueezeDrive& drive,
                   const Eigen::Vector3d& com, double torque_scale,
                   const SqueezeBalanceOptions& o) {
  const Eigen::Index joints = drive.effort.size();
  System s;
  for (Eigen::Index j = 0; j < joints; ++j) {
    bool used = false;
    for (const auto& jac : drive.jacobians) used = used || !jac.row(j).isZero(0.0);
    if (used) s.loaded.push_back(j);
  }
  const auto m = static_cast<Eigen::Index>(o.cone_edges);
  s.a.setZero(6 + static_cast<Eigen::Index>(s.loaded.size()),
              static_cast<Eigen::Index>(contacts.size()) * m);
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Eigen::Vector3d n = contacts[i].normal.normalized();
    Eigen::Vector3d t1, t2;
    tangents(n, &t1, &t2);
    const Eigen::Vector3d arm = (contacts[i].point - com) / torque_scale;
    for (Eigen::Index k = 0; k < m; ++k) {
      const double phi = 2.0 * kPi * static_cast<double>(k) / static_cast<double>(m);
      const Eigen::Vector3d d = -n + o.friction * (std::cos(phi) * t1 + std::sin(phi) * t2);
      const Eigen::Index col = static_cast<Eigen::Index>(i) * m + k;
      s.a.block<3, 1>(0, col) = d;
      s.a.block<3, 1>(3, col) = arm.cross(d);
      for (std::size_t r = 0; r < s.loaded.size(); ++r) {
        const Eigen::Index j = s.loaded[r];
        s.a(6 + static_cast<Eigen::Index>(r), col) =
            drive.jacobians[i].row(j).dot(d) / drive.lever(j);
      }
    }
  }
  return s;
}

/// Relative residual of the system with object wrench `w` (the hand must cancel it) and joint
/// rows weighted by `joint_weight`.
double relativeResidual(const System& s, const SqueezeDrive& drive,
                        const Eigen::Matrix<double, 6, 1>& w, double joint_weight) {
  Eigen::MatrixXd a = s.a;
  Eigen::VectorXd b(a.rows());
  b.head<6>() = -w;
  for (std::size_t r = 0; r < s.loaded.size(); ++r) {
    const auto row = 6 + static_cast<Eigen::Index>(r);
    const Eigen::Index j = s.loaded[r];
    a.row(row) *= joint_weight;
    b(row) = joint_weight * drive.effort(j) / drive.lever(j);
  }
  const double norm = b.norm();
  if (norm <= 0.0) return 0.0;
  double residual = 0.0;
  nonNegativeLeastSquares(a, b, &residual);
  return std::min(1.0, residual / norm);
}

void checkSizes(const std::vector<Contact>& contacts, const SqueezeDrive& drive) {
  if (drive.jacobians.size() != contacts.size())
    throw Error("squeezeBalance: " + std::to_string(drive.jacobians.size()) +
                " contact jacobians for " + std::to_string(contacts.size()) +
                " contacts; pass one per contact");
  if (drive.lever.size() != drive.effort.size())
    throw Error("squeezeBalance: lever and effort sizes differ; pass one of each per joint");
  for (const auto& jac : drive.jacobians)
    if (jac.rows() != drive.effort.size())
      throw Error("squeezeBalance: a contact jacobian has " + std::to_string(jac.rows()) +
                  " rows for " + std::to_string(drive.effort.size()) + " joints");
  if ((drive.lever.array() <= 0.0).any())
    throw Error("squeezeBalance: every joint lever must be > 0 (metres; 1 for prismatic)");
}

}  // namespace

void SqueezeBalanceOptions::validate() const {
  if (!(friction >= 0.0) || !std::isfinite(friction))
    throw Error("squeeze balance: friction must be finite and >= 0");
  if (cone_edges < 3) throw Error("squeeze balance: cone_edges must be >= 3");
  if (!(squeeze_tolerance >= 0.0 && squeeze_tolerance <= 1.0))
    throw Error("squeeze balance: squeeze_tolerance must be in [0, 1]");
  if (!(push_tolerance >= 0.0 && push_tolerance <= 1.0))
    throw Error("squeeze balance: push_tolerance must be in [0, 1]");
  if (!(push_force >= 0.0) || !std::isfinite(push_force))
    throw Error("squeeze balance: push_force must be finite and >= 0 (newtons; 0: no pushes)");
  if (!(squeeze_joint_weight > 0.0 && squeeze_joint_weight <= 1.0))
    throw Error("squeeze balance: squeeze_joint_weight must be in (0, 1]");
  if (!(push_joint_weight > 0.0 && push_joint_weight <= 1.0))
    throw Error("squeeze balance: push_joint_weight must be in (0, 1]");
}

Eigen::VectorXd nonNegativeLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                        double* residual) {
  const Eigen::Index n = a.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(static_cast<std::size_t>(n), false);
  const double tol = 1e-10 * (1.0 + a.cwiseAbs().maxCoeff()) * (1.0 + b.norm());
  Eigen::VectorXd r = b;
  for (Eigen::Index outer = 0; outer < 3 * n + 10; ++outer) {
    const Eigen::VectorXd w = a.transpose() * r;
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[static_cast<std::size_t>(j)] && w(j) > tol && (best < 0 || w(j) > w(best)))
        best = j;
    if (best < 0) break;
    passive[static_cast<std::size_t>(best)] = true;
    for (int inner = 0; inner < 3 * n + 10; ++inner) {
      std::vector<Eigen::Index> cols;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)]) cols.push_back(j);
      Eigen::MatrixXd ap(a.rows(), static_cast<Eigen::Index>(cols.size()));
      for (std::size_t c = 0; c < cols.size(); ++c)
        ap.col(static_cast<Eigen::Index>(c)) = a.col(cols[c]);
      const Eigen::VectorXd z = ap.completeOrthogonalDecomposition().solve(b);
      if ((z.array() > 0.0).all()) {
        x.setZero();
        for (std::size_t c = 0; c < cols.size(); ++c) x(cols[c]) = z(static_cast<Eigen::Index>(c));
        break;
      }
      // Step from x towards z until the first passive weight reaches zero.
      double alpha = 1.0;
      for (std::size_t c = 0; c < cols.size(); ++c) {
        const double zc = z(static_cast<Eigen::Index>(c)), xc = x(cols[c]);
        if (zc <= 0.0) alpha = std::min(alpha, xc / (xc - zc));
      }
      for (std::size_t c = 0; c < cols.size(); ++c) {
        const Eigen::Index j = cols[c];
        x(j) += alpha * (z(static_cast<Eigen::Index>(c)) - x(j));
        if (x(j) <= tol) {
          x(j) = 0.0;
          passive[static_cast<std::size_t>(j)] = false;
        }
      }
    }
    r = b - a * x;
  }
  if (residual != nullptr) *residual = (b - a * x).norm();
  return x;
}

SqueezeBalanceResult squeezeBalance(const std::vector<Contact>& contacts, const SqueezeDrive& drive,
                                    const Eigen::Vector3d& center_of_mass, double torque_scale,
                                    const SqueezeBalanceOptions& options) {
  options.validate();
  checkSizes(contacts, drive);
  if (!(torque_scale > 0.0)) throw Error("squeezeBalance: torque_scale must be > 0 (metres)");
  SqueezeBalanceResult result;
  if (contacts.empty()) return result;
  const System s = buildSystem(contacts, drive, center_of_mass, torque_scale, options);
  result.squeeze_residual =
      relativeResidual(s, drive, Eigen::Matrix<double, 6, 1>::Zero(), options.squeeze_joint_weight);
  result.balanced = result.squeeze_residual <= options.squeeze_tolerance;
  if (options.push_force <= 0.0) return result;
  for (int k = 0; k < 6; ++k) {
    Eigen::Matrix<double, 6, 1> w = Eigen::Matrix<double, 6, 1>::Zero();
    w(k / 2) = (k % 2 == 0 ? -1.0 : 1.0) * options.push_force;
    const double rho = relativeResidual(s, drive, w, options.push_joint_weight);
    result.push_residual = std::max(result.push_residual, rho);
    if (rho > options.push_tolerance && result.failed_push < 0) result.failed_push = k;
  }
  result.balanced = result.balanced && result.failed_push < 0;
  return result;
}

}  // namespace taskmap
