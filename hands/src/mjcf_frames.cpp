// MJCF orientations (mjcf_reader.hpp): quat, axisangle, euler (with the compiler's eulerseq),
// xyaxes and zaxis, as MuJoCo's compiler turns them into a quaternion; angles in the compiler's
// unit.
#include <cmath>

#include "mjcf_reader.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::detail {
namespace {

constexpr const char* kForms[] = {"quat", "axisangle", "euler", "xyaxes", "zaxis"};

Eigen::Vector3d unit(const MjcfDocument& doc, const MjcfAttr& a, const char* name,
                     const Eigen::Vector3d& v) {
  if (!(v.norm() > 1e-12)) doc.fail(a.at, std::string(name) + " must not be a zero vector");
  return v.normalized();
}

Eigen::Quaterniond euler(const MjcfCompiler& c, const std::vector<double>& v) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (int i = 0; i < 3; ++i) {
    const char axis = c.eulerseq[static_cast<std::size_t>(i)];
    const double angle =
        c.degrees ? v[static_cast<std::size_t>(i)] * kPi / 180.0 : v[static_cast<std::size_t>(i)];
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    w[(axis | 0x20) - 'x'] = 1.0;
    const Eigen::Quaterniond r(Eigen::AngleAxisd(angle, w));
    // Lower case: axes that move with the frame (post-multiply); upper case: fixed axes.
    q = (axis >= 'a') ? q * r : r * q;
  }
  return q;
}

Eigen::Quaterniond xyaxes(const MjcfDocument& doc, const MjcfAttr& a,
                          const std::vector<double>& v) {
  const Eigen::Vector3d x = unit(doc, a, "xyaxes' x", Eigen::Vector3d(v[0], v[1], v[2]));
  Eigen::Vector3d y(v[3], v[4], v[5]);
  y -= x * x.dot(y);
  y = unit(doc, a, "xyaxes' y (orthogonalised to x)", y);
  Eigen::Matrix3d m;
  m << x, y, x.cross(y);
  return Eigen::Quaterniond(m);
}

}  // namespace

Eigen::Quaterniond mjcfZToDirection(const Eigen::Vector3d& d) {
  const Eigen::Vector3d v = d.normalized();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(v);
  const double s = axis.norm();
  if (s < 1e-10)
    axis = Eigen::Vector3d::UnitX();
  else
    axis /= s;
  return Eigen::Quaterniond(Eigen::AngleAxisd(std::atan2(s, v.z()), axis));
}

Eigen::Quaterniond mjcfOrientation(const MjcfDocument& doc, const MjcfDefaults& defaults,
                                   const MjcfCompiler& compiler, const TiXmlElement* e,
                                   const std::vector<const char*>& tags, int cls) {
  // The element's own form; else (for defaultable elements) the nearest class's.
  std::optional<MjcfAttr> found;
  const char* form = nullptr;
  for (const char* f : kForms) {
    if (!e->Attribute(f)) continue;
    if (form) doc.fail(e, std::string("has both ") + form + " and " + f + ": give one orientation");
    form = f;
    found = MjcfAttr{e->Attribute(f), e};
  }
  if (!form && !tags.empty())
    for (const char* f : kForms)
      if (auto d = defaults.find(e, tags, cls, f)) {
        form = f;
        found = d;
        break;
      }
  if (!form) return Eigen::Quaterniond::Identity();
  const std::string name = form;
  if (name == "quat") {
    const auto v = mjcfNumbers(doc, *found, form, 4, 4);
    Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
    if (!(q.norm() > 1e-12)) doc.fail(found->at, "quat must not be zero");
    return q.normalized();
  }
  if (name == "axisangle") {
    const auto v = mjcfNumbers(doc, *found, form, 4, 4);
    const Eigen::Vector3d axis = unit(doc, *found, "axisangle's axis", {v[0], v[1], v[2]});
    return Eigen::Quaterniond(
        Eigen::AngleAxisd(compiler.degrees ? v[3] * kPi / 180.0 : v[3], axis));
  }
  if (name == "euler") return euler(compiler, mjcfNumbers(doc, *found, form, 3, 3));
  if (name == "xyaxes") return xyaxes(doc, *found, mjcfNumbers(doc, *found, form, 6, 6));
  const auto v = mjcfNumbers(doc, *found, form, 3, 3);
  return mjcfZToDirection(unit(doc, *found, "zaxis", {v[0], v[1], v[2]}));
}

}  // namespace taskmap::detail
