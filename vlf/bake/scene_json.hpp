// scene_json.hpp — the bundle's scene.json (DESIGN §6; docs/bake-format.md): the scene
// after loading and normalisation except its faces and charts, which are in geometry.bin
// (geometry_bin.hpp): materials, objects, cameras, the normalisation, written and read back
// losslessly (doubles in the shortest text that reads back to the same value).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "vlf/scene/scene.hpp"

namespace vlf {

nlohmann::json scene_to_json(const Scene& scene);
// [x, y, z]
nlohmann::json vec_json(const Vec3& v);

// Reads what scene_to_json wrote; every key is checked and unknown keys are refused.
// Throws Error "<file>: <json.path>: <problem>" (core/json_reader.hpp).
Scene scene_from_json(const nlohmann::json& j, const std::string& file);

}  // namespace vlf
