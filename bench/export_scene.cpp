// export_scene.cpp — a scene as VLF loads it (every face tessellated, imports mapped, units
// as the user's), written as one JSON file for an independent renderer to rebuild:
// bench/blender_reference.py renders it with Blender's Cycles. Usage:
//   vlf_export_scene SCENE OUT.json
// Written: per object its material, the outer side of each face (a two-sided face once,
// flagged; a dielectric's inner twins left out, as glass is one surface to Cycles), its
// vertices in user units and, for smooth faces, the shading normal at each corner; the
// materials (diffuse, mirror, emission, dielectric), the lights and the cameras.
// Diffuse textures are not written (their materials' mean albedo is): a note says so.
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "vlf/bake/scene_json.hpp"
#include "vlf/core/error.hpp"
#include "vlf/scene/scene_loader.hpp"

int main(int argc, char** argv) try {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s SCENE OUT.json\n", argv[0]);
        return 2;
    }
    const vlf::Scene scene = vlf::load_scene(argv[1]);
    // Materials, lights and cameras as the bundle's scene.json has them; the objects with
    // their faces instead of face ranges.
    nlohmann::json out = vlf::scene_to_json(scene);
    out["source"] = argv[1];
    out["objects"] = nlohmann::json::array();
    bool textured = false;
    for (const vlf::Material& m : scene.materials) textured = textured || m.diffuse_texture >= 0;
    if (textured)
        std::fprintf(stderr,
                     "note: %s: diffuse textures are not exported (their materials' mean albedo "
                     "is)\n",
                     argv[1]);
    for (const vlf::SceneObject& o : scene.objects) {
        nlohmann::json obj = {{"name", o.name}, {"vertices", nlohmann::json::array()}};
        nlohmann::json faces = nlohmann::json::array(), normals = nlohmann::json::array();
        bool two_sided = false, smooth = false;
        int material = -1;
        for (int k = o.first_face; k < o.first_face + o.face_count; ++k) {
            const vlf::Face& f = scene.faces[size_t(k)];
            if (f.inner || (f.twin >= 0 && f.twin < f.id)) continue;  // the other side
            two_sided =
                two_sided || (f.twin >= 0 && !scene.materials[size_t(f.material)].dielectric);
            if (material >= 0 && material != f.material)
                throw vlf::Error("object '" + o.name + "' has faces of two materials");
            material = f.material;
            nlohmann::json face = nlohmann::json::array(), corner_normals = nlohmann::json::array();
            for (size_t v = 0; v < f.vertices.size(); ++v) {
                face.push_back(obj["vertices"].size());
                obj["vertices"].push_back(
                    vlf::vec_json(scene.normalisation.to_user(f.vertices[v])));
                corner_normals.push_back(
                    vlf::vec_json(f.vertex_normals.empty() ? f.normal : f.vertex_normals[v]));
            }
            smooth = smooth || !f.vertex_normals.empty();
            faces.push_back(face);
            normals.push_back(corner_normals);
        }
        if (material < 0) continue;
        obj["material"] = material;
        obj["two_sided"] = two_sided;
        obj["faces"] = faces;
        if (smooth) obj["corner_normals"] = normals;
        out["objects"].push_back(obj);
    }
    std::ofstream os(argv[2]);
    os << out.dump();
    if (!os) throw vlf::Error(std::string(argv[2]) + ": cannot be written");
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
}
