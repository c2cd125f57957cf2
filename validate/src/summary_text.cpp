// The validation summary as text (validate/validate_map.hpp summaryText).
#include <cmath>
#include <cstdio>
#include <sstream>

#include "taskmap/validate/validate_map.hpp"

namespace taskmap {
namespace {

std::string percent(std::size_t k, std::size_t n) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f %%",
                n ? 100.0 * static_cast<double>(k) / static_cast<double>(n) : 0.0);
  return b;
}

}  // namespace

std::string summaryText(const ValidationSummary& s, const std::string& written_to) {
  std::ostringstream os;
  os << "taskmap validate: " << s.holding << " of " << s.tested << " grasps hold ("
     << percent(s.holding, s.tested) << "); force-closure grasps: " << s.fc_holding << " of "
     << s.fc_tested << " (" << percent(s.fc_holding, s.fc_tested) << ")\n";
  if (!s.variant_failures.empty()) {
    os << "  robust (every variant holds within the margin): " << s.robust << " of " << s.tested
       << " (" << percent(s.robust, s.tested) << "); force-closure grasps: " << s.fc_robust
       << " of " << s.fc_tested << " (" << percent(s.fc_robust, s.fc_tested)
       << ")\n  variants failing where the nominal held:";
    for (const auto& [name, n] : s.variant_failures) os << " " << name << " " << n;
    os << "\n";
  }
  if (s.close_from_open)
    os << "  jaws closed from open at the stored poses and pressed with the jaw force (grasps "
          "given as poses: docs/ACRONYM.md)\n";
  os << "  outcomes:";
  for (const auto& [name, n] : s.statuses) os << " " << name << " " << n;
  os << "\n  slipped under push:";
  for (std::size_t d = 0; d < 6; ++d)
    os << " " << pushDirectionNames()[d] << " " << s.failed_by_direction[d];
  char line[160];
  std::snprintf(line, sizeof line, "\n  object: %d convex piece(s), volume error %+.1f %%\n",
                s.model.object_pieces, 100.0 * s.model.object_volume_error);
  os << line;
  if (s.model.gripper_torque > 0.0) {
    std::snprintf(line, sizeof line,
                  "  hand: a gripper driven by one revolute joint, its drive limited to %.2f N m "
                  "(the jaw force at each fingertip)\n",
                  s.model.gripper_torque);
    os << line;
  }
  if (std::abs(s.model.object_volume_error) > 0.1)
    os << "  warning: the object's convex pieces differ from it by "
       << static_cast<int>(std::lround(100.0 * s.model.object_volume_error)) << " % in volume ("
       << s.model.object_note
       << "); labels of grasps that touch where they differ are not reliable\n";
  std::snprintf(line, sizeof line, "  %.1f grasps per CPU-second (%.1f CPU s, %.1f s wall)",
                s.cpu_seconds > 0 ? static_cast<double>(s.tested) / s.cpu_seconds : 0.0,
                s.cpu_seconds, s.wall_seconds);
  os << line << "; labels written to " << written_to << "\n";
  return os.str();
}

}  // namespace taskmap
