// manifest.hpp — the bundle's manifest.json (DESIGN §6; docs/bake-format.md): what the
// writer records (format and version, parameters, scene transform and units, the report's
// ledger, timings and memory, the atlas and light-field layout, the size and SHA-256 of
// every other file) and what the reader checks against it. Every reading function reports
// a defect through BundleErrors (bundle_parts.hpp).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vlf/bake/atlas.hpp"
#include "vlf/bake/bundle_parts.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/parameters.hpp"

namespace vlf {

inline constexpr const char* kBakeFormat = "vlf-bake";
// 2: ledger with loss causes, presets (issue 9); 3: perturb_cycles in the parameters
inline constexpr int kBakeVersion = 7;

// --- writing ---

// Format, version, parameters, scene transform, units, and the report's "ledger",
// "timings_s" and "memory_bytes" (null when the report has none).
nlohmann::json make_manifest(const Scene& scene, const PropagateParams& params,
                             const nlohmann::json& report);
// "lightmaps" (a rectangle per face), "lightmap_atlas" and "lightfield".
void record_layout(nlohmann::json& manifest, const Atlas& atlas, const FieldParams& field,
                   uint64_t samples);
// "files": the size and SHA-256 of scene.json, lightmaps.exr and lightfield.exr in `dir`.
void record_checksums(nlohmann::json& manifest, const std::string& dir);

// --- reading ---
// A defect of the manifest's JSON (a missing or unknown key, a wrong type) throws Error
// "<bundle>/manifest.json: <json.path>: <problem>" (core/json_reader.hpp); a defect of the
// files or a disagreement between the manifest and the files throws Error
// "<bundle>: <part>: <problem>" through `errors`.

// manifest.json of the bundle directory `dir`: present, JSON, this format and version,
// no unknown keys.
nlohmann::json read_manifest(const std::string& dir, const BundleErrors& errors);
// "files": exactly scene.json, lightmaps.exr and lightfield.exr, each present with the
// listed size and SHA-256.
void verify_files(const nlohmann::json& manifest, const std::string& dir,
                  const BundleErrors& errors);
PropagateParams manifest_parameters(const nlohmann::json& manifest, const BundleErrors& errors);
// "scene_transform" and "units" equal the scene's normalisation and units.
void check_scene_frame(const nlohmann::json& manifest, const Scene& scene,
                       const BundleErrors& errors);
// "lightmaps": the atlas rectangles, one per face, matching the faces' texel grids.
std::vector<AtlasRect> manifest_rects(const nlohmann::json& manifest, const Scene& scene,
                                      const BundleErrors& errors);
// "lightmap_atlas": the size of the atlas image.
void manifest_atlas_size(const nlohmann::json& manifest, const BundleErrors& errors, int& width,
                         int& height);
// "lightfield": directions, resolution and tile equal the parameters; samples equals the
// number of samples read.
void check_lightfield(const nlohmann::json& manifest, const FieldParams& field, uint64_t samples,
                      const BundleErrors& errors);

}  // namespace vlf
