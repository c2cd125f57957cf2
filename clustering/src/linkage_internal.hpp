#pragma once
/// @file linkage_internal.hpp
/// Private helpers shared by the clustering sources (not installed).

#include <vector>

#include "taskmap/clustering/clustering.hpp"

namespace taskmap::detail {

/// One merge between the clusters holding points a and b (point indices, 0..n-1), at
/// Euclidean distance d (not squared).
struct PointMerge {
  int a = 0;
  int b = 0;
  double d = 0.0;
};

/// Euclidean minimum spanning tree of the rows of points (n >= 2): n - 1 edges with d the
/// edge length. Borůvka over a kd-tree (emst.cpp). Deterministic; ties are broken by point
/// index, so the tree is the unique MST under the order (d^2, min index, max index).
std::vector<PointMerge> euclideanMst(const PointMatrix& points);

/// Average or complete linkage by the nearest-neighbour chain on a condensed distance
/// matrix (scipy's nn_chain). Merges in the order found (not sorted); a and b are the
/// point indices that represent the two clusters.
std::vector<PointMerge> nearestNeighbourChain(const PointMatrix& points, Linkage method);

/// scipy's `label`: stable-sorts merges by distance and turns point representatives into
/// cluster ids n + k, smaller id first, with sizes. n = merges.size() + 1.
LinkageMatrix labelMerges(std::vector<PointMerge> merges);

/// Checks that linkage is a valid dendrogram over n points (ids, sizes, finite
/// non-decreasing distances); throws Error naming the first bad row.
void validateLinkage(const LinkageMatrix& linkage, const char* what);

}  // namespace taskmap::detail
