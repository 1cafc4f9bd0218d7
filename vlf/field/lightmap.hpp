// lightmap.hpp — reading the diffuse Total Texture Maps P^T as radiance at a point of a
// face (VLF §6.3: "using bilinear interpolation pick up a value from its Total Texture Map
// P^T"; §6.2 texture mode). Shared by the walkthrough renderers and the backward
// ray-traced re-sampling of specular maps (VLF §5, resample.hpp).
#pragma once

#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Texels whose area inside the polygon is below this fraction of a full texel are too
// unreliable to interpolate from: their radiance is power / a tiny area.
inline constexpr double kReliableTexelFraction = 0.25;

// Outgoing diffuse radiance (W m^-2 sr^-1) of every texel of every face from P^T, in
// TextureMaps order (face f owns [maps.offset[f], maps.offset[f+1])); 0 for texels
// outside their polygon.
std::vector<Rgb> texel_radiance(const Scene& scene, const TextureMaps& maps);

// Radiance of face `f` at `point` (normalised coordinates, on or near the face's plane):
// bilinear between texel centres — texel (i, j) has its centre at (i+0.5, j+0.5) in
// TexelFrame::to_texel coordinates — clamped at the grid's border. Unreliable texels
// (kReliableTexelFraction) get no weight, the others are renormalised; when none of the
// four is reliable, the value of the nearest texel with the largest area is used.
// `texel_radiance_of_face` points at the face's first texel (row-major j*width + i).
Rgb sample_lightmap(const Face& f, const Rgb* texel_radiance_of_face, const Vec3& point);

}  // namespace vlf
