#pragma once
/// @file hand_draft.hpp
/// Drafting a hand sidecar (<stem>.hand.json, meshes/hands/README.md) from the URDF alone, for
/// `taskmap hand-init`. Every guess comes with the reason it was made; a field that cannot be
/// decided is named. The rules are in docs/METHOD.md, "Drafting a sidecar".

#include <string>
#include <vector>

namespace taskmap {

/// A drafted sidecar and how it was guessed.
struct SidecarDraft {
  std::string json;                ///< the sidecar text (valid JSON, sidecar keys only)
  std::vector<std::string> notes;  ///< one line per guess: the field, its value and why
  /// Fields the draft could not decide (each with what to check); empty when the draft loads.
  std::vector<std::string> undecided;
};

/// Drafts a sidecar for the hand URDF at urdf_path (package:// paths resolved as
/// HandModel::load does). The palm link is the root's rigid group member with the largest
/// collision shapes; every non-fixed joint leaving that group starts a finger (its subtree);
/// the preshape opens every joint (the limit away from its closing direction, else the value
/// nearest 0); a joint closes toward the limit that brings the fingertips toward their
/// centroid (one finger: toward the palm's axis) and is left out when it moves the fingertips
/// by less than 5 % of the most effective joint; the approach axis points from the palm's
/// centre to the fingertips' centroid where they come closest together while closing (sampled
/// at tenths of the closing motion) and the palm frame sits on the palm's face along it (z
/// the approach axis, x across the first two fingers); mimic joints follow their drivers (no
/// entry needed). The draft is then loaded: a load error lands in `undecided`.
/// Throws Error when the URDF cannot be read.
SidecarDraft draftHandSidecar(const std::string& urdf_path);

}  // namespace taskmap
