// report.hpp — what a run tells its user: the scene summary and light-field statistics,
// as text for the terminal and as JSON for --report files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "vlf/field/field_stats.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// {"faces", "objects", "materials", "emitters", "specular_faces", "texels", "bounds", ...}
nlohmann::json scene_summary(const Scene& scene);

std::string format_scene_summary(const Scene& scene);
std::string format_field_stats(const FieldStats& stats);
std::string format_bytes(int64_t bytes);

}  // namespace vlf
