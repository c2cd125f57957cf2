// Which transform takes ACRONYM's gripper base frame to the palm frame (acronym_frame.hpp).
#include "acronym_frame.hpp"

#include <cstdio>

#include "mesh_options.hpp"

namespace taskmap::cli {

void addAcronymFrameOptions(CLI::App* cmd, AcronymFrameArgs& args) {
  cmd->add_option("--palm-offset", args.palm_offset,
                  "palm frame = ACRONYM gripper base frame moved this far along its z "
                  "(approach) axis, m (default 0.1034: ACRONYM's Franka gripper)");
  cmd->add_option("--hand", args.hand,
                  "take the palm frame in the gripper base frame from this hand (URDF or bundled "
                  "name): its root-to-palm transform, for a URDF whose root is the base frame; "
                  "export ply/glb: the hand posed at the representatives (default: the map's)");
  addPackagePathOption(cmd);
}

std::string describeBaseToPalm(const AcronymFrameArgs& args, const Eigen::Isometry3d& t) {
  char buf[200];
  const Eigen::Vector3d p = t.translation();
  std::snprintf(buf, sizeof buf, "palm frame = gripper base frame shifted by (%.4g, %.4g, %.4g) m",
                p.x(), p.y(), p.z());
  std::string s = buf;
  if (!args.hand.empty())
    s += " (root to palm of hand " + args.hand + ")";
  else if (!args.palm_offset)
    s += " (ACRONYM's Franka gripper)";
  return s;
}

}  // namespace taskmap::cli
