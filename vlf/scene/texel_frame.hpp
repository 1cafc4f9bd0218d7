// texel_frame.hpp — the texel grid of a face (VLF §4.4: the diffuse texture maps P^C, P^N,
// P^T live on it) and the exact area of every texel square ∩ the face polygon, which the
// diffuse sender and receiver use as their overlap weights (DESIGN §5).
#pragma once

#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Fills face.texels and face.texel_area from face.vertices and face.normal (normalised
// units). axis_u runs along the face's longest edge (projected into the plane), axis_v =
// normal x axis_u, the origin is the minimum corner of the face's bounding rectangle in that
// frame, width/height = ceil(extent / texel_size) (at least 1). When a side would exceed
// max_texels_per_side, the texel size of this face grows until it fits.
void build_texel_frame(Face& face, double texel_size, int max_texels_per_side);

// Area of the convex polygon `poly` (2D, any units) ∩ the axis-aligned box [lo, hi];
// exact up to rounding (Sutherland–Hodgman clipping + shoelace).
double clipped_area(const std::vector<Vec2>& poly, const Vec2& lo, const Vec2& hi);

// `vertices` (points on the face's plane) in the texel coordinates of `frame`, as a
// counter-clockwise polygon.
std::vector<Vec2> polygon_in_texels(const TexelFrame& frame, const std::vector<Vec3>& vertices);

// Convex `subject` ∩ the convex counter-clockwise polygon `clip` (Sutherland–Hodgman);
// empty when they do not overlap in an area.
std::vector<Vec2> intersect_convex(std::vector<Vec2> subject, const std::vector<Vec2>& clip);

}  // namespace vlf
