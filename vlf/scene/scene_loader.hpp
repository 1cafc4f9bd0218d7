// scene_loader.hpp — JSON scene files to a Scene, in stages: parse -> validate -> build
// (DESIGN §3). Every problem throws vlf::SceneError naming the file and the JSON place,
// e.g. "scenes/room.json: objects[3].material: unknown material 'glas'".
#pragma once

#include <string>

#include "vlf/scene/charts.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct LoadOptions {
    // Texel edge length in user units; <= 0 means: the scene's "settings.texel_size",
    // or when that is absent, the scene's bounding-sphere radius / 32.
    double texel_size_user = 0.0;
    // ... and when the scene gives none either: its bounding-sphere radius / this.
    int texel_divisions = 32;
    // A face's texel grid is capped at this many texels per side (the texel size grows
    // for that face only, never silently shrinks the whole scene).
    int max_texels_per_side = 512;
    // Faces join a chart while their normals lie within this angle of its first face's
    // (charts.hpp); 0 gives every face a chart of its own.
    double chart_angle_deg = kChartAngleDeg;
};

Scene load_scene(const std::string& path, const LoadOptions& options = {});

// Same, from text already in memory. `name` is used in messages, `base_dir` resolves
// relative mesh paths.
Scene load_scene_from_string(const std::string& json_text, const std::string& name,
                             const std::string& base_dir, const LoadOptions& options = {});

}  // namespace vlf
