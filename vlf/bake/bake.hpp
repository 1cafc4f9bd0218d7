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
// Written under OUT.vlf.partial and renamed when complete. This is the bundle as a whole;
// its parts are in manifest.hpp, scene_json.hpp, atlas.hpp + lightmaps_exr.hpp,
// ray_images.hpp + lightfield_exr.hpp.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vlf/bake/manifest.hpp"
#include "vlf/bake/ray_images.hpp"
#include "vlf/bake/vertex_light.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/parameters.hpp"

namespace vlf {

class Transport;

// Everything walkthrough needs, in memory: made from a finished propagation or read back.
struct Bake {
    nlohmann::json manifest;
    Scene scene;
    PropagateParams params;
    DirectionSet directions{9};
    std::vector<Rgb>
        lightmap_radiance;             // per texel of every chart (TextureMaps order), P^T radiance
    std::vector<size_t> texel_offset;  // charts + 1
    RayImages rays;
    // The final gather's light at the vertices of faces too small for the field
    // (render/final_gather.hpp); empty when none was gathered.
    VertexLight vertex_light;
};

// In-memory bake from a finished propagation (no files), without the final gather
// (render/final_gather.hpp final_gather(bake) adds it); with_rays = false leaves
// bake.rays empty (write it with ray_source(scene, params, transport)).
Bake make_bake(const Scene& scene, const PropagateParams& params, const Transport& transport,
               const nlohmann::json& report, bool with_rays = true);

// Writes the bundle atomically; throws Error naming the path on failure. The light field
// comes from `rays` when given (then bake.rays is not used), else from bake.rays.
void write_bake(const std::string& path, const Bake& bake, const RaySource& rays = nullptr);

// Reads and verifies a bundle; every defect (missing part, truncated or corrupted file,
// checksum mismatch, other format version, manifest inconsistent with the files) throws
// Error naming the bundle and the part.
Bake read_bake(const std::string& path);

}  // namespace vlf
