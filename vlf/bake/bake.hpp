// bake.hpp — the bake bundle OUT.vlf/ (DESIGN §6; VLF §3 "layered depth images"):
//   manifest.json   format name/version, parameters, scene transform and units, ledger,
//                   timings, memory, SHA-256... (checksum) of every other file;
//   scene.json      the normalised scene, self-contained (faces, texel frames, materials,
//                   cameras, normalisation);
//   lightmaps.exr   P^T of every face as a half-RGB atlas (radiance, W m^-2 sr^-1);
//   lightfield.exr  multi-part OpenEXR, one deep tiled part per direction (N x N, tile
//                   m x m): per pixel, the fragments along that ray as deep samples
//                   (face id + outgoing radiance L_T) for specular faces (and for every
//                   face with --store-all-rays).
// Written under OUT.vlf.partial and renamed when complete.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vlf/field/direction_set.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/parameters.hpp"

namespace vlf {

class Transport;

inline constexpr const char* kBakeFormat = "vlf-bake";
// 2: ledger with loss causes, presets (issue 9); 3: perturb_cycles in the parameters
inline constexpr int kBakeVersion = 3;

// The stored rays of every direction as layered depth images: for direction d and pixel
// (i, j), samples [pixel_offset[(d*N + j)*N + i], pixel_offset[... + 1]) of face/radiance.
struct RayImages {
    int directions = 0;
    int resolution = 0;
    int tile = 0;
    std::vector<uint64_t> pixel_offset;  // directions * N * N + 1
    std::vector<int32_t> face;
    std::vector<RgbF> radiance;  // L_T, W m^-2 sr^-1, travelling along the face's front sense
    // Radiance of `face` on ray (d, i, j); false when the ray holds no sample of that face.
    bool lookup(int d, int i, int j, int face, RgbF& out) const;
};

// Everything walkthrough needs, in memory: made from a finished propagation or read back.
struct Bake {
    nlohmann::json manifest;
    Scene scene;
    PropagateParams params;
    DirectionSet directions{9};
    std::vector<Rgb>
        lightmap_radiance;             // per texel of every face (TextureMaps order), P^T radiance
    std::vector<size_t> texel_offset;  // faces + 1
    RayImages rays;
};

// In-memory bake from a finished propagation (no files); with_rays = false leaves
// bake.rays empty (write it with ray_source(scene, params, transport)).
Bake make_bake(const Scene& scene, const PropagateParams& params, const Transport& transport,
               const nlohmann::json& report, bool with_rays = true);

// One direction's stored rays as a layered depth image: per pixel (row-major, N x N) a
// sample count, the samples in pixel order, ascending face id within a pixel.
struct DirectionRays {
    std::vector<uint32_t> counts;
    std::vector<int32_t> face;
    std::vector<RgbF> radiance;
};
// Fills `out` with the stored rays of direction d (0 <= d < directions).
using RaySource = std::function<void(int d, DirectionRays& out)>;
RaySource ray_source(const RayImages& rays);
// Straight from a finished propagation's radiance maps: the bake's rays without holding
// all of them in memory (what propagate writes with).
RaySource ray_source(const Scene& scene, const PropagateParams& params, const Transport& transport);

// Writes the bundle atomically; throws Error naming the path on failure. The light field
// comes from `rays` when given (then bake.rays is not used), else from bake.rays.
void write_bake(const std::string& path, const Bake& bake, const RaySource& rays = nullptr);

// Reads and verifies a bundle; every defect (missing part, truncated or corrupted file,
// checksum mismatch, other format version, manifest inconsistent with the files) throws
// Error naming the bundle and the part.
Bake read_bake(const std::string& path);

// Scene <-> JSON (the self-contained normalised scene of the bundle), lossless.
nlohmann::json scene_to_json(const Scene& scene);
Scene scene_from_json(const nlohmann::json& j, const std::string& name);

}  // namespace vlf
