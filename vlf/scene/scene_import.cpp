// scene_import.cpp — assimp scenes to material groups, cameras and a list of what was left
// out (scene_import.hpp).
//
// Material mapping (VLF surfaces are Lambertian diffuse + ideal mirror + Lambertian
// emitter, DESIGN §3):
//   OBJ/MTL   Kd -> diffuse; illum 3 or 5 (reflection on) -> Ks as the mirror's reflectance,
//             else Ks is a Phong highlight and left out; Ke -> emission (radiance).
//   glTF      metallic 1 and roughness 0 (factors x the metallic-roughness texture's mean)
//             -> mirror of reflectance baseColor; anything else -> diffuse baseColor (a
//             glossy metal noted); emissive x KHR_materials_emissive_strength -> emission;
//             transmission and ior are listed as left out (a scene's `dielectric` material maps
//             onto them).
//   others    the diffuse and emissive colours; a reflective colour with reflectivity > 0
//             -> mirror.
// Lights (lights_of): point, spot and directional lights with their strengths as the file
// gives them; area and ambient lights are left out.
// A diffuse colour texture (map_Kd, the base-colour texture) is kept (ImportedGroup::texture);
// the material's diffuse is the colour x the texture's mean linear colour (sRGB decoded).
// Where diffuse + specular exceeds 1 in a channel both are scaled down to sum to 1.
// Winding (orient, winding.hpp): faces of one-sided materials are turned to agree with their
// neighbours, closed parts to face outward (inward around the file's camera or light).
#include "vlf/scene/scene_import.hpp"

#include <assimp/GltfMaterial.h>
#include <assimp/ObjMaterial.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/core.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"
#include "vlf/scene/winding.hpp"

namespace vlf {

namespace {

Rgb to_rgb(const aiColor4D& c) {
    return {c.r, c.g, c.b};
}

// A texture image (a file next to the model, or embedded in it) as 8-bit sRGB RGB, or
// nullopt when it cannot be read.
std::optional<Texture> read_texture(const aiScene& scene, const std::string& model_dir,
                                    const std::string& name) {
    Texture out;
    out.name = name;
    int w = 0, h = 0, n = 0;
    unsigned char* pixels = nullptr;
    if (const aiTexture* t = scene.GetEmbeddedTexture(name.c_str())) {
        if (t->mHeight == 0) {  // compressed (PNG, JPEG) in mWidth bytes
            pixels = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(t->pcData),
                                           int(t->mWidth), &w, &h, &n, 3);
        } else {  // raw BGRA texels
            out.width = int(t->mWidth);
            out.height = int(t->mHeight);
            for (size_t i = 0; i < size_t(out.width) * size_t(out.height); ++i)
                out.srgb.insert(out.srgb.end(), {t->pcData[i].r, t->pcData[i].g, t->pcData[i].b});
        }
    } else {
        std::string file = name;
        std::replace(file.begin(), file.end(), '\\', '/');
        const std::filesystem::path p = std::filesystem::path(model_dir) / file;
        pixels = stbi_load(p.string().c_str(), &w, &h, &n, 3);
    }
    if (pixels) {
        out.width = w;
        out.height = h;
        out.srgb.assign(pixels, pixels + size_t(w) * size_t(h) * 3);
        stbi_image_free(pixels);
    }
    if (out.width <= 0 || out.height <= 0) return std::nullopt;
    if (int64_t(out.width) * out.height > kMaxTextureTexels)
        throw Error(fmt::format("texture '{}' has {} x {} texels (at most {} in all)", name,
                                out.width, out.height, kMaxTextureTexels));
    if (out.name.size() > kMaxTextureName) out.name.resize(kMaxTextureName);
    out.finish();
    return out;
}

bool is_gltf(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".gltf" || ext == ".glb";
}

// A glTF material's glass extensions (KHR_materials_transmission, _volume, _ior), with the
// specification's defaults where the file leaves them out.
struct GltfGlass {
    double transmission = 0.0;  // transmissionFactor
    double thickness = 0.0;     // thicknessFactor: 0 is thin-walled (no volume)
    double ior = 1.5;
    double attenuation_distance = std::numeric_limits<double>::infinity();  // file units
    Rgb attenuation_color{1.0};
};

// What assimp 5.2 does not take from a glTF file, read from its JSON: each material's
// KHR_materials_emissive_strength and glass extensions, and each camera's vertical field of
// view (assimp stores yfov x aspect as a horizontal half-angle). Empty when the JSON cannot
// be read (assimp will already have said why).
struct GltfExtras {
    std::vector<double> emissive_strength;  // per material, 1 without the extension
    std::vector<GltfGlass> glass;           // per material
    std::vector<double> yfov;               // per camera, radians; 0 when not perspective
};

GltfExtras gltf_extras(const std::string& path) {
    GltfExtras out;
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (lower_extension(path) == ".glb") {  // 12-byte header, then the JSON chunk
        uint32_t length = 0;
        if (text.size() < 20) return out;
        std::memcpy(&length, text.data() + 12, 4);
        if (text.compare(16, 4, "JSON") != 0 || 20 + size_t(length) > text.size()) return out;
        text = text.substr(20, length);
    }
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    // A number where the file has one; anything else is refused by name.
    auto number = [&](const nlohmann::json& o, const char* key, double fallback,
                      const std::string& place) {
        if (!o.contains(key)) return fallback;
        if (!o[key].is_number() || !std::isfinite(o[key].get<double>()) || o[key].get<double>() < 0)
            throw Error(fmt::format("{}: {}.{}: expected a number >= 0", path, place, key));
        return o[key].get<double>();
    };
    if (j.is_discarded() || !j.is_object()) return out;
    for (const auto& m : j.value("materials", nlohmann::json::array())) {
        double strength = 1.0;
        GltfGlass glass;
        if (m.is_object() && m.contains("extensions") && m["extensions"].is_object()) {
            const auto& e = m["extensions"];
            // The extension `name` of this material, when the file gives it as an object.
            auto extension = [&](const char* name) -> const nlohmann::json* {
                return e.contains(name) && e[name].is_object() ? &e[name] : nullptr;
            };
            auto place = [&](const char* name) {
                return fmt::format("materials[{}].extensions.{}", out.emissive_strength.size(),
                                   name);
            };
            if (const auto* x = extension("KHR_materials_emissive_strength"))
                strength =
                    number(*x, "emissiveStrength", 1.0, place("KHR_materials_emissive_strength"));
            if (const auto* x = extension("KHR_materials_transmission"))
                glass.transmission = std::min(
                    number(*x, "transmissionFactor", 0.0, place("KHR_materials_transmission")),
                    1.0);
            if (const auto* x = extension("KHR_materials_ior"))
                glass.ior = number(*x, "ior", 1.5, place("KHR_materials_ior"));
            if (const auto* x = extension("KHR_materials_volume")) {
                const std::string at = place("KHR_materials_volume");
                glass.thickness = number(*x, "thicknessFactor", 0.0, at);
                glass.attenuation_distance =
                    number(*x, "attenuationDistance", glass.attenuation_distance, at);
                if (x->contains("attenuationColor")) {
                    const auto& c = (*x)["attenuationColor"];
                    if (!c.is_array() || c.size() != 3)
                        throw Error(
                            fmt::format("{}: {}.attenuationColor: expected 3 numbers", path, at));
                    for (int k = 0; k < 3; ++k) {
                        if (!c[size_t(k)].is_number() ||
                            !(c[size_t(k)].get<double>() >= 0 && c[size_t(k)].get<double>() <= 1))
                            throw Error(fmt::format(
                                "{}: {}.attenuationColor[{}]: expected a number in [0, 1]", path,
                                at, k));
                        glass.attenuation_color[k] = c[size_t(k)].get<double>();
                    }
                }
            }
        }
        out.emissive_strength.push_back(strength);
        out.glass.push_back(glass);
    }
    for (const auto& c : j.value("cameras", nlohmann::json::array())) {
        double yfov = 0.0;
        if (c.is_object() && c.contains("perspective") && c["perspective"].is_object())
            yfov = number(c["perspective"], "yfov", 0.0,
                          fmt::format("cameras[{}].perspective", out.yfov.size()));
        out.yfov.push_back(yfov);
    }
    return out;
}

std::string rgb_text(const Rgb& c) {
    return fmt::format("[{:.3g}, {:.3g}, {:.3g}]", c.x, c.y, c.z);
}

// A dielectric of index `ior` named after the group's material.
Material dielectric(const std::string& name, double ior) {
    Material glass;
    glass.name = name;
    glass.dielectric = true;
    glass.ior = ior;
    return glass;
}

// Maps one assimp material (see the table at the top of the file); `ext` is a glTF
// material's glass extensions.
void map_material(const aiScene& scene, const aiMaterial& m, bool gltf, const GltfGlass& ext,
                  const std::string& dir, ImportedGroup& g) {
    aiColor4D c;
    float x = 0.0f;
    int i = 0;
    auto note = [&](std::string s) { g.unrepresented.push_back(std::move(s)); };
    Material& out = g.material;
    out.name = g.material_name;

    Rgb base(0.0);
    double metallic = 0.0, roughness = 1.0;
    if (gltf) {
        if (m.Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS)
            base = to_rgb(c);
        else if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
            base = to_rgb(c);
        else
            base = Rgb(1.0);  // glTF's default base colour
        metallic = m.Get(AI_MATKEY_METALLIC_FACTOR, x) == AI_SUCCESS ? x : 1.0;
        roughness = m.Get(AI_MATKEY_ROUGHNESS_FACTOR, x) == AI_SUCCESS ? x : 1.0;
    } else if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
        base = to_rgb(c);
    }

    // A diffuse colour texture: the albedo is the colour x the texture (Scene::albedo_at).
    aiString tex;
    const bool has_texture =
        (gltf && m.GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS) ||
        m.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS;
    if (has_texture) {
        if (auto t = read_texture(scene, dir, tex.C_Str())) {
            base *= t->average;
            g.texture = std::move(*t);
        } else {
            note(fmt::format("diffuse texture '{}' (cannot be read; the colour alone is used)",
                             tex.C_Str()));
        }
    }

    if (gltf) {
        // The metallic-roughness texture scales the factors (metalness in blue, roughness
        // in green, linear).
        aiString mr;
        if (m.GetTexture(AI_MATKEY_GLTF_PBRMETALLICROUGHNESS_METALLICROUGHNESS_TEXTURE, &mr) ==
            AI_SUCCESS) {
            if (const auto t = read_texture(scene, dir, mr.C_Str())) {
                double g_sum = 0.0, b_sum = 0.0;
                const size_t n = size_t(t->width) * size_t(t->height);
                for (size_t k = 0; k < n; ++k)
                    g_sum += t->srgb[3 * k + 1], b_sum += t->srgb[3 * k + 2];
                roughness *= g_sum / (255.0 * double(n));
                metallic *= b_sum / (255.0 * double(n));
            }
        }
        const bool mirror = metallic >= 1.0 && roughness <= 0.0;
        if (mirror) {
            out.specular = base;
        } else {
            // A glossy or partly metallic surface scatters its base colour broadly: the
            // nearest VLF surface is diffuse of the base colour.
            out.diffuse = base;
            if (metallic > 0.0)
                note(
                    fmt::format("metallic {:.3g} with roughness {:.3g} (a glossy metal: taken "
                                "as diffuse of the base colour; only metallic 1 with roughness "
                                "0 is a mirror)",
                                metallic, roughness));
        }
        if (ext.transmission > 0.0) {
            out.transmission = ext.transmission;
            out.ior = ext.ior;
            if (ext.thickness <= 0.0) {
                note(fmt::format(
                    "transmission {:.3g}, ior {:.3g} (thin-walled: no KHR_materials_volume "
                    "thickness; kept in the material, not glass: map a scene dielectric "
                    "material onto it with \"materials\")",
                    ext.transmission, ext.ior));
            } else if (!(ext.ior > 1.0 && ext.ior <= 4.0)) {
                note(
                    fmt::format("transmission {:.3g} with ior {:.3g} (not glass: a dielectric's "
                                "ior is in (1, 4])",
                                ext.transmission, ext.ior));
            } else {
                // Solid glass (KHR_materials_volume): Beer-Lambert absorption from the
                // attenuation colour reached at the attenuation distance, per file unit.
                Material glass = dielectric(out.name, ext.ior);
                for (int ch = 0; ch < 3; ++ch)
                    if (std::isfinite(ext.attenuation_distance) && ext.attenuation_color[ch] < 1.0)
                        glass.absorption[ch] =
                            ext.attenuation_color[ch] > 0.0 && ext.attenuation_distance > 0.0
                                ? -std::log(ext.attenuation_color[ch]) / ext.attenuation_distance
                                : std::numeric_limits<double>::infinity();
                g.glass = glass;
                g.glass_what = fmt::format("transmission {:.3g} with a volume", ext.transmission);
                if (ext.transmission < 1.0)
                    g.glass_unrepresented.push_back(fmt::format(
                        "the diffuse part of transmission {:.3g} (taken as clear glass)",
                        ext.transmission));
                if (roughness > 0.0)
                    g.glass_unrepresented.push_back(
                        fmt::format("roughness {:.3g} (taken as smooth glass)", roughness));
                if (metallic > 0.0)
                    g.glass_unrepresented.push_back(
                        fmt::format("metallic {:.3g} (taken as glass)", metallic));
                if (base != Rgb(1.0))
                    g.glass_unrepresented.push_back(fmt::format(
                        "base colour {} (the glass's surface does not tint; its volume's "
                        "attenuation does)",
                        rgb_text(base)));
            }
        }
    } else {
        out.diffuse = base;
        Rgb ks(0.0);
        if (m.Get(AI_MATKEY_COLOR_SPECULAR, c) == AI_SUCCESS) ks = to_rgb(c);
        const bool has_illum = m.Get(AI_MATKEY_OBJ_ILLUM, i) == AI_SUCCESS;
        Rgb reflective(0.0);
        float reflectivity = 0.0f;
        if (m.Get(AI_MATKEY_COLOR_REFLECTIVE, c) == AI_SUCCESS) reflective = to_rgb(c);
        m.Get(AI_MATKEY_REFLECTIVITY, reflectivity);
        if (has_illum && (i == 3 || i == 5)) {
            out.specular = ks;  // MTL: reflection on, Ks is the mirror's reflectance
        } else if (!has_illum && reflectivity > 0.0f && reflective != Rgb(0.0)) {
            out.specular = reflective * double(reflectivity);
        } else if (ks != Rgb(0.0) && !(has_illum && i < 2)) {
            note(fmt::format("a Phong highlight Ks = {} (only ideal mirrors: illum 3 or 5)",
                             rgb_text(ks)));
        }
        if (has_illum && (i == 4 || i == 6 || i == 7 || i == 9)) {
            // Glass: the index is Ni, 1.5 where the file gives none above 1 (assimp's
            // default is 1); Kd, Ks and Tf give way to Fresnel's reflection and refraction.
            float ni = 1.0f;
            m.Get(AI_MATKEY_REFRACTI, ni);
            const bool ni_used = ni > 1.0f && ni <= 4.0f;
            g.glass = dielectric(out.name, ni_used ? double(ni) : 1.5);
            g.glass_what = fmt::format("illum {}", i);
            if (!ni_used)
                g.glass_unrepresented.push_back(
                    fmt::format("Ni {:.3g} (not in (1, 4]: ior 1.5)", ni));
            std::vector<std::string> parts;
            if (base != Rgb(0.0)) parts.push_back("Kd = " + rgb_text(base));
            if (ks != Rgb(0.0)) parts.push_back("Ks = " + rgb_text(ks));
            if (m.Get(AI_MATKEY_COLOR_TRANSPARENT, c) == AI_SUCCESS && to_rgb(c) != Rgb(1.0))
                parts.push_back("Tf = " + rgb_text(to_rgb(c)));
            if (!parts.empty()) {
                std::string list;
                for (const std::string& p : parts) list += (list.empty() ? "" : ", ") + p;
                g.glass_unrepresented.push_back(
                    list + " (glass reflects and refracts by Fresnel's equations, clear)");
            }
        }
    }

    Rgb emission(0.0);
    if (m.Get(AI_MATKEY_COLOR_EMISSIVE, c) == AI_SUCCESS) emission = to_rgb(c);
    if (m.Get(AI_MATKEY_EMISSIVE_INTENSITY, x) == AI_SUCCESS)
        emission *= double(x);
    else
        emission *= g.emissive_strength;
    aiString etex;
    if (m.GetTexture(aiTextureType_EMISSIVE, 0, &etex) == AI_SUCCESS)
        note(
            fmt::format("emissive texture '{}' (the emissive colour alone is used)", etex.C_Str()));
    out.emission = emission;

    for (int ch = 0; ch < 3; ++ch) {
        out.diffuse[ch] = std::clamp(out.diffuse[ch], 0.0, 1.0);
        out.specular[ch] = std::clamp(out.specular[ch], 0.0, 1.0);
        out.emission[ch] = std::max(out.emission[ch], 0.0);
    }
    const double worst = std::max({(out.diffuse + out.specular).x, (out.diffuse + out.specular).y,
                                   (out.diffuse + out.specular).z});
    if (worst > 1.0) {
        note(fmt::format("diffuse + mirror reflectance {:.3g} > 1 (both scaled by {:.3g})", worst,
                         1.0 / worst));
        out.diffuse /= worst;
        out.specular /= worst;
    }
    int two = 0;
    if (m.Get(AI_MATKEY_TWOSIDED, two) == AI_SUCCESS) g.two_sided = two != 0;
}

aiMatrix4x4 global_transform(const aiNode* node) {
    aiMatrix4x4 m;
    for (; node; node = node->mParent) m = node->mTransformation * m;
    return m;
}

Vec3 to_vec(const aiVector3D& v) {
    return {v.x, v.y, v.z};
}

struct Collector {
    const aiScene& scene;
    const std::string& path;
    std::vector<ImportedGroup>& groups;
    size_t skipped_primitives = 0;

    void add_mesh(const aiMesh& mesh, const aiMatrix4x4& xf) {
        if (!(mesh.mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) {
            ++skipped_primitives;
            return;
        }
        ImportedMesh& out = groups[mesh.mMaterialIndex].mesh;
        const int base = int(out.vertices.size());
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
            const aiVector3D p = xf * mesh.mVertices[v];
            const Vec3 q = to_vec(p);
            if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
                throw Error(fmt::format("{}: mesh '{}': vertex {} is not finite", path,
                                        mesh.mName.C_Str(), v));
            out.vertices.push_back(q);
        }
        // Texture coordinates for a textured material's faces (NaN where the mesh has none:
        // those faces take the material's mean albedo).
        const ImportedGroup& g = groups[mesh.mMaterialIndex];
        if (g.texture.width > 0) {
            const double nan = std::numeric_limits<double>::quiet_NaN();
            out.uvs.resize(size_t(base), Vec2(nan));
            for (unsigned v = 0; v < mesh.mNumVertices; ++v)
                out.uvs.push_back(mesh.HasTextureCoords(0) ? Vec2(mesh.mTextureCoords[0][v].x,
                                                                  mesh.mTextureCoords[0][v].y)
                                                           : Vec2(nan));
        }
        // Vertex normals (NaN where a mesh has none: those faces stay flat), moved by the
        // inverse transpose of the node transform's linear part.
        if (mesh.HasNormals() || !out.normals.empty()) {
            const double nan = std::numeric_limits<double>::quiet_NaN();
            out.normals.resize(size_t(base), Vec3(nan));
            aiMatrix3x3 normal_matrix(xf);
            normal_matrix.Inverse().Transpose();
            for (unsigned v = 0; v < mesh.mNumVertices; ++v)
                out.normals.push_back(mesh.HasNormals() ? to_vec(normal_matrix * mesh.mNormals[v])
                                                        : Vec3(nan));
        }
        // A mirroring transform turns the winding: reverse it so the front stays the front.
        const bool mirrored = xf.Determinant() < 0;
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices < 3) continue;  // points and lines of a mixed mesh
            std::vector<int> idx(face.mNumIndices);
            for (unsigned k = 0; k < face.mNumIndices; ++k) idx[k] = base + int(face.mIndices[k]);
            if (mirrored) std::reverse(idx.begin(), idx.end());
            out.faces.push_back(std::move(idx));
        }
    }

    void visit(const aiNode* node, const aiMatrix4x4& parent) {
        const aiMatrix4x4 xf = parent * node->mTransformation;
        for (unsigned k = 0; k < node->mNumMeshes; ++k)
            add_mesh(*scene.mMeshes[node->mMeshes[k]], xf);
        for (unsigned k = 0; k < node->mNumChildren; ++k) visit(node->mChildren[k], xf);
    }
};

// The file's cameras that make a view (finite, a view direction, an up not along it, a
// field of view in (0, 180)); the others are listed in `left_out`. Names are made unique.
std::vector<Camera> cameras_of(const aiScene& scene, const GltfExtras* gltf,
                               std::vector<std::string>& left_out) {
    std::vector<Camera> out;
    std::set<std::string> names;
    for (unsigned k = 0; k < scene.mNumCameras; ++k) {
        const aiCamera& c = *scene.mCameras[k];
        const aiMatrix4x4 xf = global_transform(scene.mRootNode->FindNode(c.mName));
        aiMatrix3x3 rot(xf);
        // assimp's glTF reader copies the node's translation into mPosition as well.
        const aiVector3D position = gltf ? aiVector3D(0, 0, 0) : c.mPosition;
        Camera cam;
        cam.name = c.mName.length ? c.mName.C_Str() : fmt::format("camera#{}", k);
        cam.eye = to_vec(xf * position);
        cam.look_at = to_vec(xf * (position + c.mLookAt));
        cam.up = to_vec(rot * c.mUp);
        // mHorizontalFOV is half the horizontal angle; VLF cameras give the vertical one.
        const double aspect = c.mAspect > 0 ? c.mAspect : 1.0;
        const double half_v = std::atan(std::tan(double(c.mHorizontalFOV)) / aspect);
        cam.fov_y_deg = 2.0 * half_v * 180.0 / kPi;
        if (gltf && k < gltf->yfov.size() && gltf->yfov[k] > 0)
            cam.fov_y_deg = gltf->yfov[k] * 180.0 / kPi;
        const Vec3 view = cam.look_at - cam.eye;
        const bool finite = std::isfinite(glm::length(view)) &&
                            std::isfinite(glm::length(cam.eye)) &&
                            std::isfinite(glm::length(cam.up));
        const bool ok =
            finite && glm::length(view) > 0 && glm::length(cam.up) > 0 &&
            glm::length(glm::cross(glm::normalize(view), glm::normalize(cam.up))) > 1e-6 &&
            cam.fov_y_deg > 0 && cam.fov_y_deg < 180;
        if (!ok) {
            left_out.push_back(
                fmt::format("camera '{}' (it makes no view: no direction, an up "
                            "along it or a field of view outside (0, 180))",
                            cam.name));
            continue;
        }
        cam.up = glm::normalize(cam.up);
        for (int n = 2; !names.insert(cam.name).second; ++n)
            cam.name = fmt::format("{}#{}", c.mName.C_Str(), n);
        out.push_back(cam);
    }
    return out;
}

const char* light_kind(aiLightSourceType t) {
    switch (t) {
        case aiLightSource_DIRECTIONAL:
            return "directional";
        case aiLightSource_POINT:
            return "point";
        case aiLightSource_SPOT:
            return "spot";
        case aiLightSource_AMBIENT:
            return "ambient";
        case aiLightSource_AREA:
            return "area";
        default:
            return "undefined";
    }
}

// The file's point, spot and directional lights (light.hpp, ImportedScene::lights): placed by
// the node of their name (as assimp names them), strengths as the file gives them. Area,
// ambient and unplaced lights are listed in `left_out`, lights without strength too; what is
// taken differently (attenuation, a glTF range) goes to `notes`. Names are made unique.
//
// assimp 5.2's glTF reader (KHR_lights_punctual) puts colour x intensity into mColorDiffuse,
// 0 0 -1 into mDirection and the spot's cone half-angles (glTF's convention) into
// mAngleInnerCone / mAngleOuterCone; assimp's other readers give full cone angles there
// (Collada's falloff_angle, 3ds Max's hotspot and falloff), as its light.h says.
std::vector<Light> lights_of(const aiScene& scene, const std::string& path, bool gltf,
                             std::vector<std::string>& left_out, std::vector<std::string>& notes) {
    std::vector<Light> out;
    std::set<std::string> names;
    for (unsigned k = 0; k < scene.mNumLights; ++k) {
        const aiLight& l = *scene.mLights[k];
        const std::string name = l.mName.length ? l.mName.C_Str() : fmt::format("light#{}", k);
        const std::string what = fmt::format("light '{}' ({})", name, light_kind(l.mType));
        Light light;
        if (l.mType == aiLightSource_POINT)
            light.type = LightType::Point;
        else if (l.mType == aiLightSource_SPOT)
            light.type = LightType::Spot;
        else if (l.mType == aiLightSource_DIRECTIONAL)
            light.type = LightType::Directional;
        else {
            left_out.push_back(what +
                               ": VLF lights are point, spot and directional (an emissive surface "
                               "makes an area light)");
            continue;
        }
        const aiNode* node = l.mName.length ? scene.mRootNode->FindNode(l.mName) : nullptr;
        if (!node) {
            left_out.push_back(what + ": no node of the scene places it");
            continue;
        }
        const aiMatrix4x4 xf = global_transform(node);
        const aiMatrix3x3 rot(xf);
        const Vec3 direction = to_vec(rot * l.mDirection);
        Rgb strength = Rgb(l.mColorDiffuse.r, l.mColorDiffuse.g, l.mColorDiffuse.b);
        for (int c = 0; c < 3; ++c) strength[c] = std::max(strength[c], 0.0);  // no negative light

        // assimp's fall-off is 1 / (constant + linear d + quadratic d^2); VLF's lights fall
        // off as 1 / d^2, so only quadratic alone is kept (as intensity / quadratic).
        std::vector<std::string> changed;  // noted when the light is kept
        if (light.type != LightType::Directional) {
            const double c0 = l.mAttenuationConstant, c1 = l.mAttenuationLinear,
                         c2 = l.mAttenuationQuadratic;
            if (c0 == 0 && c1 == 0 && c2 > 0) {
                strength /= c2;
            } else {
                changed.push_back(fmt::format(
                    "{}: attenuation 1 / ({:.3g} + {:.3g} d + {:.3g} d^2) replaced by the "
                    "inverse square law 1 / d^2",
                    what, c0, c1, c2));
            }
            float range = 0.0f;
            if (gltf && node->mMetaData && node->mMetaData->Get("PBR_LightRange", range))
                changed.push_back(fmt::format(
                    "{}: range {:.3g} not kept (the light reaches every distance)", what, range));
        }
        const Vec3 position = to_vec(xf * l.mPosition);
        const double finite = glm::length(strength) + glm::length(direction);
        if (!std::isfinite(finite) || !(std::max({std::abs(position.x), std::abs(position.y),
                                                  std::abs(position.z)}) <= 1e15)) {
            left_out.push_back(what +
                               ": a strength or direction that is not finite, or a position beyond "
                               "+-1e15");
            continue;
        }
        if (!(std::max({strength.x, strength.y, strength.z}) > 0)) {
            left_out.push_back(what + ": zero intensity");
            continue;
        }
        if (!(std::max({strength.x, strength.y, strength.z}) <= 1e20))
            throw Error(fmt::format("{}: {}: strength {} is out of range (at most 1e20)", path,
                                    what, rgb_text(strength)));
        if (light.type != LightType::Point) {
            if (!(glm::length(direction) > 0)) {
                left_out.push_back(what + ": its node's transform leaves it no direction");
                continue;
            }
            light.direction = glm::normalize(direction);
        }
        if (light.type == LightType::Directional) {
            light.irradiance = strength;
        } else {
            light.position = position;
            light.intensity = strength;
        }
        if (light.type == LightType::Spot) {
            const double to_half = gltf ? 1.0 : 0.5;
            const double outer = std::min(double(l.mAngleOuterCone) * to_half, kPi);
            if (!(outer > 0)) {
                left_out.push_back(
                    fmt::format("{}: outer cone angle {:.3g} (no cone)", what, l.mAngleOuterCone));
                continue;
            }
            const double given_inner = double(l.mAngleInnerCone) * to_half;
            const double inner = given_inner >= 0 ? std::min(given_inner, outer) : 0.0;
            light.cos_inner = std::cos(inner);
            light.cos_outer = std::cos(outer);
        }
        light.name = name;
        for (int n = 2; !names.insert(light.name).second; ++n)
            light.name = fmt::format("{}#{}", name, n);
        out.push_back(light);
        notes.insert(notes.end(), changed.begin(), changed.end());
    }
    if (!out.empty())
        notes.push_back(
            gltf ? "light strengths taken as they are: KHR_lights_punctual's candela as W/sr "
                   "(point, spot) and lux as W per square unit (directional), as emission is "
                   "taken as radiance"
                 : "light strengths (colour x intensity) taken as they are: W/sr for point and "
                   "spot lights, W per square unit for directional ones");
    return out;
}

// Turns faces so that each part of the file faces one way (winding.hpp) and notes what was
// turned, per material. Double-sided materials are left as the file has them and do not join
// parts: the loader adds each of their faces reversed, so their winding cannot show. The
// viewpoints are the file's cameras and point and spot lights and the `extra` ones of the
// scene around it (a closed part around one is a room seen from inside).
void orient(std::vector<ImportedGroup>& groups, const std::vector<Camera>& cameras,
            const std::vector<Light>& lights, const std::vector<Vec3>& extra,
            std::vector<std::string>& notes) {
    std::vector<ImportedMesh*> meshes;
    std::vector<const ImportedGroup*> owners;
    for (ImportedGroup& g : groups)
        if (!g.two_sided) meshes.push_back(&g.mesh), owners.push_back(&g);
    std::vector<Vec3> viewpoints = extra;
    for (const Camera& c : cameras) viewpoints.push_back(c.eye);
    for (const Light& l : lights)
        if (l.type != LightType::Directional) viewpoints.push_back(l.position);
    const std::vector<WindingChanges> changes = orient_faces(meshes, viewpoints);
    for (size_t k = 0; k < changes.size(); ++k) {
        const WindingChanges& c = changes[k];
        if (!c.changed()) continue;
        std::vector<std::string> what;
        if (c.agreed)
            what.push_back(fmt::format("{} of {} face(s) turned to agree with their neighbours",
                                       c.agreed, c.faces));
        if (c.outward_parts)
            what.push_back(
                fmt::format("{} closed part(s) turned to face outward ({} of {} face(s) turned)",
                            c.outward_parts, c.outward_faces, c.faces));
        if (c.inward_parts)
            what.push_back(fmt::format(
                "{} closed part(s) around the file's camera or light turned to face inward ({} "
                "of {} face(s) turned)",
                c.inward_parts, c.inward_faces, c.faces));
        if (c.non_orientable)
            what.push_back(fmt::format(
                "{} part(s) cannot face one way throughout (one-sided, like a Moebius strip): "
                "the faces of {} edge(s) still disagree",
                c.non_orientable, c.disagreeing_edges));
        std::string text;
        for (const std::string& w : what) text += (text.empty() ? "" : "; ") + w;
        notes.push_back(fmt::format("material '{}': {}", owners[k]->material_name, text));
    }
}

// Where a group's faces do not close up into solids: an edge (by its end points' exact
// positions) that is not on exactly two faces, described in one phrase; nothing when closed.
std::optional<std::string> open_edge_of(const ImportedMesh& mesh) {
    using Key = std::array<double, 3>;
    auto key = [&](int v) {
        const Vec3& p = mesh.vertices[size_t(v)];
        return Key{p.x, p.y, p.z};
    };
    std::map<std::pair<Key, Key>, int> edges;
    for (const std::vector<int>& f : mesh.faces)
        for (size_t k = 0; k < f.size(); ++k) {
            Key a = key(f[k]), b = key(f[(k + 1) % f.size()]);
            if (b < a) std::swap(a, b);
            ++edges[{a, b}];
        }
    for (const auto& [edge, faces] : edges)
        if (faces != 2)
            return fmt::format(
                "the edge ({:.6g}, {:.6g}, {:.6g})-({:.6g}, {:.6g}, {:.6g}) is on "
                "{} face(s), not 2",
                edge.first[0], edge.first[1], edge.first[2], edge.second[0], edge.second[1],
                edge.second[2], faces);
    return std::nullopt;
}

// Makes each group's glass its material where the group's faces close up into solids (light
// refracted in must meet the far side; the loader checks their winding and adds the inner
// faces). Such a group is one-sided whatever the file says: its faces bound a solid. Where
// they do not, or the material also emits, the mapped material stays and the reason is noted.
void choose_glass(std::vector<ImportedGroup>& groups, std::vector<std::string>& notes) {
    for (ImportedGroup& g : groups) {
        if (!g.glass) continue;
        std::optional<std::string> why;
        if (g.material.is_emitter())
            why = "the material also emits";
        else if (const auto open = open_edge_of(g.mesh))
            why = "its faces are not closed: " + *open;
        if (why) {
            g.unrepresented.push_back(
                fmt::format("{} (glass; not made glass: {})", g.glass_what, *why));
            continue;
        }
        notes.push_back(fmt::format(
            "material '{}': {} made glass of ior {:.4g}{}", g.material_name, g.glass_what,
            g.glass->ior,
            g.glass->is_absorbing()
                ? fmt::format(", absorption {} per file unit", rgb_text(g.glass->absorption))
                : std::string()));
        g.not_glass = g.material;
        g.material = *g.glass;
        g.unrepresented = g.glass_unrepresented;
        g.two_sided = false;
        g.texture = Texture{};
        g.mesh.uvs.clear();
    }
}

}  // namespace

bool is_importable_scene_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext.empty()) return false;
    Assimp::Importer importer;
    return importer.IsExtensionSupported(ext);
}

ImportedScene import_scene_file(const std::string& path, const std::vector<Vec3>& viewpoints) {
    check_input_file(path, "scene file");
    if (!is_importable_scene_file(path))
        throw Error(fmt::format("'{}': no importer reads '{}' files", path, lower_extension(path)));
    const std::string ext = lower_extension(path);
    if (ext == ".obj") check_obj_text(path, false);
    if (ext == ".off") check_off_text(path);
    if (ext == ".stl") check_stl_size(path);
    if (ext == ".ply") check_ply_header(path);

    Assimp::Importer importer;
    // Points and lines come out as meshes of their own; identical vertices are joined so
    // faces share edges (charts.hpp keys edges by their end points).
    const unsigned flags =
        aiProcess_JoinIdenticalVertices | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    const aiScene* scene = importer.ReadFile(path, flags);
    if (!scene || !scene->mRootNode)
        throw Error(fmt::format("'{}' could not be read: {}", path, importer.GetErrorString()));
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        throw Error(fmt::format("'{}' is incomplete (assimp could not read all of it)", path));

    ImportedScene out;
    const std::string dir = std::filesystem::path(path).parent_path().string();
    const bool gltf = is_gltf(path);
    const GltfExtras extras = gltf ? gltf_extras(path) : GltfExtras{};
    std::vector<ImportedGroup> groups(scene->mNumMaterials);
    for (unsigned k = 0; k < scene->mNumMaterials; ++k) {
        if (k < extras.emissive_strength.size())
            groups[k].emissive_strength = extras.emissive_strength[k];
        const aiMaterial& m = *scene->mMaterials[k];
        aiString name;
        groups[k].material_name = m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length
                                      ? name.C_Str()
                                      : fmt::format("material#{}", k);
        map_material(*scene, m, gltf, k < extras.glass.size() ? extras.glass[k] : GltfGlass{}, dir,
                     groups[k]);
        const Rgb& e = groups[k].material.emission;
        if (!(std::max({e.x, e.y, e.z}) <= 1e20))
            throw Error(
                fmt::format("{}: material '{}': emission {} is out of range (at most "
                            "1e20 W m^-2 sr^-1)",
                            path, groups[k].material_name, rgb_text(e)));
    }
    Collector collect{*scene, path, groups};
    collect.visit(scene->mRootNode, aiMatrix4x4());
    // Materials of one name (assimp's default material, repeated names) stay apart: the
    // caller names them "<name>", "<name>#2", ...
    for (ImportedGroup& g : groups)
        if (!g.mesh.faces.empty()) out.groups.push_back(std::move(g));
    if (out.groups.empty()) throw Error(fmt::format("'{}' has no faces", path));

    if (collect.skipped_primitives)
        out.left_out.push_back(
            fmt::format("{} mesh(es) of points or lines", collect.skipped_primitives));
    out.cameras = cameras_of(*scene, gltf ? &extras : nullptr, out.left_out);
    out.lights = lights_of(*scene, path, gltf, out.left_out, out.notes);
    choose_glass(out.groups, out.notes);
    orient(out.groups, out.cameras, out.lights, viewpoints, out.notes);
    return out;
}

}  // namespace vlf
