#pragma once
/// @file contact_reduction.hpp
/// Per-link contact reduction before the wrench hull (docs/METHOD.md §4, "Contact reduction"):
/// each link's contact patch becomes at most K representative contacts, so the size of the
/// 6-D wrench set, and the cost of its hull, no longer grow with the mesh's resolution.
/// Thread-safe: no global state.

#include <vector>

#include "taskmap/core/contact.hpp"

namespace taskmap {

/// Reduces each link's pressing contacts (depth > 0) to at most `per_link` representatives.
/// Per link (Contact::link; contacts of link -1 are never grouped): when it has at most
/// `per_link` pressing contacts they are kept unchanged; otherwise representatives are chosen
/// greedily as a contact manifold spans its patch: the deepest contact (the earliest on ties),
/// then the one farthest from it, then the one maximising the triangle area with those two,
/// then each further one maximising its smallest distance to those chosen (earliest on ties).
/// Every other contact of the link joins its nearest representative (the earliest on ties);
/// a representative keeps its point, takes the largest depth of its group and the normalised
/// sum of its group's unit normals (its own normal if that sum vanishes). Contacts without
/// pressure are dropped. Output in input order, so a grasp whose links all have at most
/// `per_link` pressing contacts scores exactly as without reduction. per_link >= 1 (throws
/// Error otherwise); non-finite contacts are the caller's to refuse (evaluateGrasp does).
std::vector<Contact> reduceContactsPerLink(const std::vector<Contact>& contacts, int per_link);

}  // namespace taskmap
