#pragma once
/// @file grasp_contacts.hpp
/// The stored contacts of one grasp of a map as the Contact list the quality stage, the hold
/// filter and the closing check take.

#include <cstddef>
#include <vector>

#include "taskmap/core/contact.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Contacts of grasp i (rows contact_offsets[i] .. contact_offsets[i+1]-1): point and outward
/// normal in the object frame, depth in metres, hand link index. Requires i < grasps.size() of a
/// valid map (MapGrasps holds N + 1 offsets); an imported map has no contacts: the list is empty.
std::vector<Contact> graspContacts(const MapGrasps& grasps, std::size_t i);

}  // namespace taskmap
