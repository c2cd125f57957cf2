// printf into a string (core/text.hpp).
#include "taskmap/core/text.hpp"

#include <cmath>
#include <cstdarg>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {

std::string formatted(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string out;
  if (n > 0) {
    std::vector<char> buffer(static_cast<std::size_t>(n) + 1);
    std::vsnprintf(buffer.data(), buffer.size(), format, again);
    out.assign(buffer.data(), static_cast<std::size_t>(n));
  }
  va_end(again);
  return out;
}

Eigen::VectorXd parseNumbers(const std::string& text, int n, const std::string& option) {
  std::istringstream in(text);
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(word, &used));
      if (used != word.size()) throw std::invalid_argument(word);
    } catch (const std::exception&) {
      throw Error(option + ": '" + word + "' is not a number");
    }
  }
  if (n >= 0 && static_cast<int>(v.size()) != n)
    throw Error(option + " needs " + std::to_string(n) + " numbers, got " +
                std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) throw Error(option + ": values must be finite");
  return Eigen::Map<Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

Eigen::Isometry3d parsePoseText(const std::string& text, const std::string& option) {
  try {
    return Pose::fromVector7(parseNumbers(text, 7, option)).toIsometry();
  } catch (const Error& e) {
    const std::string m = e.what();
    throw Error(m.rfind(option, 0) == 0 ? m : option + " \"x y z qw qx qy qz\": " + m);
  }
}

Eigen::Isometry3d parseXyzYaw(const std::string& text, const std::string& option) {
  std::istringstream in(text);
  double v[4];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x))
      throw Error(option + " needs 4 finite numbers \"x y z yaw\" (metres, radians)");
  std::string extra;
  if (in >> extra) throw Error(option + " needs exactly 4 numbers \"x y z yaw\"");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  t.linear() = Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

}  // namespace taskmap
