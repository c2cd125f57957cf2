// Force closure and Ferrari-Canny epsilon of a grasp (docs/METHOD.md §2 step 5, §4).
//
// Cone edges (GraspIt!'s convention): contact with outward unit normal n pushes along -n; edge
// j of m is  f_j = -n + mu (cos(2 pi j / m) t1 + sin(2 pi j / m) t2),  a unit normal force plus
// mu times a unit tangent. Because the edges average to -n, the hull only grows with mu (the
// edges at mu' < mu are convex combinations of those at mu), so epsilon is non-decreasing in mu.
//
// Tangent basis (deterministic and covariant under rigid motions of contacts and object):
//   t1 = the component of (c - p) orthogonal to n, normalised (points from the contact towards
//        the centre of mass within the tangent plane), when that component is longer than
//        kCovariantBasisMin * |c - p|;
//   otherwise (the normal line passes through c, e.g. every contact on a sphere about c)
//   t1 = normalise(n x e_k), e_k the axis of the normal's smallest |component| (lowest k on
//        ties), which is fixed to the object frame;
//   t2 = n x t1.
// Wrench of force f at p: (f, (p - c) x f / r).
//
// Soft finger: the m edges above plus two torsional edges (-n, +-gamma n / r): a normal unit
// force with the largest torsional moment gamma about the normal. Their hull is an inner
// (double-pyramid) approximation of the elliptic limit surface |f_t|^2/mu^2 + tau^2/gamma^2 <= 1.
//
// L1 norm: hull of the union of all edge wrenches. LInf norm: hull of the Minkowski sum of the
// contacts' sets {0} u edges (GraspIt!'s LInfGWS: every contact pushes with a normal force in
// [0, 1]); (edges + 1)^contacts points, so small contact sets only.
#include "taskmap/quality/grasp_quality.hpp"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/quality/contact_reduction.hpp"
#include "taskmap/quality/wrench_epsilon.hpp"

namespace taskmap {
namespace {

/// Below this relative length the (c - p) tangent component is too short to orient the cone.
constexpr double kCovariantBasisMin = 1e-6;
/// Normals shorter than this are rejected as zero; others are normalised.
constexpr double kMinNormalNorm = 1e-9;
/// LInf: largest Minkowski-sum size accepted.
constexpr long long kMaxLInfWrenches = 1LL << 21;

/// Scores a wrench set into `result` (status, message, force closure, epsilon, volume).
void scoreWrenches(const WrenchMatrix& w, const QualityOptions& options, QualityResult& result) {
  WrenchEpsilonOptions eo;
  eo.volume = options.volume;
  eo.closure_pretest = options.closure_pretest;
  const WrenchEpsilon e = wrenchEpsilon(w, eo);
  result.status = e.status;
  result.message = e.message;
  result.force_closure = e.force_closure;
  result.epsilon = e.epsilon;
  result.volume = e.volume;
}

bool hasPressure(const Contact& c) {
  return c.depth > 0.0;
}

void tangentBasis(const Eigen::Vector3d& n, const Eigen::Vector3d& lever_to_com,
                  Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  const Eigen::Vector3d in_plane = lever_to_com - lever_to_com.dot(n) * n;
  const double len = in_plane.norm();
  if (len > kCovariantBasisMin * lever_to_com.norm() && len > 0.0) {
    t1 = in_plane / len;
  } else {
    int k = 0;
    for (int i = 1; i < 3; ++i) {
      if (std::abs(n(i)) < std::abs(n(k))) k = i;
    }
    t1 = n.cross(Eigen::Vector3d::Unit(k)).normalized();
  }
  t2 = n.cross(t1);
}

int edgesPerContact(const QualityOptions& o) {
  const bool torsion = o.contact_model == ContactModel::kSoftFinger && o.torsional_friction > 0.0;
  return o.cone_edges + (torsion ? 2 : 0);
}

/// Appends the edge wrenches of one pressing contact at columns [col, col + edges).
void appendContactWrenches(const Contact& contact, const Eigen::Vector3d& com, double r,
                           const QualityOptions& o, WrenchMatrix& w, Eigen::Index col) {
  const Eigen::Vector3d n = contact.normal.normalized();
  const Eigen::Vector3d lever = contact.point - com;
  Eigen::Vector3d t1, t2;
  tangentBasis(n, -lever, t1, t2);
  const int m = o.cone_edges;
  for (int j = 0; j < m; ++j) {
    const double a = 2.0 * kPi * j / m;
    const Eigen::Vector3d f = -n + o.friction * (std::cos(a) * t1 + std::sin(a) * t2);
    w.col(col + j) << f, lever.cross(f) / r;
  }
  if (edgesPerContact(o) > m) {
    const Eigen::Vector3d f = -n;
    const Eigen::Vector3d tau = lever.cross(f);
    const Eigen::Vector3d torsion = o.torsional_friction * n;
    w.col(col + m) << f, (tau + torsion) / r;
    w.col(col + m + 1) << f, (tau - torsion) / r;
  }
}

/// Checks the pressing contacts; returns an empty string when they are usable.
std::string checkContacts(const std::vector<Contact>& contacts, const Eigen::Vector3d& com) {
  if (!com.allFinite()) return "centre of mass is NaN or infinite";
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    if (!std::isfinite(c.depth) || !c.point.allFinite() || !c.normal.allFinite()) {
      return "contact " + std::to_string(i) + " has a NaN or infinite point, normal or depth";
    }
    if (hasPressure(c) && c.normal.norm() < kMinNormalNorm) {
      return "contact " + std::to_string(i) + " has a zero normal";
    }
  }
  return {};
}

void checkTorqueScale(double torque_scale) {
  if (!std::isfinite(torque_scale) || !(torque_scale > 0.0)) {
    throw Error("evaluateGrasp: torque_scale must be a finite length > 0 (metres), got " +
                std::to_string(torque_scale) + "; pass the object's MassProperties::torque_scale");
  }
}

}  // namespace

void QualityOptions::validate() const {
  if (!std::isfinite(friction) || friction < 0.0) {
    throw Error("friction (--friction) must be finite and >= 0 (Coulomb mu), got " +
                std::to_string(friction));
  }
  if (cone_edges < 3 || cone_edges > 1024) {
    throw Error("cone_edges (--cone-edges) must be in [3, 1024] (GraspIt! uses 8), got " +
                std::to_string(cone_edges));
  }
  if (!std::isfinite(torsional_friction) || torsional_friction < 0.0) {
    throw Error("QualityOptions.torsional_friction must be finite and >= 0 (metres), got " +
                std::to_string(torsional_friction));
  }
  if (contact_model != ContactModel::kPointWithFriction &&
      contact_model != ContactModel::kSoftFinger) {
    throw Error("QualityOptions.contact_model is not a known ContactModel value");
  }
  if (volume != VolumeMode::kForceClosure && volume != VolumeMode::kAlways &&
      volume != VolumeMode::kNever) {
    throw Error("QualityOptions.volume is not a known VolumeMode value");
  }
  if (norm != WrenchNorm::kL1 && norm != WrenchNorm::kLInf) {
    throw Error("QualityOptions.norm is not a known WrenchNorm value");
  }
  if (contacts_per_link < 0 || contacts_per_link > 1024) {
    throw Error("QualityOptions.contacts_per_link must be in [0, 1024] (0 = every contact), got " +
                std::to_string(contacts_per_link));
  }
  if (max_linf_contacts < 1 || max_linf_contacts > 12) {
    throw Error("QualityOptions.max_linf_contacts must be in [1, 12], got " +
                std::to_string(max_linf_contacts));
  }
}

const char* toString(QualityStatus status) {
  switch (status) {
    case QualityStatus::kOk:
      return "ok";
    case QualityStatus::kNoContacts:
      return "no_contacts";
    case QualityStatus::kDegenerate:
      return "degenerate";
    case QualityStatus::kInvalidInput:
      return "invalid_input";
    case QualityStatus::kHullFailed:
      return "hull_failed";
  }
  return "unknown";
}

const char* toString(ContactModel model) {
  switch (model) {
    case ContactModel::kPointWithFriction:
      return "point_with_friction";
    case ContactModel::kSoftFinger:
      return "soft_finger";
  }
  return "unknown";
}

ContactModel contactModelFromString(const std::string& name) {
  if (name == "point_with_friction") return ContactModel::kPointWithFriction;
  if (name == "soft_finger") return ContactModel::kSoftFinger;
  throw Error("unknown contact model '" + name + "'; use 'point_with_friction' or 'soft_finger'");
}

const char* toString(VolumeMode mode) {
  switch (mode) {
    case VolumeMode::kForceClosure:
      return "force_closure";
    case VolumeMode::kAlways:
      return "always";
    case VolumeMode::kNever:
      return "never";
  }
  return "unknown";
}

VolumeMode volumeModeFromString(const std::string& name) {
  if (name == "force_closure") return VolumeMode::kForceClosure;
  if (name == "always") return VolumeMode::kAlways;
  if (name == "never") return VolumeMode::kNever;
  throw Error("unknown volume mode '" + name + "'; use 'never', 'force_closure' or 'always'");
}

WrenchMatrix contactWrenches(const std::vector<Contact>& contacts,
                             const Eigen::Vector3d& center_of_mass, double torque_scale,
                             const QualityOptions& options) {
  options.validate();
  checkTorqueScale(torque_scale);
  const std::string problem = checkContacts(contacts, center_of_mass);
  if (!problem.empty()) throw Error("contactWrenches: " + problem);
  Eigen::Index pressing = 0;
  for (const Contact& c : contacts) pressing += hasPressure(c);
  const int e = edgesPerContact(options);
  WrenchMatrix w(6, pressing * e);
  Eigen::Index col = 0;
  for (const Contact& c : contacts) {
    if (!hasPressure(c)) continue;
    appendContactWrenches(c, center_of_mass, torque_scale, options, w, col);
    col += e;
  }
  return w;
}

QualityResult evaluateGrasp(const std::vector<Contact>& contacts,
                            const Eigen::Vector3d& center_of_mass, double torque_scale,
                            const QualityOptions& options) {
  options.validate();
  checkTorqueScale(torque_scale);
  QualityResult result;
  const std::string problem = checkContacts(contacts, center_of_mass);
  if (!problem.empty()) {
    result.status = QualityStatus::kInvalidInput;
    result.message = problem;
    return result;
  }
  const WrenchMatrix edges =
      options.contacts_per_link > 0
          ? contactWrenches(reduceContactsPerLink(contacts, options.contacts_per_link),
                            center_of_mass, torque_scale, options)
          : contactWrenches(contacts, center_of_mass, torque_scale, options);
  const int e = edgesPerContact(options);
  const Eigen::Index used = edges.cols() / e;
  result.contacts_used = static_cast<int>(used);
  if (used == 0) {
    result.status = QualityStatus::kNoContacts;
    result.message = contacts.empty() ? "no contacts" : "no contact carries pressure (depth > 0)";
    return result;
  }

  if (options.norm == WrenchNorm::kL1) {
    scoreWrenches(edges, options, result);
    return result;
  }

  // LInf: Minkowski sum over contacts of {0} u (the contact's edges), (e + 1)^used points:
  // every contact pushes with a normal force between 0 and 1 (GraspIt!'s LInfGWS).
  if (used > options.max_linf_contacts) {
    result.status = QualityStatus::kInvalidInput;
    result.message =
        "LInf norm: " + std::to_string(used) +
        " contacts exceed max_linf_contacts = " + std::to_string(options.max_linf_contacts) +
        "; use the L1 norm or raise max_linf_contacts";
    return result;
  }
  const int choices = e + 1;  // choice 0: the zero wrench
  long long total = 1;
  for (Eigen::Index i = 0; i < used; ++i) {
    total *= choices;
    if (total > kMaxLInfWrenches) {
      result.status = QualityStatus::kInvalidInput;
      result.message = "LInf norm: the Minkowski sum would exceed " +
                       std::to_string(kMaxLInfWrenches) +
                       " wrenches; use fewer cone edges, fewer contacts or the L1 norm";
      return result;
    }
  }
  WrenchMatrix sum(6, total);
  std::vector<int> digit(static_cast<std::size_t>(used), 0);
  for (long long k = 0; k < total; ++k) {
    Eigen::Matrix<double, 6, 1> s = Eigen::Matrix<double, 6, 1>::Zero();
    for (Eigen::Index i = 0; i < used; ++i) {
      if (digit[i] > 0) s += edges.col(i * e + digit[i] - 1);
    }
    sum.col(k) = s;
    for (Eigen::Index i = 0; i < used; ++i) {  // odometer increment
      if (++digit[i] < choices) break;
      digit[i] = 0;
    }
  }
  scoreWrenches(sum, options, result);
  return result;
}

}  // namespace taskmap
