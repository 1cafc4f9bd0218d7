#include "vlf/field/field_stats.hpp"

#include <cmath>

#include "vlf/core/parallel.hpp"
#include "vlf/core/stopwatch.hpp"

namespace vlf {

namespace {

struct DirectionTally {
    int64_t nonempty_tiles = 0, fragments = 0, covered = 0, specular = 0;
    int max_fragments = 0;
    double sum_sq = 0.0;
    PsfMemory memory;
};

}  // namespace

FieldStats measure_field(const Scene& scene, const FieldParams& params) {
    const Stopwatch clock;
    validate_raster(params.resolution, params.tile);
    const DirectionSet dirs(params.directions, params.scheme);
    std::vector<DirectionTally> tally(dirs.size());
    parallel_for(0, dirs.size(), [&](long d) {
        const Psf psf = rasterise_psf(scene, dirs.direction(static_cast<int>(d)),
                                      static_cast<int>(d), params.resolution, params.tile);
        DirectionTally& t = tally[d];
        t.nonempty_tiles = static_cast<int64_t>(psf.tiles.size());
        for (const Tile& tile : psf.tiles) {
            const int nf = static_cast<int>(tile.fragments.size());
            t.fragments += nf;
            t.sum_sq += double(nf) * nf;
            t.max_fragments = std::max(t.max_fragments, nf);
            t.covered += tile.covered;
            for (const Fragment& f : tile.fragments)
                if (scene.material_of(scene.faces[f.face]).is_specular()) t.specular += f.covered;
        }
        t.memory = memory_of(psf);
    });

    FieldStats s;
    s.params = params;
    const int64_t n = params.resolution / params.tile;
    s.tiles_total = static_cast<int64_t>(dirs.size()) * n * n;
    double sum_sq = 0.0;
    for (const DirectionTally& t : tally) {  // in direction order: deterministic
        s.nonempty_tiles += t.nonempty_tiles;
        s.fragments += t.fragments;
        s.covered_rays += t.covered;
        s.specular_rays += t.specular;
        s.fragments_per_tile_max = std::max(s.fragments_per_tile_max, t.max_fragments);
        sum_sq += t.sum_sq;
        s.memory.tiles += static_cast<int64_t>(t.memory.tiles);
        s.memory.fragments += static_cast<int64_t>(t.memory.fragments);
        s.memory.edge_tables += static_cast<int64_t>(t.memory.edge_tables);
    }
    if (s.nonempty_tiles > 0) {
        s.fragments_per_tile_mean = double(s.fragments) / s.nonempty_tiles;
        const double var =
            sum_sq / s.nonempty_tiles - s.fragments_per_tile_mean * s.fragments_per_tile_mean;
        s.fragments_per_tile_stddev = std::sqrt(std::max(0.0, var));
    }
    s.solid_angle_spread = dirs.solid_angle_spread();
    s.memory.directions =
        static_cast<int64_t>(dirs.size()) * static_cast<int64_t>(sizeof(Vec3) + sizeof(double)) +
        static_cast<int64_t>(dirs.triangles().size() * sizeof(DirectionSet::Triangle));
    // L_U and L_T, RGB float, per covered ray of a specular fragment.
    s.memory.radiance_maps = s.specular_rays * 2 * 3 * static_cast<int64_t>(sizeof(float));
    int64_t texels = 0;
    for (const Chart& c : scene.charts) texels += c.texels.count();
    s.memory.texture_maps = texels * 3 * 3 * static_cast<int64_t>(sizeof(double));
    s.seconds = clock.seconds();
    return s;
}

nlohmann::json to_json(const FieldStats& s) {
    return {{"directions", s.params.directions},
            {"scheme", to_string(s.params.scheme)},
            {"resolution", s.params.resolution},
            {"tile", s.params.tile},
            {"tiles_per_side", s.params.resolution / s.params.tile},
            {"tiles_total", s.tiles_total},
            {"nonempty_tiles", s.nonempty_tiles},
            {"fragments", s.fragments},
            {"fragments_per_tile_mean", s.fragments_per_tile_mean},
            {"fragments_per_tile_stddev", s.fragments_per_tile_stddev},
            {"fragments_per_tile_max", s.fragments_per_tile_max},
            {"covered_rays", s.covered_rays},
            {"specular_rays", s.specular_rays},
            {"solid_angle_spread", s.solid_angle_spread},
            {"memory_bytes",
             {{"directions", s.memory.directions},
              {"tiles", s.memory.tiles},
              {"fragments", s.memory.fragments},
              {"edge_tables", s.memory.edge_tables},
              {"radiance_maps", s.memory.radiance_maps},
              {"texture_maps", s.memory.texture_maps},
              {"total", s.memory.total()}}},
            {"seconds", s.seconds}};
}

}  // namespace vlf
