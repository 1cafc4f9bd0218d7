// field_stats.hpp — statistics of the whole virtual light field (VLF §3: one PSF per
// direction of the direction set) for `propagate --dry-run` and the reports: tiles,
// fragments, covered rays and the memory a propagation would need. Every direction is
// rasterised and dropped, so any l fits in memory. (The field a propagation uses lives in
// Transport, transport/transport.hpp.)
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "vlf/field/field_params.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct FieldStats {
    FieldParams params;
    int64_t tiles_total = 0;  // l * n^2
    int64_t nonempty_tiles = 0;
    int64_t fragments = 0;
    int fragments_per_tile_max = 0;
    double fragments_per_tile_mean = 0.0;  // over non-empty tiles
    double fragments_per_tile_stddev = 0.0;
    int64_t covered_rays = 0;         // (ray, fragment) pairs over all directions
    int64_t specular_rays = 0;        // of those, on faces with rho_s > 0
    double solid_angle_spread = 0.0;  // max/min solid angle of the direction set
    // Estimated memory of a propagation with these parameters, bytes, by structure.
    struct Memory {
        int64_t directions = 0;     // direction vectors, solid angles, triangles
        int64_t tiles = 0;          // tile headers and tile index
        int64_t fragments = 0;      // fragment records
        int64_t edge_tables = 0;    // spans
        int64_t radiance_maps = 0;  // L_U and L_T (RGB float) of specular fragments
        int64_t texture_maps = 0;   // P^C, P^N, P^T (RGB double) of every face
        int64_t total() const {
            return directions + tiles + fragments + edge_tables + radiance_maps + texture_maps;
        }
    } memory;
    double seconds = 0.0;  // wall time of the measurement
};

// Rasterises every direction, keeps only the statistics (any l fits in memory).
FieldStats measure_field(const Scene& scene, const FieldParams& params);

nlohmann::json to_json(const FieldStats& s);

}  // namespace vlf
