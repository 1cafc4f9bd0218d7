// imprint.hpp — contact lines cut the surfaces they run across (docs/charts.md "Contact
// lines"; issue 11, two-sided dividers).
//
// A wall met by a partition, or a floor by a wall-to-wall divider, is one polygon with
// one texel grid: the texels along the line where the partition meets it straddle both
// sides. Light landing on the lit side fills them, and they send it on from their whole
// area, the dark side's half too: the dark room glows along its junctions (1.4 % of the lit
// side's radiance in a room halved by a two-sided divider, where the path tracer finds
// none). A lightmap baker's answer is to cut the surface along the contact line, so that
// each side owns its texels. VLF does so at load, before charts:
//
//   face A is cut by the plane of face B when A's vertices lie on both sides of that plane
//   (beyond the tolerance) and B covers the whole segment where the plane crosses A (both
//   ends inside B): B runs right across A, touching or piercing it.
//
// A partial contact (a box standing on a floor, a picture on a wall) cuts nothing. The two
// pieces of a cut face are faces of their own whose shared edge is a contact line
// (Face::cut_edges): charts do not grow across it. The surface, its area, material and
// texture coordinates are unchanged; only its faces are. Faces cut: one-sided, not
// emitting, not specular, not glass, of at least `min_area` (smaller faces hold at most a
// few texels, where the straddle matters little).
#pragma once

#include <string>
#include <vector>

#include "vlf/scene/scene.hpp"

namespace vlf {

struct ImprintResult {
    int cut_faces = 0;  // faces cut (each replaced by its pieces)
    int pieces = 0;     // faces they became
};

// Cuts scene.faces as above (normalised coordinates, `tol` a length there), renumbering
// faces, objects' face ranges and twins. Call before charts are built. Deterministic.
ImprintResult imprint_contacts(Scene& scene, double min_area, double tol);

}  // namespace vlf
