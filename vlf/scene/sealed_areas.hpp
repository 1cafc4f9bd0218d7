// sealed_areas.hpp — the parts of faces that lie right behind another face.
//
// A mirror panel hung 1.2 mm in front of a wall, a lamp 0.1 mm under its ceiling: the part
// of the wall (the ceiling) behind it can neither receive nor send light — every ray from
// it meets the back of the panel at once (exchange.hpp, kSealed). A texel straddling the
// panel's rim would otherwise average its lit part with the dark part behind the panel
// and show the wall next to the panel up to 15 % dark. So the sealed part is taken out of
// each texel's area (the face's area stays its polygon's), exactly: the polygon of the face in
// front, projected onto the face, ∩ the face ∩ the texel. Radiance is then power over the open
// area.
//
// "Right behind": a face g whose plane is parallel to f's with the same orientation
// (g's back towards f's front), in front of f by at most `gap` (normalised units).
#pragma once

#include "vlf/scene/scene.hpp"

namespace vlf {

// Subtracts from every chart's texel areas what faces within `gap` in front of its faces
// cover. Faces of any orientation are grouped by normal, so the cost is about
// n log n plus the pairs that are really that close.
void subtract_sealed_areas(Scene& scene, double gap);

// Below this open fraction (Chart::texel_open) a texel counts as sealed: numerically
// nothing of it is open. Light landing there goes to the sealing face's black back.
inline constexpr double kSealedTexel = 1e-3;

}  // namespace vlf
