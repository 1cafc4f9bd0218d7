#include "vlf/transport/report.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {
nlohmann::json vec(const Vec3& v) {
    return {v.x, v.y, v.z};
}
}  // namespace

nlohmann::json scene_summary(const Scene& scene) {
    int64_t texels = 0;
    double area = 0.0;
    for (const Face& f : scene.faces) area += f.area;
    for (const Chart& c : scene.charts) texels += c.texels.count();
    const double s2 = scene.normalisation.scale * scene.normalisation.scale;
    return {{"source", scene.source},
            {"units", scene.units},
            {"faces", scene.faces.size()},
            {"charts", scene.charts.size()},
            {"objects", scene.objects.size()},
            {"materials", scene.materials.size()},
            {"emitters", scene.emitter_count()},
            {"specular_faces", scene.specular_face_count()},
            {"cameras", scene.cameras.size()},
            {"texels", texels},
            {"texel_size", scene.texel_size_user},
            {"surface_area", area / s2},
            {"bounds", {{"min", vec(scene.user_bounds_min)}, {"max", vec(scene.user_bounds_max)}}},
            {"normalisation",
             {{"center", vec(scene.normalisation.center)}, {"scale", scene.normalisation.scale}}}};
}

std::string format_bytes(int64_t bytes) {
    const double b = static_cast<double>(bytes);
    if (b >= 1024.0 * 1024 * 1024) return fmt::format("{:.2f} GiB", b / (1024.0 * 1024 * 1024));
    if (b >= 1024.0 * 1024) return fmt::format("{:.1f} MiB", b / (1024.0 * 1024));
    if (b >= 1024.0) return fmt::format("{:.1f} KiB", b / 1024.0);
    return fmt::format("{} B", bytes);
}

std::string format_scene_summary(const Scene& scene) {
    const nlohmann::json j = scene_summary(scene);
    const Vec3 &a = scene.user_bounds_min, &b = scene.user_bounds_max;
    return fmt::format(
        "scene      {}\n"
        "  faces {}  objects {}  materials {}  emitters {}  specular faces {}  cameras {}\n"
        "  bounds [{:.4g}, {:.4g}, {:.4g}] .. [{:.4g}, {:.4g}, {:.4g}]{}\n"
        "  normalised: p' = (p - [{:.4g}, {:.4g}, {:.4g}]) * {:.6g}\n"
        "  texels {} (texel size {:.4g})\n",
        scene.source, scene.faces.size(), scene.objects.size(), scene.materials.size(),
        scene.emitter_count(), scene.specular_face_count(), scene.cameras.size(), a.x, a.y, a.z,
        b.x, b.y, b.z, scene.units.empty() ? "" : " " + scene.units, scene.normalisation.center.x,
        scene.normalisation.center.y, scene.normalisation.center.z, scene.normalisation.scale,
        j["texels"].get<int64_t>(), scene.texel_size_user);
}

std::string format_field_stats(const FieldStats& s) {
    const auto& m = s.memory;
    return fmt::format(
        "light field\n"
        "  directions {} ({}, solid-angle spread {:.3f})  resolution {}x{}  tiles {}x{} of {}x{}\n"
        "  non-empty tiles {} of {}  fragments {}  per tile mean {:.2f} (sd {:.2f}) max {}\n"
        "  covered rays {}  on specular faces {}\n"
        "  estimated memory {}: directions {}, tiles {}, fragments {}, edge tables {},\n"
        "                        radiance maps {}, texture maps {}\n"
        "  rasterised in {:.3f} s\n",
        s.params.directions, to_string(s.params.scheme), s.solid_angle_spread, s.params.resolution,
        s.params.resolution, s.params.resolution / s.params.tile,
        s.params.resolution / s.params.tile, s.params.tile, s.params.tile, s.nonempty_tiles,
        s.tiles_total, s.fragments, s.fragments_per_tile_mean, s.fragments_per_tile_stddev,
        s.fragments_per_tile_max, s.covered_rays, s.specular_rays, format_bytes(m.total()),
        format_bytes(m.directions), format_bytes(m.tiles), format_bytes(m.fragments),
        format_bytes(m.edge_tables), format_bytes(m.radiance_maps), format_bytes(m.texture_maps),
        s.seconds);
}

}  // namespace vlf
