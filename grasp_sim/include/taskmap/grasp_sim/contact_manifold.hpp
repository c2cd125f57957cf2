#pragma once
/// @file contact_manifold.hpp
/// Reduction of one link's contacts to a small contact manifold, as physics engines keep
/// (Bullet's persistent manifold holds 4 points).

#include <vector>

#include "taskmap/core/contact.hpp"

namespace taskmap {

/// Selects at most max_points contacts of one link (max_points = 0 keeps all). Input deepest
/// first. Greedy and deterministic: the deepest contact; then the contact farthest from it;
/// then the one maximising the triangle area with the first two; then each further one
/// maximising its smallest distance to those already chosen. Ties keep the earlier contact.
/// The output keeps the input order.
std::vector<Contact> contactManifold(const std::vector<Contact>& candidates, int max_points);

}  // namespace taskmap
