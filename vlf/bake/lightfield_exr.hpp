// lightfield_exr.hpp — lightfield.exr, the stored rays as a multi-part deep tiled OpenEXR
// file (DESIGN §6; VLF §3 "layered depth images"; docs/bake-format.md): one part per line
// direction, N x N pixels in m x m tiles (the EXR tiles are the VLF tiles), per pixel the
// fragments along that ray as deep samples (channel `face` UINT, `R` `G` `B` FLOAT L_T).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vlf/bake/bundle_parts.hpp"
#include "vlf/bake/ray_images.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/field_params.hpp"

namespace vlf {

// Writes every direction of `source`, each part carrying its direction and solid angle.
// Returns the number of samples written. Throws on OpenEXR errors.
uint64_t write_lightfield_exr(const std::string& file, const FieldParams& field,
                              const DirectionSet& directions, const RaySource& source);

// What the manifest says lightfield.exr holds.
struct LightfieldLayout {
    int directions = 0, resolution = 0, tile = 0;
    std::vector<bool> stored;  // per face: whether it has stored rays
};

// Reads and validates every part (names, types, windows, tiles, channels; samples of stored
// faces in range, ascending face order per pixel, finite radiance). Defects are reported
// through `errors` as "lightfield.exr" or "lightfield.exr: part <d>".
RayImages read_lightfield_exr(const std::string& file, const LightfieldLayout& layout,
                              const BundleErrors& errors);

}  // namespace vlf
