// Mesh repair options of `mesh-info` and `build` (see mesh_options.hpp).
#include "mesh_options.hpp"

#include <cstdlib>
#include <string>
#include <vector>

#include "taskmap/core/error.hpp"

namespace taskmap::cli {

void addMeshRepairOptions(CLI::App* cmd, MeshRepairArgs& args) {
  cmd->add_flag("--no-repair", args.no_repair, "refuse meshes that need repair");
  cmd->add_option("--repair", args.repair,
                  "wrap: also close a surface that stays open (holes, missing faces) or "
                  "non-manifold by 3D alpha wrapping (CGAL), reporting the volume change")
      ->check(CLI::IsMember({"wrap"}));
  cmd->add_option("--wrap-alpha", args.wrap_alpha,
                  "with --repair wrap: openings narrower than about this (m) are sealed "
                  "(default: bounding-box diagonal / 100)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--wrap-offset", args.wrap_offset,
                  "with --repair wrap: distance of the wrap outside the input surface (m) "
                  "(default: bounding-box diagonal / 3000)")
      ->check(CLI::PositiveNumber);
}

void addPackagePathOption(CLI::App* cmd) {
  cmd->add_option_function<std::vector<std::string>>(
         "--package-path",
         [](const std::vector<std::string>& dirs) {
           std::string value;
           for (const std::string& d : dirs) value += (value.empty() ? "" : ":") + d;
           if (const char* old = std::getenv("ROS_PACKAGE_PATH"); old != nullptr && *old != '\0')
             value += ":" + std::string(old);
           ::setenv("ROS_PACKAGE_PATH", value.c_str(), 1);
         },
         "folder of a ROS package, or a folder holding packages, where package://PKG/... mesh "
         "paths of the hand's URDF are looked up before ROS_PACKAGE_PATH and the package that "
         "holds the URDF (repeatable)")
      ->check(CLI::ExistingDirectory)
      ->type_size(1)
      ->allow_extra_args(false);
}

void applyMeshRepairArgs(const MeshRepairArgs& args, MeshLoadOptions& options) {
  const bool wrap = args.repair == "wrap";
  if (wrap && args.no_repair) throw Error("--repair wrap and --no-repair contradict each other");
  if (!wrap && (args.wrap_alpha > 0 || args.wrap_offset > 0))
    throw Error("--wrap-alpha and --wrap-offset need --repair wrap");
  options.repair = !args.no_repair;
  options.wrap = wrap;
  options.wrap_alpha = args.wrap_alpha;
  options.wrap_offset = args.wrap_offset;
}

}  // namespace taskmap::cli
