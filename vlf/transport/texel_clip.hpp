// texel_clip.hpp — "continuous" clipping between a surface's texel grid and the PSF ray
// grid (VLF §4.2: "Discrete cells on a sender Q are mapped onto a receiver using polygon
// clipping ... The ratio of intersected (visible) to total area of the sender cell
// determines the amount of radiance attributed to the receiver cell"; Fig. 5).
//
// A ray's beam has a square cross-section (its pixel); on a face's plane that square is a
// parallelogram, and in the face's texel coordinates (texel (i,j) = [i,i+1]x[j,j+1]) it
// is still a parallelogram because the map PSF -> plane -> texels is affine. The overlap
// of that parallelogram with each texel cell is the exact weight both for sending (texel
// -> ray) and for receiving (ray -> texel).
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// The affine map from rotated-frame (x, y) of a PSF to its chart's texel coordinates (the
// point on the face's plane, projected along the chart's normal):
// texel = origin + x * dx + y * dy.
struct PsfToTexel {
    Vec2 origin{0.0}, dx{0.0}, dy{0.0};
    Vec2 operator()(double x, double y) const { return origin + x * dx + y * dy; }
};

PsfToTexel psf_to_texel(const Face& face, const TexelFrame& chart, const Mat3& rotation);

struct TexelOverlap {
    uint32_t texel;  // j * width + i
    float area;      // overlap area, texel units (any common unit works: only ratios matter)
};

// Appends the overlaps of the convex quadrilateral `quad` (texel coordinates, any winding)
// with the cells of a width x height grid whose rim cells extend to infinity outwards (so
// every part of the quad lands on some cell). Returns the number of entries appended.
int clip_quad_to_grid(const Vec2 quad[4], int width, int height, std::vector<TexelOverlap>& out);

// A covered ray's beam on its face (docs/propagation.md §3): rays are sampled at pixel
// centres, so a beam whose centre is inside the polygon may spill over an edge while the
// beams next to it, whose centres fell outside, leave a gap inside. The weights are the
// quad ∩ polygon plus each part beyond an edge mirrored back across that edge, ∩ polygon.
// For a straight edge this is unbiased: averaged over the position of the ray grid, every
// point of the face receives the same weight density (the footprint is centrally
// symmetric, so the mirrored spill fills exactly the expected gap). The quad and the
// convex polygon (counter-clockwise) are in texel coordinates. In a chart of several faces
// (docs/charts.md) the beam runs on over edges shared inside the chart into the
// neighbour's part of the same grid: the lines it is clipped (and mirrored) at are the
// chart's rim near the face, `rim`, each with the chart on its left.
struct RimLine {
    Vec2 a, b;
};
int clip_footprint_to_grid(const Vec2 quad[4], const std::vector<RimLine>& rim, int width,
                           int height, std::vector<TexelOverlap>& out);

// The rim lines of a convex counter-clockwise polygon: its edges.
std::vector<RimLine> polygon_rim(const std::vector<Vec2>& polygon);

// A face's rim lines in its chart's texel coordinates: its own edges on the chart's rim,
// then the other rim lines of its chart within `reach` (normalised units) of it (a beam's
// footprint is at most that far from the face), collinear pieces once.
struct FaceInTexels {
    std::vector<RimLine> rim;
};
std::vector<FaceInTexels> faces_in_texels(const Scene& scene, double reach);

// Overlaps of the beam of pixel (i, j) of an N x N PSF, clipped to the face's rim (in
// texel coordinates, from faces_in_texels), with its chart's texels.
int pixel_texel_overlaps(const PsfToTexel& map, int i, int j, int resolution,
                         const FaceInTexels& face, int width, int height,
                         std::vector<TexelOverlap>& out);

}  // namespace vlf
