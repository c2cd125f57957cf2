// ClosingChecker: options, names, and the public entry (the Bullet work is in closing_model.cpp
// and closing_world.cpp).
#include "taskmap/grasp_sim/closing_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "closing_model.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

void positive(double v, const char* name, const char* unit) {
  if (!(v > 0.0 && std::isfinite(v)))
    throw Error(std::string("closing check option ") + name + " must be a positive number" + unit +
                ", got " + std::to_string(v));
}

}  // namespace

const char* toString(ClosingCheckMode mode) {
  switch (mode) {
    case ClosingCheckMode::kOff:
      return "off";
    case ClosingCheckMode::kClosing:
      return "closing";
    case ClosingCheckMode::kPushes:
      return "pushes";
  }
  return "unknown";
}

ClosingCheckMode closingCheckModeFromString(const std::string& name) {
  if (name == "off") return ClosingCheckMode::kOff;
  if (name == "closing") return ClosingCheckMode::kClosing;
  if (name == "pushes") return ClosingCheckMode::kPushes;
  throw Error("closing check mode must be \"off\", \"closing\" or \"pushes\", got \"" + name +
              "\"");
}

void ClosingCheckOptions::validate() const {
  if (mode != ClosingCheckMode::kOff && mode != ClosingCheckMode::kClosing &&
      mode != ClosingCheckMode::kPushes)
    throw Error("closing check option mode must be off, closing or pushes");
  positive(object_mass, "object_mass", " (kg)");
  positive(friction, "friction", "");
  if (!(torsional_friction >= 0.0 && std::isfinite(torsional_friction)))
    throw Error("closing check option torsional_friction must be >= 0 (m; 0: none), got " +
                std::to_string(torsional_friction));
  positive(kp_revolute, "kp_revolute", " (N m / rad)");
  positive(damping_revolute, "damping_revolute", " (N m s / rad)");
  positive(kp_prismatic, "kp_prismatic", " (N / m)");
  positive(damping_prismatic, "damping_prismatic", " (N s / m)");
  positive(jaw_force, "jaw_force", " (N)");
  positive(link_density, "link_density", " (kg / m^3)");
  positive(closing_time, "closing_time", " (s)");
  positive(timestep, "timestep", " (s)");
  positive(max_translation, "max_translation", " (m)");
  positive(max_rotation, "max_rotation", " (rad)");
  positive(max_penetration, "max_penetration", " (m)");
  positive(margin, "margin", " (m)");
  positive(push_force, "push_force", " (N)");
  positive(push_duration, "push_duration", " (s)");
  if (!(contact_erp > 0.0 && contact_erp <= 1.0))
    throw Error("closing check option contact_erp must be in (0, 1], got " +
                std::to_string(contact_erp));
  if (!(settle_erp > 0.0 && settle_erp <= 1.0))
    throw Error("closing check option settle_erp must be in (0, 1], got " +
                std::to_string(settle_erp));
  if (!(pregrasp_fraction >= 0.0 && pregrasp_fraction <= 1.0))
    throw Error("closing check option pregrasp_fraction must be in [0, 1], got " +
                std::to_string(pregrasp_fraction));
  if (!(squeeze_fraction >= 1.0 && squeeze_fraction <= 2.0))
    throw Error("closing check option squeeze_fraction must be in [1, 2], got " +
                std::to_string(squeeze_fraction));
  if (interpolation_stages < 1 || substeps < 1 || solver_iterations < 1)
    throw Error(
        "closing check options interpolation_stages, substeps and solver_iterations must be >= 1, "
        "got " +
        std::to_string(interpolation_stages) + ", " + std::to_string(substeps) + " and " +
        std::to_string(solver_iterations));
  if (jaws.solver_iterations < 0)
    throw Error(
        "closing check option jaws.solver_iterations must be >= 0 (0: solver_iterations), "
        "got " +
        std::to_string(jaws.solver_iterations));
  if (!std::isfinite(jaws.torsional_friction))
    throw Error(
        "closing check option jaws.torsional_friction must be a number (m; < 0: "
        "torsional_friction)");
  if (!(rest_speed >= 0.0 && std::isfinite(rest_speed)))
    throw Error("closing check option rest_speed must be >= 0 (m/s; 0: no early end), got " +
                std::to_string(rest_speed));
  std::array<int, 6> sorted = push_order;
  std::sort(sorted.begin(), sorted.end());
  if (sorted != std::array<int, 6>{0, 1, 2, 3, 4, 5})
    throw Error(
        "closing check option push_order must name each push direction 0..5 (-x, +x, -y, +y, "
        "-z, +z) once");
  if (!(push_bound_creep >= 0.0 && std::isfinite(push_bound_creep)))
    throw Error("closing check option push_bound_creep must be >= 0 (m/s; 0: no condition), got " +
                std::to_string(push_bound_creep));
  if (rest_steps < 1)
    throw Error("closing check option rest_steps must be >= 1, got " + std::to_string(rest_steps));
  if (max_settle_steps < 0)
    throw Error("closing check option max_settle_steps must be >= 0, got " +
                std::to_string(max_settle_steps));
  if (object_max_pieces < 1 || object_max_pieces > 64)
    throw Error("closing check option object_max_pieces must be in [1, 64], got " +
                std::to_string(object_max_pieces));
  if (timestep / substeps * interpolation_stages > 0.5 * closing_time)
    throw Error("closing check: timestep / substeps must be at most closing_time / (2 x " +
                std::string("interpolation_stages); lower timestep or raise closing_time"));
}

ClosingCheckOptions ClosingCheckOptions::earlyVerdict() {
  ClosingCheckOptions o;
  o.mode = ClosingCheckMode::kPushes;
  o.timestep = 0.008;
  o.substeps = 1;
  o.solver_iterations = 4;
  o.closing_time = 0.1;
  o.interpolation_stages = 5;
  o.max_settle_steps = 10;
  o.settle_erp = 0.8;
  o.push_duration = 0.05;
  o.rest_speed = 0.005;
  o.rest_steps = 2;
  o.jaws.solver_iterations = 20;
  o.jaws.torsional_friction = 0.02;
  o.jaws.warm_start_drives = true;
  return o;
}

ClosingChecker::ClosingChecker(const ObjectModel& object, const HandModel& hand,
                               const ClosingCheckOptions& options)
    : model_(std::make_unique<Model>(object, hand, options)) {}

ClosingChecker::~ClosingChecker() = default;

ClosingCheckResult ClosingChecker::check(const Pose& palm, const Eigen::VectorXd& joints) const {
  const auto n = static_cast<Eigen::Index>(model_->hand.jointNames().size());
  if (joints.size() != n)
    throw Error("closing check: " + std::to_string(joints.size()) + " joint values for hand '" +
                model_->hand.name() + "' with " + std::to_string(n) + " actuated joints");
  return model_->run(palm, joints);
}

int ClosingChecker::objectPieces() const {
  return model_->object_pieces;
}

const ClosingCheckOptions& ClosingChecker::options() const {
  return model_->options;
}

}  // namespace taskmap
