// bundle_parts.hpp — the files of a bake bundle and how its readers report a defect: one
// line naming the bundle and the part, "<bundle>: <part>: <problem>" (docs/bake-format.md,
// "What the reader checks"). A problem inside a JSON file is reported by the JSON reader
// instead, as "<bundle>/<file>: <json.path>: <problem>". Internal to vlf/bake.
#pragma once

#include <fmt/format.h>

#include <string>

#include "vlf/core/error.hpp"

namespace vlf {

inline constexpr const char* kManifestFile = "manifest.json";
inline constexpr const char* kSceneFile = "scene.json";
inline constexpr const char* kGeometryFile = "geometry.bin";
inline constexpr const char* kTexturesFile = "textures.bin";
inline constexpr const char* kVertexLightFile = "vertexlight.bin";
inline constexpr const char* kLightmapsFile = "lightmaps.exr";
inline constexpr const char* kLightfieldFile = "lightfield.exr";

struct BundleErrors {
    std::string bundle;  // the bundle's path as given (without trailing slashes)

    // The path of one of its files, as messages name it.
    std::string file(const std::string& part) const { return bundle + "/" + part; }

    [[noreturn]] void fail(const std::string& part, const std::string& what) const {
        throw Error(fmt::format("{}: {}: {}", bundle, part, what));
    }
    [[noreturn]] void mismatch(const std::string& part, const std::string& what) const {
        fail(part, "manifest does not match its files: " + what);
    }
};

}  // namespace vlf
