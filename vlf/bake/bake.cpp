// bake.cpp — the bake bundle as a whole (bake.hpp): a bake made from a finished
// propagation, written atomically (OUT.vlf.partial, then renamed), read back and verified
// part by part.
#include "vlf/bake/bake.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "vlf/bake/atlas.hpp"
#include "vlf/bake/bundle_parts.hpp"
#include "vlf/bake/geometry_bin.hpp"
#include "vlf/bake/lightfield_exr.hpp"
#include "vlf/bake/lightmaps_exr.hpp"
#include "vlf/bake/scene_json.hpp"
#include "vlf/bake/textures_bin.hpp"
#include "vlf/bake/vertex_light_bin.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"
#include "vlf/core/json_reader.hpp"
#include "vlf/scene/texel_albedo.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string strip_slashes(std::string p) {
    while (p.size() > 1 && p.back() == '/') p.pop_back();
    return p;
}

}  // namespace

Bake make_bake(const Scene& scene, const PropagateParams& params, const Transport& transport,
               const json& report, bool with_rays) {
    Bake b;
    b.scene = scene;
    b.params = params;
    b.directions = transport.directions();
    b.manifest = make_manifest(scene, params, report);

    // Diffuse total radiance per texel (VLF §4.1 P^T, DESIGN §6 lightmaps).
    const TextureMaps& tex = transport.texture_maps();
    b.texel_offset = tex.offset;
    b.lightmap_radiance.resize(tex.texels());
    for (const Chart& c : scene.charts)
        for (size_t t = 0; t < tex.count(c.id); ++t)
            b.lightmap_radiance[tex.begin(c.id) + t] = tex.radiance(c, t);

    // Stored rays as layered depth images, one direction at a time.
    if (with_rays)
        b.rays = gather_rays(ray_source(scene, params, transport), transport.directions().size(),
                             params.field.resolution, params.field.tile);
    return b;
}

// ---------------------------------------------------------------------------------------
// Writing

namespace {

// A bundle being replaced must be one: never delete an unrelated directory.
void check_replaceable(const fs::path& dest) {
    std::error_code ec;
    if (fs::exists(dest, ec) && fs::is_directory(dest, ec) && !fs::is_empty(dest, ec) &&
        !fs::exists(dest / kManifestFile, ec))
        throw Error("exists and is not a bake bundle (no manifest.json); not replacing it");
    if (fs::exists(dest, ec) && !fs::is_directory(dest, ec))
        throw Error("exists and is not a directory");
}

// Every file of the bundle into `dir`, the manifest last; `step` names the file being written.
void write_parts(const fs::path& dir, const Bake& bake, const RaySource& rays, std::string& step) {
    json manifest = bake.manifest;
    step = kSceneFile;
    write_text((dir / kSceneFile).string(), scene_to_json(bake.scene).dump(1) + "\n");
    step = kGeometryFile;
    write_geometry((dir / kGeometryFile).string(), bake.scene);
    step = kTexturesFile;
    write_textures((dir / kTexturesFile).string(), bake.scene);
    step = kVertexLightFile;
    write_vertex_light((dir / kVertexLightFile).string(), bake.scene, bake.vertex_light);

    step = kLightmapsFile;
    const Atlas atlas = pack_atlas(bake.scene);
    write_lightmaps_exr((dir / kLightmapsFile).string(), atlas, bake.lightmap_radiance,
                        bake.texel_offset);

    step = kLightfieldFile;
    const uint64_t samples =
        write_lightfield_exr((dir / kLightfieldFile).string(), bake.params.field, bake.directions,
                             rays ? rays : ray_source(bake.rays));
    record_layout(manifest, atlas, bake.params.field, samples);

    step = kManifestFile;
    record_checksums(manifest, dir.string());
    write_text((dir / kManifestFile).string(), manifest.dump(1) + "\n");
}

// Renames the finished `partial` to `dest`. The old bundle is moved aside first (a
// directory cannot be renamed over a non-empty one) and put back if the rename fails.
void replace_bundle(const fs::path& partial, const fs::path& dest, const std::string& path) {
    const fs::path old(path + ".old");
    const bool replacing = fs::exists(dest);
    if (replacing) {
        fs::remove_all(old);
        fs::rename(dest, old);
    }
    std::error_code ec;
    fs::rename(partial, dest, ec);
    if (ec) {
        std::error_code ignored;
        if (replacing) fs::rename(old, dest, ignored);
        throw fs::filesystem_error("rename", partial, dest, ec);
    }
    if (replacing) fs::remove_all(old);
}

}  // namespace

void write_bake(const std::string& path_in, const Bake& bake, const RaySource& rays) {
    const std::string path = strip_slashes(path_in);
    const fs::path dest(path);
    const fs::path partial(path + ".partial");
    std::string step = "creating " + partial.filename().string();
    std::string problem;
    try {
        check_replaceable(dest);
        fs::remove_all(partial);  // a stale attempt
        fs::create_directories(partial);
        write_parts(partial, bake, rays, step);
        step = "renaming " + partial.filename().string();
        replace_bundle(partial, dest, path);
        return;
    } catch (const fs::filesystem_error& e) {
        problem = e.code().message();
    } catch (const std::exception& e) {  // Error, Iex::BaseExc (derives from std::exception)
        problem = e.what();
    }
    std::error_code ec;
    fs::remove_all(partial, ec);
    throw Error(fmt::format("{}: {}: {}", path, step, problem));
}

// ---------------------------------------------------------------------------------------
// Reading

namespace {

Scene read_scene_file(const BundleErrors& errors) {
    const std::string file = errors.file(kSceneFile);
    Scene s = scene_from_json(read_json_file(file), file);
    read_geometry(errors.file(kGeometryFile), s);
    read_textures(errors.file(kTexturesFile), s);
    compute_texel_albedo(s);
    for (size_t k = 0; k < s.objects.size(); ++k) {
        const SceneObject& o = s.objects[k];
        if (size_t(o.first_face) + size_t(o.face_count) > s.faces.size())
            errors.fail(
                kSceneFile,
                fmt::format("objects[{}]: faces {} to {} are out of range (the geometry "
                            "has {})",
                            k, o.first_face, o.first_face + o.face_count - 1, s.faces.size()));
    }
    return s;
}

// The parts after the manifest's checksums are verified; `step` names the part being read.
void read_parts(const fs::path& dir, const BundleErrors& errors, Bake& bake, std::string& step) {
    step = kSceneFile;
    bake.scene = read_scene_file(errors);
    const size_t nf = bake.scene.faces.size();
    const size_t nc = bake.scene.charts.size();
    bake.texel_offset.assign(nc + 1, 0);
    for (size_t c = 0; c < nc; ++c)
        bake.texel_offset[c + 1] = bake.texel_offset[c] + bake.scene.charts[c].texel_area.size();

    step = kVertexLightFile;
    bake.vertex_light = read_vertex_light(errors.file(kVertexLightFile), bake.scene);

    step = kManifestFile;
    bake.params = manifest_parameters(bake.manifest, errors);
    check_scene_frame(bake.manifest, bake.scene, errors);
    bake.directions = DirectionSet(bake.params.field.directions, bake.params.field.scheme);

    step = kLightmapsFile;
    const std::vector<AtlasRect> rects = manifest_rects(bake.manifest, bake.scene, errors);
    int atlas_width = 0, atlas_height = 0;
    manifest_atlas_size(bake.manifest, errors, atlas_width, atlas_height);
    bake.lightmap_radiance = read_lightmaps_exr((dir / kLightmapsFile).string(), rects, atlas_width,
                                                atlas_height, bake.texel_offset, errors);

    step = kLightfieldFile;
    LightfieldLayout layout{bake.params.field.directions, bake.params.field.resolution,
                            bake.params.field.tile, std::vector<bool>(nf)};
    for (size_t f = 0; f < nf; ++f)
        layout.stored[f] =
            bake.params.store_all_rays || bake.scene.material_of(bake.scene.faces[f]).is_specular();
    bake.rays = read_lightfield_exr((dir / kLightfieldFile).string(), layout, errors);
    check_lightfield(bake.manifest, bake.params.field, bake.rays.face.size(), errors);
}

}  // namespace

Bake read_bake(const std::string& path_in) {
    const BundleErrors errors{strip_slashes(path_in)};
    const fs::path dir(errors.bundle);
    {
        std::error_code ec;
        if (!fs::exists(dir, ec)) throw Error(fmt::format("{}: no such bundle", errors.bundle));
        if (!fs::is_directory(dir, ec))
            throw Error(fmt::format("{}: not a bundle directory", errors.bundle));
    }
    Bake bake;
    std::string step = kManifestFile;
    try {
        bake.manifest = read_manifest(dir.string(), errors);
        verify_files(bake.manifest, dir.string(), errors);
        read_parts(dir, errors, bake, step);
    } catch (const Error&) {
        throw;                           // already names the bundle and the part
    } catch (const std::exception& e) {  // OpenEXR (Iex::BaseExc), filesystem, allocation
        throw Error(fmt::format("{}: {}: {}", errors.bundle, step, e.what()));
    }
    return bake;
}

}  // namespace vlf
