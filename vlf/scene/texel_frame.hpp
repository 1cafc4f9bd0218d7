// texel_frame.hpp — the texel grid of a chart (charts.hpp) (VLF §4.4: the diffuse texture maps P^C,
// P^N, P^T live on it) and the exact area of every texel square ∩ the chart's faces, which the
// diffuse sender and receiver use as their overlap weights (DESIGN §5).
#pragma once

#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Fills chart.texels and chart.texel_area from its faces (normalised units). axis_u runs
// along the direction in which the chart's rim (a single face: its edges) is longest in
// total, ties to the canonical direction (texel_frame.cpp), projected into its plane; axis_v =
// normal x axis_u; the origin is the minimum corner of the chart's bounding rectangle in that
// frame, width/height = ceil(extent / texel_size) (at least 1). When a side would exceed
// max_texels_per_side, the texel size of this chart grows until it fits. A face tilted against the
// chart's plane counts its projected area times projected_area_scale.
void build_chart_texels(Chart& chart, const std::vector<Face>& faces, double texel_size,
                        int max_texels_per_side);

// The area of `face` (one of the chart's) in each texel it covers, normalised units^2,
// appended to `out`; sealed parts are not taken out.
struct TexelArea {
    uint32_t texel;  // j * width + i
    double area;
};
void face_texel_areas(const Chart& chart, const Face& face, std::vector<TexelArea>& out);

// 1 / cos of the angle between a face of a chart and the chart's plane: the face's area
// over its projection (exactly 1 for a face in the plane).
double projected_area_scale(const Chart& chart, const Face& face);

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
