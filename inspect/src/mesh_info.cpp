// The report of an object mesh (inspect/mesh_info.hpp): what `taskmap mesh-info` prints.
#include "taskmap/inspect/mesh_info.hpp"

#include <sstream>

#include <nlohmann/json.hpp>

#include "taskmap/core/text.hpp"
#include "taskmap/meshes/object_size.hpp"

namespace taskmap {
namespace {

nlohmann::json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

std::string fmt(const Eigen::Vector3d& v) {
  return formatted("(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
}

std::string infoJson(const ObjectModel& model, const std::string& size_warning) {
  const MeshLoadReport& report = model.report();
  const MassProperties& mass = model.massProperties();
  nlohmann::json j;
  j["path"] = report.path;
  j["format"] = report.format;
  j["sha256"] = model.sourceSha256();
  j["scale"] = model.scale();
  j["input_vertices"] = report.input_vertices;
  j["input_faces"] = report.input_faces;
  j["vertices"] = model.mesh().vertices.size();
  j["faces"] = model.mesh().faces.size();
  j["repairs"] = report.repairs;
  j["warnings"] = report.warnings;
  if (!size_warning.empty()) j["warnings"].push_back(size_warning);
  j["size"] = vec(mass.bounds_max - mass.bounds_min);
  j["graspable_size"] = size_warning.empty();
  j["closed"] = report.closed;
  j["volume"] = mass.volume;
  j["bounds_min"] = vec(mass.bounds_min);
  j["bounds_max"] = vec(mass.bounds_max);
  j["center_of_mass"] = vec(mass.center_of_mass);
  j["inertia"] = {vec(mass.inertia.row(0)), vec(mass.inertia.row(1)), vec(mass.inertia.row(2))};
  j["torque_scale"] = mass.torque_scale;
  return j.dump(2);
}

std::string infoText(const ObjectModel& model, const std::string& size_warning) {
  const MeshLoadReport& report = model.report();
  const MassProperties& mass = model.massProperties();
  const Eigen::Vector3d size = mass.bounds_max - mass.bounds_min;
  std::ostringstream os;
  os << formatted("file:           %s\n", report.path.c_str());
  os << formatted("format:         %s\n", report.format.c_str());
  os << formatted("sha256:         %s\n", model.sourceSha256().c_str());
  os << formatted("scale:          %.6g\n", model.scale());
  os << formatted("input:          %zu vertices, %zu faces\n", report.input_vertices,
                  report.input_faces);
  os << formatted("solid:          %zu vertices, %zu faces, %s\n", model.mesh().vertices.size(),
                  model.mesh().faces.size(), report.closed ? "closed" : "NOT closed");
  if (report.repairs.empty()) os << "repairs:        none\n";
  for (std::size_t i = 0; i < report.repairs.size(); ++i)
    os << (i == 0 ? "repairs:        " : "                ") << report.repairs[i] << "\n";
  for (const auto& w : report.warnings) os << "warning:        " << w << "\n";
  if (!size_warning.empty()) os << "warning:        " << size_warning << "\n";
  os << formatted("volume:         %.9g m^3\n", mass.volume);
  os << formatted("bounds:         %s .. %s m\n", fmt(mass.bounds_min).c_str(),
                  fmt(mass.bounds_max).c_str());
  os << formatted("size:           %s m (largest side %.4g m)\n", fmt(size).c_str(),
                  size.maxCoeff());
  os << formatted("centre of mass: %s m\n", fmt(mass.center_of_mass).c_str());
  os << "inertia (1 kg/m^3, about the centre of mass, kg m^2):\n";
  for (int r = 0; r < 3; ++r)
    os << formatted("                %.6g %.6g %.6g\n", mass.inertia(r, 0), mass.inertia(r, 1),
                    mass.inertia(r, 2));
  os << formatted("torque scale:   %.6g m\n", mass.torque_scale);
  return os.str();
}

}  // namespace

MeshInfo meshInfo(const ObjectModel& object) {
  const MassProperties& mass = object.massProperties();
  const std::string size_warning =
      graspableSizeWarning((mass.bounds_max - mass.bounds_min).maxCoeff(), object.scale());
  return {infoJson(object, size_warning), infoText(object, size_warning)};
}

std::string meshInfoErrorJson(const std::string& path, const std::string& error) {
  return nlohmann::json{{"path", path}, {"closed", false}, {"error", error}}.dump(2);
}

}  // namespace taskmap
