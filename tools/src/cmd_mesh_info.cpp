// taskmap mesh-info FILE [--scale S] [--json] [--no-repair | --repair wrap]: load an object
// mesh as a solid and print what was found and repaired, and its mass properties.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "mesh_options.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/meshes/object_size.hpp"

namespace taskmap::cli {
namespace {

struct MeshInfoArgs {
  std::string file;
  double scale = 1.0;
  bool json = false;
  MeshRepairArgs repair;
};

nlohmann::json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

std::string fmt(const Eigen::Vector3d& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
  return buf;
}

void run(const MeshInfoArgs& args) {
  MeshLoadOptions options;
  options.scale = args.scale;
  applyMeshRepairArgs(args.repair, options);
  ObjectModel model;
  try {
    requireObjectFile(args.file);
    model = ObjectModel::load(args.file, options);
  } catch (const Error& e) {
    if (args.json) {
      nlohmann::json j = {{"path", args.file}, {"closed", false}, {"error", e.what()}};
      std::cout << j.dump(2) << "\n";
    }
    throw;
  }
  const MeshLoadReport& report = model.report();
  const MassProperties& mass = model.massProperties();
  const Eigen::Vector3d size = mass.bounds_max - mass.bounds_min;
  const std::string size_warning = graspableSizeWarning(size.maxCoeff(), model.scale());
  if (args.json) {
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
    j["size"] = vec(size);
    j["graspable_size"] = size_warning.empty();
    j["closed"] = report.closed;
    j["volume"] = mass.volume;
    j["bounds_min"] = vec(mass.bounds_min);
    j["bounds_max"] = vec(mass.bounds_max);
    j["center_of_mass"] = vec(mass.center_of_mass);
    j["inertia"] = {vec(mass.inertia.row(0)), vec(mass.inertia.row(1)), vec(mass.inertia.row(2))};
    j["torque_scale"] = mass.torque_scale;
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::printf("file:           %s\n", report.path.c_str());
  std::printf("format:         %s\n", report.format.c_str());
  std::printf("sha256:         %s\n", model.sourceSha256().c_str());
  std::printf("scale:          %.6g\n", model.scale());
  std::printf("input:          %zu vertices, %zu faces\n", report.input_vertices,
              report.input_faces);
  std::printf("solid:          %zu vertices, %zu faces, %s\n", model.mesh().vertices.size(),
              model.mesh().faces.size(), report.closed ? "closed" : "NOT closed");
  if (report.repairs.empty()) {
    std::printf("repairs:        none\n");
  } else {
    for (std::size_t i = 0; i < report.repairs.size(); ++i) {
      std::printf("%s%s\n", i == 0 ? "repairs:        " : "                ",
                  report.repairs[i].c_str());
    }
  }
  for (const auto& w : report.warnings) std::printf("warning:        %s\n", w.c_str());
  if (!size_warning.empty()) std::printf("warning:        %s\n", size_warning.c_str());
  std::printf("volume:         %.9g m^3\n", mass.volume);
  std::printf("bounds:         %s .. %s m\n", fmt(mass.bounds_min).c_str(),
              fmt(mass.bounds_max).c_str());
  std::printf("size:           %s m (largest side %.4g m)\n", fmt(size).c_str(), size.maxCoeff());
  std::printf("centre of mass: %s m\n", fmt(mass.center_of_mass).c_str());
  std::printf("inertia (1 kg/m^3, about the centre of mass, kg m^2):\n");
  for (int r = 0; r < 3; ++r) {
    std::printf("                %.6g %.6g %.6g\n", mass.inertia(r, 0), mass.inertia(r, 1),
                mass.inertia(r, 2));
  }
  std::printf("torque scale:   %.6g m\n", mass.torque_scale);
}

const CommandRegistrar kRegistrar("mesh-info", [](CLI::App& app) {
  auto args = std::make_shared<MeshInfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "mesh-info",
      "Load an object mesh as a closed solid; print repairs, size and mass properties, and "
      "flag a size implausible for a graspable object (with the --scale that fixes a file in "
      "millimetres, centimetres or inches)");
  cmd->add_option("file", args->file, "mesh file (any format assimp reads)")->required();
  cmd->add_option("--scale", args->scale, "multiplies coordinates (file units to metres)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--json", args->json, "print JSON instead of text");
  addMeshRepairOptions(cmd, args->repair);
  cmd->callback([args]() { run(*args); });
});

}  // namespace
}  // namespace taskmap::cli
