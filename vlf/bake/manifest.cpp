// manifest.cpp — the bundle's manifest.json, written and checked (manifest.hpp).
#include "vlf/bake/manifest.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"

namespace vlf {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json vec_json(const Vec3& v) {
    return json::array({v.x, v.y, v.z});
}

Vec3 vec_from(const json& j) {
    if (!j.is_array() || j.size() != 3) throw Error("expected an array of 3 numbers");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

}  // namespace

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
            {{"face", r.face}, {"x", r.x}, {"y", r.y}, {"width", r.width}, {"height", r.height}});
    manifest["lightmaps"] = rects;
    manifest["lightmap_atlas"] = {{"width", atlas.width}, {"height", atlas.height}};
    manifest["lightfield"] = {{"directions", field.directions},
                              {"resolution", field.resolution},
                              {"tile", field.tile},
                              {"samples", samples}};
}

void record_checksums(json& manifest, const std::string& dir) {
    json files = json::object();
    for (const char* name : {kSceneFile, kLightmapsFile, kLightfieldFile}) {
        uint64_t bytes = 0;
        const std::string sha = sha256_file((fs::path(dir) / name).string(), bytes);
        files[name] = {{"bytes", bytes}, {"sha256", sha}};
    }
    manifest["files"] = files;
}

// ---------------------------------------------------------------------------------------

json read_manifest(const std::string& dir, const BundleErrors& errors) {
    const fs::path file = fs::path(dir) / kManifestFile;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) errors.fail(kManifestFile, "is missing");
    std::ifstream in(file, std::ios::binary);
    if (!in) errors.fail(kManifestFile, "cannot be opened");
    json m;
    try {
        m = json::parse(in);
    } catch (const json::exception& e) {
        errors.fail(kManifestFile, fmt::format("not valid JSON ({})", e.what()));
    }
    if (!m.is_object() || !m.contains("format") || !m["format"].is_string() ||
        m["format"].get<std::string>() != kBakeFormat)
        errors.fail(kManifestFile, fmt::format("not a {} manifest", kBakeFormat));
    if (!m.contains("version") || !m["version"].is_number_integer())
        errors.fail(kManifestFile, "format version is missing");
    const auto version = m["version"].get<int64_t>();
    if (version != kBakeVersion)
        errors.fail(kManifestFile,
                    fmt::format("format version {} is not supported (this build reads {})", version,
                                kBakeVersion));
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

}  // namespace

void verify_files(const json& manifest, const std::string& dir, const BundleErrors& errors) {
    if (!manifest.contains("files") || !manifest["files"].is_object())
        errors.fail(kManifestFile, "files: missing");
    const json& files = manifest["files"];
    for (const char* required : {kSceneFile, kLightmapsFile, kLightfieldFile})
        if (!files.contains(required))
            errors.fail(kManifestFile, fmt::format("files: {} is not listed", required));
    for (const auto& [name, entry] : files.items()) {
        if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
            errors.fail(kManifestFile, fmt::format("files: '{}' is not a file name", name));
        uint64_t want_bytes = 0;
        std::string want_sha;
        try {
            want_bytes = entry.at("bytes").get<uint64_t>();
            want_sha = entry.at("sha256").get<std::string>();
        } catch (const json::exception& e) {
            errors.fail(kManifestFile, fmt::format("files.{}: {}", name, e.what()));
        }
        verify_file(fs::path(dir) / name, name, want_bytes, want_sha, errors);
    }
}

PropagateParams manifest_parameters(const json& manifest, const BundleErrors& errors) {
    if (!manifest.contains("parameters")) errors.fail(kManifestFile, "parameters: missing");
    try {
        return propagate_params_from_json(manifest["parameters"]);
    } catch (const Error& e) {
        errors.fail(kManifestFile, e.what());
    }
}

void check_scene_transform(const json& manifest, const Scene& scene, const BundleErrors& errors) {
    try {
        const json& st = manifest.at("scene_transform");
        const Vec3 c = vec_from(st.at("center"));
        const double s = st.at("scale").get<double>();
        if (c != scene.normalisation.center || s != scene.normalisation.scale)
            errors.mismatch(kSceneFile, "scene_transform differs from the scene's normalisation");
    } catch (const json::exception& e) {
        errors.fail(kManifestFile, fmt::format("scene_transform: {}", e.what()));
    }
}

std::vector<AtlasRect> manifest_rects(const json& manifest, const Scene& scene,
                                      const BundleErrors& errors) {
    if (!manifest.contains("lightmaps") || !manifest["lightmaps"].is_array())
        errors.fail(kManifestFile, "lightmaps: missing");
    const json& list = manifest["lightmaps"];
    if (list.size() != scene.faces.size())
        errors.mismatch(kLightmapsFile, fmt::format("{} atlas rectangles for {} faces", list.size(),
                                                    scene.faces.size()));
    std::vector<AtlasRect> rects(list.size());
    try {
        for (size_t k = 0; k < list.size(); ++k) {
            const json& e = list[k];
            AtlasRect a{e.at("face").get<int>(), e.at("x").get<int>(), e.at("y").get<int>(),
                        e.at("width").get<int>(), e.at("height").get<int>()};
            if (a.face != static_cast<int>(k))
                errors.mismatch(kLightmapsFile, fmt::format("lightmaps[{}] is face {}", k, a.face));
            const TexelFrame& t = scene.faces[k].texels;
            if (a.width != t.width || a.height != t.height)
                errors.mismatch(kLightmapsFile,
                                fmt::format("face {}: atlas rectangle {}x{}, texel grid {}x{}", k,
                                            a.width, a.height, t.width, t.height));
            rects[k] = a;
        }
    } catch (const json::exception& e) {
        errors.fail(kManifestFile, fmt::format("lightmaps: {}", e.what()));
    }
    return rects;
}

void check_samples(const json& manifest, uint64_t samples, const BundleErrors& errors) {
    if (!manifest.contains("lightfield") || !manifest["lightfield"].contains("samples")) return;
    const json& s = manifest["lightfield"]["samples"];
    if (!s.is_number_unsigned() || s.get<uint64_t>() != samples)
        errors.mismatch(kLightfieldFile,
                        fmt::format("{} samples, the manifest says {}", samples, s.dump()));
}

}  // namespace vlf
