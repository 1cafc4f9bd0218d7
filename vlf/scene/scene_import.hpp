// scene_import.hpp — whole scenes from modelling tools' files (OBJ+MTL, glTF 2.0 / GLB, PLY,
// FBX, COLLADA, ...) through assimp (issue 12). Geometry comes out in file units with the
// file's node transforms applied (instances repeated), grouped by material; materials are
// mapped onto VLF's (diffuse, ideal mirror, Lambertian emitter, and glass where the file's
// glass is a closed solid) and whatever cannot be represented is listed per material so the
// caller reports it once. The file's point, spot
// and directional lights become VLF lights (light.hpp) with their strengths taken as they are
// (glTF: 1 cd -> 1 W/sr, 1 lux -> 1 W per square unit). The scene loader turns the groups into
// objects and adds the cameras and lights (scene_loader.cpp, object type "import").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/light.hpp"
#include "vlf/scene/mesh_import.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// One material of the file with the faces that use it.
struct ImportedGroup {
    std::string material_name;       // the file's name ("material#<i>" when it has none)
    Material material;               // mapped (material_mapping in scene_import.cpp)
    bool two_sided = false;          // the file marks the material double-sided
    double emissive_strength = 1.0;  // glTF KHR_materials_emissive_strength
    // Its diffuse colour texture (width 0 when it has none); material.diffuse is then the
    // file's colour x the texture's mean (Material::diffuse_texture).
    Texture texture;
    // What the mapping could not represent, one phrase each ("a Phong highlight Ks = ...").
    std::vector<std::string> unrepresented;
    // The file's glass (MTL illum 4, 6, 7 or 9; glTF transmission with a volume) as a
    // dielectric, its absorption per file unit, and what that leaves out. import_scene_file
    // makes it the material where the group's faces close up into solids (else `material`
    // stays, and the reason is noted).
    std::optional<Material> glass;
    std::string glass_what;  // what made it glass ("illum 7", "transmission 1 with a volume")
    std::vector<std::string> glass_unrepresented;
    // Where the glass was made the material: the material it replaced, which the loader
    // falls back to if the faces come apart when it drops degenerate or repeated ones.
    std::optional<Material> not_glass;
    // File units, node transforms applied; faces as in the file, except that faces of
    // one-sided materials are turned to face one way per part (winding.hpp; noted).
    ImportedMesh mesh;
};

struct ImportedScene {
    std::vector<ImportedGroup> groups;  // in the file's material order; empty groups left out
    std::vector<Camera> cameras;        // file units, node transforms applied
    // Point, spot and directional lights: positions in file units, unit directions in the
    // file's frame (node transforms applied); names unique. Strengths as the file gives them
    // (colour x intensity): point and spot intensity in W/sr, directional irradiance in W per
    // square unit (glTF's candela and lux taken as these, as emission is taken as radiance).
    std::vector<Light> lights;
    // Things of the file left out, one phrase each ("2 meshes of points or lines",
    // "light 'Sky' (ambient): ...").
    std::vector<std::string> left_out;
    // Things taken differently from the file, one phrase each ("light 'Lamp' (point):
    // attenuation ... replaced by the inverse square law", "material 'Body': 12 of 480
    // face(s) turned to agree with their neighbours").
    std::vector<std::string> notes;
};

// True when assimp has a reader for the file's extension.
bool is_importable_scene_file(const std::string& path);

// Reads a scene file. Faces whose winding disagrees with their neighbours', and closed parts
// that face inward (unless around the file's camera or light), are turned (winding.hpp);
// double-sided materials keep the file's winding. Throws vlf::Error naming the file and the place:
// missing or unreadable file, unsupported format, assimp's parse error, a non-finite or
// out-of-range vertex (an OBJ's by line number), a file without faces.
// `viewpoints` (the file's frame): where the scene around the file has cameras or lights,
// besides the file's own; a closed part around one faces inward (winding.hpp).
ImportedScene import_scene_file(const std::string& path, const std::vector<Vec3>& viewpoints = {});

}  // namespace vlf
