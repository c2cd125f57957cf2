// Test helper for tests/python/test_clustering_scipy.py.
//   taskmap_linkage_helper poses N SEED RHO OUT   clustered poses, embedded, one point a line
//   taskmap_linkage_helper linkage METHOD IN OUT  dendrogram of the points in IN (text)
// Text: one row per line, values separated by spaces, %.17g.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace {

taskmap::PointMatrix clusteredPoses(int n, std::uint64_t seed, double rho) {
  // Gaussian blobs of poses: centres uniform in a 0.3 m cube with uniform orientations;
  // members 1 cm and 0.1 rad around them.
  const int blobs = std::max(1, n / 50);
  taskmap::Rng centre_rng(seed, 0);
  std::vector<taskmap::Pose> centres(blobs);
  for (auto& c : centres) {
    c.position = Eigen::Vector3d(centre_rng.uniform(0, 0.3), centre_rng.uniform(0, 0.3),
                                 centre_rng.uniform(0, 0.3));
    c.orientation = centre_rng.rotation();
  }
  taskmap::PointMatrix points(n, taskmap::kEmbeddingDim);
  taskmap::Rng rng(seed, 1);
  for (int i = 0; i < n; ++i) {
    const taskmap::Pose& c = centres[rng.below(blobs)];
    taskmap::Pose p;
    p.position = c.position + 0.01 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    const Eigen::Vector3d w = 0.1 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    p.orientation = Eigen::Quaterniond(c.orientation.toRotationMatrix() * taskmap::rotationExp(w));
    points.row(i) = taskmap::embedPose(p, rho).transpose();
  }
  return points;
}

void writeRows(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& m) {
  std::ofstream out(path);
  if (!out) throw taskmap::Error("cannot write " + path);
  char buf[64];
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      std::snprintf(buf, sizeof buf, "%.17g", m(i, j));
      out << (j ? " " : "") << buf;
    }
    out << "\n";
  }
  if (!out) throw taskmap::Error("cannot write " + path);
}

taskmap::PointMatrix readRows(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw taskmap::Error("cannot read " + path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::vector<double> row;
    double v = 0;
    while (ls >> v) row.push_back(v);
    if (row.empty()) continue;
    if (!rows.empty() && row.size() != rows[0].size()) {
      throw taskmap::Error(path + ": rows of different lengths");
    }
    rows.push_back(row);
  }
  taskmap::PointMatrix m(static_cast<Eigen::Index>(rows.size()),
                         rows.empty() ? 0 : static_cast<Eigen::Index>(rows[0].size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < rows[i].size(); ++j) m(i, j) = rows[i][j];
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 5 && args[0] == "poses") {
      writeRows(args[4],
                clusteredPoses(std::stoi(args[1]), std::stoull(args[2]), std::stod(args[3])));
      return 0;
    }
    if (args.size() == 4 && args[0] == "linkage") {
      const taskmap::PointMatrix points = readRows(args[2]);
      writeRows(args[3], taskmap::computeLinkage(points, taskmap::linkageFromString(args[1])));
      return 0;
    }
    std::cerr << "usage: taskmap_linkage_helper poses N SEED RHO OUT | linkage METHOD IN OUT\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "taskmap_linkage_helper: " << e.what() << "\n";
    return 1;
  }
}
