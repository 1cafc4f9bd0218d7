// vertex_light_bin.hpp — the bundle's vertexlight.bin (docs/bake-format.md): the final
// gather's light at the vertices of the faces it covers (vertex_light.hpp). Written for every
// bake; a bake without gathered faces writes an empty one.
#pragma once

#include <string>

#include "vlf/bake/vertex_light.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Writes `light` (for the faces of `scene`) to `file`.
void write_vertex_light(const std::string& file, const Scene& scene, const VertexLight& light);

// Reads it back for `scene`, whose faces are already read: face indices, counts and values
// (finite, not negative) are checked, and a defect throws Error "<file>: <problem>".
VertexLight read_vertex_light(const std::string& file, const Scene& scene);

}  // namespace vlf
