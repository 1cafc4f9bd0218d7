// geometry_bin.hpp — the bundle's geometry.bin (docs/bake-format.md): every face and chart of
// the normalised scene in binary, little-endian arrays, so a million-triangle bake writes
// and loads in seconds (scene.json holds the rest: materials, objects, cameras,
// normalisation). Written and read back bit for bit.
#pragma once

#include <string>

#include "vlf/scene/scene.hpp"

namespace vlf {

// Writes scene.faces and scene.charts to `file`.
void write_geometry(const std::string& file, const Scene& scene);

// Reads them into `scene`, whose materials and objects are already read: every count,
// index, offset and number is checked, and a defect throws Error "<file>: <problem>".
void read_geometry(const std::string& file, Scene& scene);

}  // namespace vlf
