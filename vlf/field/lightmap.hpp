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

// Outgoing diffuse radiance (W m^-2 sr^-1) of every texel of every chart from P^T, in
// TextureMaps order (chart c owns [maps.offset[c], maps.offset[c+1])); 0 for texels
// off their chart.
std::vector<Rgb> texel_radiance(const Scene& scene, const TextureMaps& maps);

// Radiance of chart `c` at `point` (normalised coordinates, on or near one of its faces):
// bilinear between texel centres — texel (i, j) has its centre at (i+0.5, j+0.5) in
// TexelFrame::to_texel coordinates — clamped at the grid's border. Unreliable texels
// (kReliableTexelFraction) get no weight, the others are renormalised; when none of the
// four is reliable, the value of the nearest texel with the largest area is used.
// `texel_radiance_of_chart` points at the chart's first texel (row-major j*width + i).
Rgb sample_lightmap(const Chart& c, const Rgb* texel_radiance_of_chart, const Vec3& point);

}  // namespace vlf
