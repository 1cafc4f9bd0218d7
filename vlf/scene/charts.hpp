// charts.hpp — the surfaces that own texels (docs/charts.md): faces grouped into charts of
// connected faces, one material, and normals within a bounded angle of the chart's first
// face, each chart with one texel grid. The same surface gets the same texels however it is
// cut into triangles.
#pragma once

#include "vlf/scene/scene.hpp"

namespace vlf {

// Normals of a chart's faces lie within this angle of its first face's normal: coplanar
// faces always merge; on a curved mesh the projection onto the chart's plane stretches a
// face's area by at most 1 / cos(kChartAngleDeg) (15 %), which the texel areas count.
inline constexpr double kChartAngleDeg = 30.0;

// A chart smaller than a texel joins the neighbouring chart whose normal is nearest, if its
// faces lie within this angle of that normal (charts.cpp merge_small_charts).
inline constexpr double kMergeAngleDeg = 75.0;

// Groups scene.faces into scene.charts (sets Face::chart and Face::inner_edges) and builds
// every chart's texel grid (texel_frame.hpp) at `texel_size` (normalised units). Faces are
// neighbours when they share an edge (the same two vertices, bit for bit, in opposite order)
// and no third face of compatible orientation claims it. Deterministic: charts grow
// breadth-first from the lowest unassigned face id; then charts of less than a texel join
// a neighbour (kMergeAngleDeg). `max_angle_deg` 0 makes every face its own chart.
void build_charts(Scene& scene, double texel_size, int max_texels_per_side,
                  double max_angle_deg = kChartAngleDeg);

// Sets a chart's derived sums (Chart::area_normal, min_cos) from its faces.
void finish_chart(Chart& chart, const std::vector<Face>& faces);

}  // namespace vlf
