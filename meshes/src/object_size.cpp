// Plausible object sizes and the scale that fixes a file in other units (object_size.hpp).
#include "taskmap/meshes/object_size.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "taskmap/core/text.hpp"

namespace taskmap {
namespace {

std::string scaleText(double s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", s);
  return buf;
}

}  // namespace

std::vector<UnitGuess> unitGuesses(double file_extent, double current_scale, double lo, double hi,
                                   double typical) {
  static const struct {
    const char* unit;
    double scale;
  } kUnits[] = {{"metres", 1.0}, {"centimetres", 0.01}, {"millimetres", 0.001}, {"inches", 0.0254}};
  std::vector<UnitGuess> out;
  if (!(file_extent > 0) || !std::isfinite(file_extent)) return out;
  for (const auto& u : kUnits) {
    if (std::abs(u.scale - current_scale) <= 1e-9 * u.scale) continue;
    const double extent = file_extent * u.scale;
    if (extent >= lo && extent <= hi) out.push_back({u.unit, u.scale, extent});
  }
  std::stable_sort(out.begin(), out.end(), [typical](const UnitGuess& a, const UnitGuess& b) {
    return std::abs(std::log(a.extent / typical)) < std::abs(std::log(b.extent / typical));
  });
  return out;
}

std::string scaleAdvice(double extent, double current_scale, double lo, double hi, double typical) {
  const std::vector<UnitGuess> guesses =
      unitGuesses(extent / current_scale, current_scale, lo, hi, typical);
  if (guesses.empty())
    return "no unit (metres, centimetres, millimetres, inches) gives it a size between " +
           shortNumber(lo) + " and " + shortNumber(hi) +
           " m; check the scale (--scale, file units to metres)";
  const UnitGuess& best = guesses.front();
  std::string s = "is the file in " + best.unit + "? scale " + scaleText(best.scale) +
                  " (--scale " + scaleText(best.scale) + ") makes it " + shortNumber(best.extent) +
                  " m across";
  for (std::size_t i = 1; i < guesses.size(); ++i)
    s += std::string(i == 1 ? " (" : "; ") + "in " + guesses[i].unit + ": --scale " +
         scaleText(guesses[i].scale) + ", " + shortNumber(guesses[i].extent) + " m";
  if (guesses.size() > 1) s += ")";
  return s;
}

std::string graspableSizeWarning(double extent, double current_scale) {
  if (extent >= kGraspableMinExtent && extent <= kGraspableMaxExtent) return "";
  const bool large = extent > kGraspableMaxExtent;
  return "the object is " + shortNumber(extent) + " m across: " + (large ? "large" : "small") +
         " for a graspable object (hand-held objects are about " +
         shortNumber(kGraspableMinExtent) + " to " + shortNumber(kGraspableMaxExtent) + " m); " +
         scaleAdvice(extent, current_scale, kGraspableMinExtent, kGraspableMaxExtent,
                     kGraspableTypicalExtent);
}

namespace {
thread_local const std::function<void(const Eigen::Vector3d&)>* g_load_bounds_check = nullptr;
}  // namespace

ScopedLoadBoundsCheck::ScopedLoadBoundsCheck(std::function<void(const Eigen::Vector3d&)> check)
    : check_(std::move(check)), previous_(g_load_bounds_check) {
  g_load_bounds_check = &check_;
}

ScopedLoadBoundsCheck::~ScopedLoadBoundsCheck() {
  g_load_bounds_check = previous_;
}

const std::function<void(const Eigen::Vector3d&)>* ScopedLoadBoundsCheck::current() {
  return g_load_bounds_check;
}

}  // namespace taskmap
