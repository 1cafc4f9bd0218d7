// manifest.cpp — the bundle's manifest.json, written and checked (manifest.hpp).
#include "vlf/bake/manifest.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "vlf/bake/scene_json.hpp"
#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/json_reader.hpp"

namespace vlf {

namespace fs = std::filesystem;
using nlohmann::json;

json make_manifest(const Scene& scene, const PropagateParams& params, const json& report) {
    auto from_report = [&](const char* key) {
        return report.is_object() && report.contains(key) ? report[key] : json(nullptr);
    };
    return {
        {"format", kBakeFormat},
        {"version", kBakeVersion},
        {"parameters", to_json(params)},
        {"scene_transform",
         {{"center", vec_json(scene.normalisation.center)}, {"scale", scene.normalisation.scale}}},
        {"units", scene.units},
        {"ledger", from_report("ledger")},
        {"timings_s", from_report("timings_s")},
        {"memory_bytes", from_report("memory_bytes")},
        {"files", json::object()}};
}

void record_layout(json& manifest, const Atlas& atlas, const FieldParams& field, uint64_t samples) {
    json rects = json::array();
    for (const AtlasRect& r : atlas.rects)
        rects.push_back(
            {{"chart", r.chart}, {"x", r.x}, {"y", r.y}, {"width", r.width}, {"height", r.height}});
    manifest["lightmaps"] = rects;
    manifest["lightmap_atlas"] = {{"width", atlas.width}, {"height", atlas.height}};
    manifest["lightfield"] = {{"directions", field.directions},
                              {"resolution", field.resolution},
                              {"tile", field.tile},
                              {"samples", samples}};
}

void record_checksums(json& manifest, const std::string& dir) {
    json files = json::object();
    for (const char* name : {kSceneFile, kGeometryFile, kTexturesFile, kVertexLightFile,
                             kLightmapsFile, kLightfieldFile}) {
        uint64_t bytes = 0;
        const std::string sha = sha256_file((fs::path(dir) / name).string(), bytes);
        files[name] = {{"bytes", bytes}, {"sha256", sha}};
    }
    manifest["files"] = files;
}

// ---------------------------------------------------------------------------------------

namespace {

JsonReader reader(const json& manifest, const BundleErrors& errors) {
    return JsonReader(manifest, errors.file(kManifestFile));
}

}  // namespace

json read_manifest(const std::string& dir, const BundleErrors& errors) {
    const fs::path file = fs::path(dir) / kManifestFile;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) errors.fail(kManifestFile, "is missing");
    const json m = read_json_file(errors.file(kManifestFile));
    const JsonReader r = reader(m, errors);
    r.expect_object();
    // Format and version first: another version may well have other keys.
    if (!r.has("format"))
        r.fail(fmt::format("not a {} manifest (it has no \"format\")", kBakeFormat));
    const JsonReader format = r.required("format");
    if (format.string() != kBakeFormat)
        format.fail(fmt::format("not a {} manifest (format {})", kBakeFormat,
                                describe_json(format.json())));
    const JsonReader version = r.required("version");
    if (const int64_t v = version.integer64(); v != kBakeVersion)
        version.fail(fmt::format("format version {} is not supported (this build reads {})", v,
                                 kBakeVersion));
    r.only_keys({"format", "version", "parameters", "scene_transform", "units", "ledger",
                 "timings_s", "memory_bytes", "files", "lightmaps", "lightmap_atlas",
                 "lightfield"});
    return m;
}

namespace {

void verify_file(const fs::path& file, const std::string& name, uint64_t want_bytes,
                 const std::string& want_sha, const BundleErrors& errors) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) errors.fail(name, "is missing");
    const uint64_t size = fs::file_size(file, ec);
    if (ec) errors.fail(name, "cannot be read");
    if (size != want_bytes)
        errors.fail(name, fmt::format("{} bytes, the manifest says {} ({})", size, want_bytes,
                                      size < want_bytes ? "truncated" : "overlong"));
    uint64_t hashed = 0;
    std::string sha;
    try {
        sha = sha256_file(file.string(), hashed);
    } catch (const Error&) {
        errors.fail(name, "cannot be read");
    }
    if (hashed != want_bytes) errors.fail(name, "changed while being read");
    if (sha != want_sha)
        errors.fail(name, "checksum mismatch (sha256 " + sha + ", the manifest says " + want_sha +
                              "): the file is corrupted");
}

bool is_sha256_hex(const std::string& s) {
    return s.size() == 64 && s.find_first_not_of("0123456789abcdef") == std::string::npos;
}

}  // namespace

void verify_files(const json& manifest, const std::string& dir, const BundleErrors& errors) {
    const JsonReader files = reader(manifest, errors).required("files");
    files.only_keys({kSceneFile, kGeometryFile, kTexturesFile, kVertexLightFile, kLightmapsFile,
                     kLightfieldFile});
    for (const char* name : {kSceneFile, kGeometryFile, kTexturesFile, kVertexLightFile,
                             kLightmapsFile, kLightfieldFile})
        files.required(name);
    for (const auto& [name, entry] : files.members()) {  // in the manifest's (sorted) order
        entry.only_keys({"bytes", "sha256"});
        const uint64_t bytes = entry.required("bytes").unsigned64();
        const JsonReader sha = entry.required("sha256");
        if (!is_sha256_hex(sha.string()))
            sha.fail(fmt::format("expected 64 lower-case hex digits, got {}",
                                 describe_json(sha.json())));
        verify_file(fs::path(dir) / name, name, bytes, sha.string(), errors);
    }
}

PropagateParams manifest_parameters(const json& manifest, const BundleErrors& errors) {
    return propagate_params_from_json(reader(manifest, errors).required("parameters"));
}

void check_scene_frame(const json& manifest, const Scene& scene, const BundleErrors& errors) {
    const JsonReader r = reader(manifest, errors);
    const JsonReader st = r.required("scene_transform");
    st.only_keys({"center", "scale"});
    const Vec3 c = st.required("center").vec3();
    const double s = st.required("scale").number();
    if (c != scene.normalisation.center || s != scene.normalisation.scale)
        errors.mismatch(kSceneFile, "scene_transform differs from the scene's normalisation");
    const std::string units = r.required("units").string();
    if (units != scene.units)
        errors.mismatch(kSceneFile,
                        fmt::format("units '{}', the manifest says '{}'", scene.units, units));
}

namespace {

AtlasRect read_rect(const JsonReader& r) {
    r.only_keys({"chart", "x", "y", "width", "height"});
    return {r.required("chart").integer(), r.required("x").integer(), r.required("y").integer(),
            r.required("width").integer(), r.required("height").integer()};
}

}  // namespace

std::vector<AtlasRect> manifest_rects(const json& manifest, const Scene& scene,
                                      const BundleErrors& errors) {
    const std::vector<JsonReader> list = reader(manifest, errors).required("lightmaps").elements();
    if (list.size() != scene.charts.size())
        errors.mismatch(kLightmapsFile, fmt::format("{} atlas rectangles for {} charts",
                                                    list.size(), scene.charts.size()));
    std::vector<AtlasRect> rects(list.size());
    for (size_t k = 0; k < list.size(); ++k) {
        const AtlasRect a = read_rect(list[k]);
        if (a.chart != static_cast<int>(k))
            errors.mismatch(kLightmapsFile, fmt::format("lightmaps[{}] is chart {}", k, a.chart));
        const TexelFrame& t = scene.charts[k].texels;
        if (a.width != t.width || a.height != t.height)
            errors.mismatch(kLightmapsFile,
                            fmt::format("chart {}: atlas rectangle {}x{}, texel grid {}x{}", k,
                                        a.width, a.height, t.width, t.height));
        rects[k] = a;
    }
    return rects;
}

void manifest_atlas_size(const json& manifest, const BundleErrors& errors, int& width,
                         int& height) {
    const JsonReader atlas = reader(manifest, errors).required("lightmap_atlas");
    atlas.only_keys({"width", "height"});
    width = atlas.required("width").integer(1);
    height = atlas.required("height").integer(1);
}

void check_lightfield(const json& manifest, const FieldParams& field, uint64_t samples,
                      const BundleErrors& errors) {
    const JsonReader lf = reader(manifest, errors).required("lightfield");
    lf.only_keys({"directions", "resolution", "tile", "samples"});
    const std::pair<const char*, int> counts[] = {
        {"directions", field.directions}, {"resolution", field.resolution}, {"tile", field.tile}};
    for (const auto& [key, want] : counts) {
        const JsonReader v = lf.required(key);
        if (v.integer() != want)
            v.fail(fmt::format("{}, the parameters say {}", v.integer(), want));
    }
    const uint64_t listed = lf.required("samples").unsigned64();
    if (listed != samples)
        errors.mismatch(kLightfieldFile,
                        fmt::format("{} samples, the manifest says {}", samples, listed));
}

}  // namespace vlf
