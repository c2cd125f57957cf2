// Per-link contact reduction (contact_reduction.hpp, docs/METHOD.md §4 "Contact reduction").
#include "taskmap/quality/contact_reduction.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <map>
#include <string>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// Greedy spread of `k` representatives among the contacts `ids` (deepest first by depth,
/// then farthest, largest triangle, largest smallest distance; earliest on ties).
std::vector<std::size_t> pickRepresentatives(const std::vector<Contact>& c,
                                             const std::vector<std::size_t>& ids, int k) {
  std::size_t deepest = ids[0];
  for (std::size_t i : ids)
    if (c[i].depth > c[deepest].depth) deepest = i;
  std::vector<std::size_t> picks{deepest};
  std::vector<char> chosen(c.size(), 0);
  chosen[deepest] = 1;
  auto pickBest = [&](auto score) {
    std::size_t best = ids[0];
    double best_score = -std::numeric_limits<double>::infinity();
    for (std::size_t i : ids) {
      if (chosen[i]) continue;
      const double s = score(c[i].point);
      if (s > best_score) {
        best_score = s;
        best = i;
      }
    }
    chosen[best] = 1;
    picks.push_back(best);
  };
  const Eigen::Vector3d p0 = c[deepest].point;
  if (k >= 2) pickBest([&](const Eigen::Vector3d& p) { return (p - p0).squaredNorm(); });
  if (k >= 3) {
    const Eigen::Vector3d p1 = c[picks[1]].point;
    pickBest([&](const Eigen::Vector3d& p) { return (p1 - p0).cross(p - p0).squaredNorm(); });
  }
  while (picks.size() < static_cast<std::size_t>(k)) {
    pickBest([&](const Eigen::Vector3d& p) {
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t j : picks) nearest = std::min(nearest, (p - c[j].point).squaredNorm());
      return nearest;
    });
  }
  return picks;
}

/// Reduces one link's contacts `ids` (more than k) into `out` at the representatives' indices.
void reduceLink(const std::vector<Contact>& c, const std::vector<std::size_t>& ids, int k,
                std::vector<Contact>& out, std::vector<char>& keep) {
  const std::vector<std::size_t> picks = pickRepresentatives(c, ids, k);
  std::vector<Eigen::Vector3d> normal_sum(picks.size(), Eigen::Vector3d::Zero());
  std::vector<double> depth(picks.size(), 0.0);
  for (std::size_t i : ids) {
    std::size_t nearest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t r = 0; r < picks.size(); ++r) {
      const double d = (c[i].point - c[picks[r]].point).squaredNorm();
      if (d < best) {
        best = d;
        nearest = r;
      }
    }
    normal_sum[nearest] += c[i].normal.normalized();
    depth[nearest] = std::max(depth[nearest], c[i].depth);
  }
  for (std::size_t r = 0; r < picks.size(); ++r) {
    Contact& rep = out[picks[r]];
    const double len = normal_sum[r].norm();
    if (len > 1e-12) rep.normal = normal_sum[r] / len;
    rep.depth = depth[r];
    keep[picks[r]] = 1;
  }
}

}  // namespace

std::vector<Contact> reduceContactsPerLink(const std::vector<Contact>& contacts, int per_link) {
  if (per_link < 1) {
    throw Error(
        "reduceContactsPerLink: per_link (QualityOptions::contacts_per_link) must be "
        ">= 1, got " +
        std::to_string(per_link));
  }
  std::map<int, std::vector<std::size_t>> by_link;  // pressing contacts of each known link
  std::vector<char> keep(contacts.size(), 0);
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    if (!(contacts[i].depth > 0.0)) continue;
    if (contacts[i].link < 0)
      keep[i] = 1;
    else
      by_link[contacts[i].link].push_back(i);
  }
  std::vector<Contact> work = contacts;
  for (const auto& [link, ids] : by_link) {
    if (ids.size() <= static_cast<std::size_t>(per_link)) {
      for (std::size_t i : ids) keep[i] = 1;
    } else {
      reduceLink(contacts, ids, per_link, work, keep);
    }
  }
  std::vector<Contact> out;
  out.reserve(contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i)
    if (keep[i]) out.push_back(work[i]);
  return out;
}

}  // namespace taskmap
