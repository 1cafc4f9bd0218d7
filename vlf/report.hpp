// report.hpp — what a run tells its user: the scene summary and light-field statistics,
// as text for the terminal and as JSON for --report files.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "vlf/light_field.hpp"
#include "vlf/scene.hpp"

namespace vlf {

// {"faces", "objects", "materials", "emitters", "specular_faces", "texels", "bounds", ...}
nlohmann::json scene_summary(const Scene& scene);

std::string format_scene_summary(const Scene& scene);
std::string format_field_stats(const FieldStats& stats);
std::string format_bytes(int64_t bytes);

// Fails early (before any work) when `path` cannot be written: its directory must exist
// and be writable. Throws ParameterError naming the path.
void check_output_path(const std::string& path);

// Writes JSON to `path` through a temporary file renamed when complete, so a reader never
// sees a half-written report. Throws Error naming the path when it cannot be written.
void write_json_atomically(const std::string& path, const nlohmann::json& j);

}  // namespace vlf
