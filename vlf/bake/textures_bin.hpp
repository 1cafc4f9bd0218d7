// textures_bin.hpp — the bundle's textures.bin (docs/bake-format.md): the scene's diffuse
// colour textures and its faces' texture coordinates, so a textured bake renders its
// textures at full resolution without the model's files (issue 12). Written for every
// bake; a scene without textures writes an empty one.
#pragma once

#include <string>

#include "vlf/scene/scene.hpp"

namespace vlf {

// Writes scene.textures and every face's uv to `file`.
void write_textures(const std::string& file, const Scene& scene);

// Reads them into `scene`, whose faces and materials are already read: counts, sizes and
// indices are checked, and a defect throws Error "<file>: <problem>".
void read_textures(const std::string& file, Scene& scene);

}  // namespace vlf
