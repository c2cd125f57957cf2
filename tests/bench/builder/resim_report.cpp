// resim_report: do a map's stored grasps survive a re-simulation? `taskmap reach --map` checks
// the planned final grasp by re-simulating it from where the arm ends (builder/resimulate.hpp)
// and testing the result in physics; this report does that for every stored grasp, from its
// pose moved by palm-frame offsets: how far from its sample a grasp still holds
// (docs/history/validation-2026-11.md, "The stored palm pose"). Per offset and in total: grasps
// whose re-simulation is force closure, whose joints equal the stored ones (within 1e-6), and that
// hold (hold test of the re-simulated pose and joints, the validator's defaults).
//
//   resim_report MAP.h5 [--grasps N] [--offset "X Y Z" ...] [--random N HALF SEED]
//     --offset: a palm-frame offset of the starts, millimetres (default "0 0 0");
//     --random: N offsets uniform in the cube of half-size HALF millimetres (seeded);
//   resim_report MAP.h5 --start "X Y Z QW QX QY QZ"
//     one re-simulation from that palm pose (object frame, metres), e.g. a plan's `start`.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/builder/resimulate.hpp"
#include "taskmap/mapstore/map_file.hpp"

int main(int argc, char** argv) {
  using namespace taskmap;
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: resim_report MAP.h5 [--grasps N] [--offset \"X Y Z\" ...] "
                 "[--random N HALF SEED] | --start \"X Y Z QW QX QY QZ\"\n");
    return 2;
  }
  std::size_t limit = 1000000;
  std::vector<Eigen::Vector3d> shifts;
  const char* start_pose = nullptr;
  for (int a = 2; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--grasps" && a + 1 < argc)
      limit = std::strtoull(argv[++a], nullptr, 10);
    else if (arg == "--random" && a + 3 < argc) {
      // --random N HALF_MM SEED: N offsets uniform in the cube of half-size HALF_MM
      const int count = std::atoi(argv[++a]);
      const double half = std::atof(argv[++a]);
      std::srand(static_cast<unsigned>(std::atoi(argv[++a])));
      for (int k = 0; k < count; ++k) {
        Eigen::Vector3d v;
        for (int c = 0; c < 3; ++c) v[c] = 2.0 * std::rand() / RAND_MAX - 1.0;
        shifts.push_back(1e-3 * half * v);
      }
    } else if (arg == "--start" && a + 1 < argc) {
      start_pose = argv[++a];
    } else if (arg == "--offset" && a + 1 < argc) {
      Eigen::Vector3d v;
      if (std::sscanf(argv[++a], "%lf %lf %lf", &v.x(), &v.y(), &v.z()) != 3) return 2;
      shifts.push_back(1e-3 * v);
    }
  }
  if (shifts.empty()) shifts = {Eigen::Vector3d::Zero()};
  const TaskMapData map = readMap(argv[1]);
  if (start_pose != nullptr) {
    Eigen::Matrix<double, 7, 1> v;
    if (std::sscanf(start_pose, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                    &v[5], &v[6]) != 7)
      return 2;
    const Resimulation r = resimulateGrasp(map, Pose::fromVector7(v));
    std::printf("%s fc %d eps %g retraction %g contacts %d fingers %zu\n", r.outcome.c_str(),
                r.force_closure ? 1 : 0, r.epsilon, r.retraction_m, r.contacts, r.fingers.size());
    return 0;
  }
  const std::size_t n = std::min(limit, map.grasps.size());
  for (const Eigen::Vector3d& shift : shifts) {
    int fc = 0, same = 0, holds = 0;
    for (std::size_t i = 0; i < n; ++i) {
      Pose start = map.grasps.poseAt(i);
      start.position += start.orientation * shift;
      Resimulation r = resimulateGrasp(map, start);
      holdTestResimulated(map, &r);
      fc += r.force_closure;
      const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
      const bool is_same =
          r.joints.size() == q.size() && (r.joints - q).cwiseAbs().maxCoeff() < 1e-6;
      const bool h = r.hold && r.hold->holds;
      same += is_same;
      holds += h;
      std::printf("offset %.2f %.2f %.2f mm grasp %zu: %s fc %d same %d hold %d\n", 1e3 * shift.x(),
                  1e3 * shift.y(), 1e3 * shift.z(), i, r.outcome.c_str(), r.force_closure ? 1 : 0,
                  is_same ? 1 : 0, h ? 1 : 0);
    }
    std::printf("offset %.2f %.2f %.2f mm: %zu grasps, force closure %d, same joints %d, hold %d\n",
                1e3 * shift.x(), 1e3 * shift.y(), 1e3 * shift.z(), n, fc, same, holds);
  }
  return 0;
}
