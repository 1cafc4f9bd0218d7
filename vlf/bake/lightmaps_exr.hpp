// lightmaps_exr.hpp — lightmaps.exr, the diffuse total radiance P^T of every face as one
// half-RGB atlas image (DESIGN §6; docs/bake-format.md): written from and read back into
// the per-texel radiance of every chart (TextureMaps order, texel_offset per chart).
#pragma once

#include <string>
#include <vector>

#include "vlf/bake/atlas.hpp"
#include "vlf/bake/bundle_parts.hpp"
#include "vlf/core/math.hpp"

namespace vlf {

// Writes the atlas: chart c's texel (i, j) at pixel (x + i, y + j) of its rectangle, values
// clamped to the largest half, zeros elsewhere. Throws on OpenEXR errors.
void write_lightmaps_exr(const std::string& file, const Atlas& atlas,
                         const std::vector<Rgb>& radiance, const std::vector<size_t>& texel_offset);

// Reads the atlas back; `rects` (from the manifest) must lie inside the `atlas_width` x
// `atlas_height` image. Defects are reported through `errors` as part lightmaps.exr.
std::vector<Rgb> read_lightmaps_exr(const std::string& file, const std::vector<AtlasRect>& rects,
                                    int atlas_width, int atlas_height,
                                    const std::vector<size_t>& texel_offset,
                                    const BundleErrors& errors);

}  // namespace vlf
