// scene_import_test.cpp — whole scenes from model files (vlf/scene/scene_import.hpp and the
// loader's "import" objects): material mapping of OBJ/MTL and glTF, node transforms, cameras,
// overrides, the repairs and errors of bad files, and faces turned to one winding.
#include "vlf/scene/scene_import.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/scene/light.hpp"
#include "vlf/scene/primitives.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/scene/winding.hpp"

namespace vlf {
namespace {

const std::string kModels = std::string(VLF_SOURCE_DIR) + "/scenes/models";

using test::TempDir;

const Material& material_named(const Scene& s, const std::string& name) {
    for (const Material& m : s.materials)
        if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return s.materials.front();
}

using test::object_named;

bool has_note(const Scene& s, const std::string& text) {
    for (const std::string& n : s.load_notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

void expect_rgb(const Rgb& got, const Rgb& want, double tol = 1e-6) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tol) << "channel " << c;
}

std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                           (unsigned char)bytes[i + 2];
        for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
    }
    if (i < bytes.size()) {
        unsigned v = (unsigned char)bytes[i] << 16;
        if (i + 1 < bytes.size()) v |= (unsigned char)bytes[i + 1] << 8;
        out += k[(v >> 18) & 63];
        out += k[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

// A glTF 2.0 file of one unit quad (y = 0, facing +y, x and z in [-1, 1]) used by three
// nodes: a diffuse floor, a lamp turned upside down at y = 1 (emissive x strength 4), and
// a mirror with a mirroring scale (x -> -x) at y = 0.5; and a camera at (0, 0.5, 3).
std::string quad_gltf() {
    const float pos[12] = {-1, 0, -1, -1, 0, 1, 1, 0, 1, 1, 0, -1};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    std::string bytes(sizeof pos + sizeof idx, '\0');
    std::memcpy(bytes.data(), pos, sizeof pos);
    std::memcpy(bytes.data() + sizeof pos, idx, sizeof idx);
    using nlohmann::json;
    json g = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_materials_emissive_strength"}},
        {"buffers",
         {{{"byteLength", bytes.size()},
           {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", sizeof pos}},
          {{"buffer", 0}, {"byteOffset", sizeof pos}, {"byteLength", sizeof idx}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", 5126},
           {"count", 4},
           {"type", "VEC3"},
           {"min", {-1, 0, -1}},
           {"max", {1, 0, 1}}},
          {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
        {"materials",
         {{{"name", "paint"},
           {"pbrMetallicRoughness",
            {{"baseColorFactor", {0.5, 0.6, 0.7, 1}}, {"metallicFactor", 0}}}},
          {{"name", "glow"},
           {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
           {"emissiveFactor", {1, 0.5, 0.25}},
           {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
          {{"name", "chrome"},
           {"pbrMetallicRoughness",
            {{"baseColorFactor", {0.9, 0.8, 0.7, 1}},
             {"metallicFactor", 1},
             {"roughnessFactor", 0}}}}}},
        {"meshes",
         {{{"name", "floor"},
           {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}},
          {{"name", "lamp"},
           {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 1}}}}},
          {{"name", "mirror"},
           {"primitives",
            {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 2}}}}}}},
        {"cameras",
         {{{"name", "view"},
           {"type", "perspective"},
           {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.5}, {"znear", 0.01}}}}}},
        {"nodes",
         {{{"mesh", 0}},
          {{"mesh", 1}, {"translation", {0, 1, 0}}, {"rotation", {1, 0, 0, 0}}},
          {{"mesh", 2}, {"translation", {0, 0.5, 0}}, {"scale", {-0.25, 1, 0.25}}},
          {{"name", "view"}, {"camera", 0}, {"translation", {0, 0.5, 3}}}}},
        {"scenes", {{{"nodes", {0, 1, 2, 3}}}}},
        {"scene", 0}};
    return g.dump(1);
}

// ---- OBJ + MTL: the public Cornell box (scenes/models/cornell-box/README.md) ------------

TEST(SceneImport, CornellBoxObjMaterialsAndRepairs) {
    const Scene s = load_scene(kModels + "/cornell-box/CornellBox-Original.obj");
    expect_rgb(material_named(s, "CornellBox-Original/leftWall").diffuse, {0.63, 0.065, 0.05});
    expect_rgb(material_named(s, "CornellBox-Original/rightWall").diffuse, {0.14, 0.45, 0.091});
    const Material& light = material_named(s, "CornellBox-Original/light");
    expect_rgb(light.emission, {17, 12, 4});
    expect_rgb(light.diffuse, {0.78, 0.78, 0.78});
    // 8 quads of the room and lamp, 12 of the boxes less the two the file repeats
    // ("f -8 -7 -6 -5" for a box's bottom repeats its front), all as triangles.
    EXPECT_EQ(s.faces.size(), 2u * (6 + 12 - 2));
    EXPECT_TRUE(has_note(s, "2 repeated triangle(s) dropped")) << s.load_notes.size();
    EXPECT_TRUE(has_note(s, "non-planar face(s) split into triangles"));
    for (const Face& f : s.faces) EXPECT_EQ(f.vertices.size(), 3u);
    // Every wall faces into the room: its normal points at the box's centre.
    const Vec3 centre = s.normalisation.to_normalised({0.0, 1.0, 0.0});
    for (const char* wall : {"floor", "ceiling", "backWall", "leftWall", "rightWall"}) {
        const SceneObject& o = object_named(s, std::string("CornellBox-Original/") + wall);
        for (int k = 0; k < o.face_count; ++k) {
            const Face& f = s.faces[size_t(o.first_face + k)];
            EXPECT_GT(glm::dot(f.normal, centre - f.vertices[0]), 0) << wall;
        }
    }
}

// An FBX (ASCII 7.4, written for this test): materials by their Lambert colours, the
// emissive colour as a lamp, node translations applied, faces facing as wound.
TEST(SceneImport, FbxMaterialsAndNodes) {
    const Scene s = load_scene(test::source_path("tests/scenes/fbx-room.fbx"));
    expect_rgb(material_named(s, "fbx-room/grey").diffuse, {0.5, 0.4, 0.3});
    expect_rgb(material_named(s, "fbx-room/glow").emission, {4, 4, 4});
    EXPECT_EQ(s.faces.size(), 4u);
    const SceneObject& lamp = object_named(s, "fbx-room/glow");
    for (int k = 0; k < lamp.face_count; ++k) {
        const Face& f = s.faces[size_t(lamp.first_face + k)];
        EXPECT_NEAR(s.normalisation.to_user(f.vertices[0]).y, 1.5, 1e-9);  // 1 + the node's 0.5
        EXPECT_NEAR(f.normal.y, -1.0, 1e-12);                              // facing the floor
    }
    const SceneObject& floor = object_named(s, "fbx-room/grey");
    for (int k = 0; k < floor.face_count; ++k)
        EXPECT_NEAR(s.faces[size_t(floor.first_face + k)].normal.y, 1.0, 1e-12);
}

// McGuire's sphere Cornell box: illum 5 is a mirror, and the closed sphere of illum 7 is
// glass of index Ni (its Kd, Ks and Tf noted as left out), smooth by the file's normals,
// every face with its inner twin.
TEST(SceneImport, MtlIllumFiveIsAMirrorAndClosedIllumSevenIsGlass) {
    const Scene s = load_scene(kModels + "/cornell-box/CornellBox-Sphere.obj");
    const Material& chrome = material_named(s, "CornellBox-Sphere/leftSphere");
    expect_rgb(chrome.specular, {0.95, 0.95, 0.95});
    expect_rgb(chrome.diffuse, {0.01, 0.01, 0.01});
    const Material& glass = material_named(s, "CornellBox-Sphere/rightSphere");
    EXPECT_TRUE(glass.dielectric);
    EXPECT_EQ(glass.ior, 2.5);
    expect_rgb(glass.absorption, {0, 0, 0});
    expect_rgb(glass.diffuse + glass.specular + glass.emission, {0, 0, 0});
    EXPECT_TRUE(has_note(s, "material 'rightSphere': illum 7 made glass of ior 2.5"));
    EXPECT_TRUE(
        has_note(s,
                 "material 'rightSphere': left out: Kd = [0.01, 0.01, 0.01], Ks = [0.3, 0.3, "
                 "0.3], Tf = [0.1, 0.1, 0.1] (glass reflects and refracts"));
    EXPECT_FALSE(has_note(s, "a Phong highlight Ks = [0.3"));
    const SceneObject& ball = object_named(s, "CornellBox-Sphere/rightSphere");
    ASSERT_GT(ball.face_count, 0);
    ASSERT_EQ(ball.face_count % 2, 0);
    for (int k = 0; k < ball.face_count; ++k) {
        const Face& f = s.faces[size_t(ball.first_face + k)];
        EXPECT_EQ(f.inner, k >= ball.face_count / 2) << "face " << k;
        EXPECT_GE(f.twin, 0) << "face " << k;
    }
    EXPECT_FALSE(s.faces[size_t(ball.first_face)].vertex_normals.empty());  // smooth
}

// The same glass written as an open surface (one quad) stays what the rest of its material
// says, and the note says why it is not glass.
TEST(SceneImport, MtlGlassThatIsNotClosedStaysAndIsNoted) {
    TempDir dir("open-glass");
    dir.write("pane.mtl",
              "newmtl pane\nKd 0.2 0.2 0.2\nNi 1.5\nillum 7\n"
              "newmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
    const std::string file = dir.write("pane.obj",
                                       "mtllib pane.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                       "v 0 2 1\nv 1 2 1\nv 1 2 2\n"
                                       "usemtl pane\nf 1 2 3 4\nusemtl lamp\nf 5 7 6\n");
    const Scene s = load_scene(file);
    const Material& pane = material_named(s, "pane/pane");
    EXPECT_FALSE(pane.dielectric);
    expect_rgb(pane.diffuse, {0.2, 0.2, 0.2});
    EXPECT_TRUE(has_note(s, "illum 7 (glass; not made glass: its faces are not closed: the edge "));
}

// Glass that is closed in the file only through a zero-area triangle (a T-junction on an
// edge, closed by a sliver): the loader drops the sliver, the cube opens, and the file's
// other material is taken, with a note, instead of a load error.
TEST(SceneImport, MtlGlassThatOpensWhenRepairedFallsBack) {
    TempDir dir("sliver-glass");
    dir.write("sliver.mtl",
              "newmtl glass\nKd 0.3 0.3 0.3\nNi 1.5\nillum 7\n"
              "newmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
    const std::string file = dir.write(
        "sliver.obj",
        "mtllib sliver.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
        "v 0 1 1\nv 0.5 0 0\nv 0 3 0\nv 1 3 0\nv 1 3 1\nusemtl glass\n"
        "f 1 4 3\nf 1 3 9\nf 9 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\n"
        "f 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\nf 1 9 2\nusemtl lamp\nf 10 11 12\n");
    const Scene s = load_scene(file);
    const Material& m =
        s.materials[size_t(s.faces[size_t(object_named(s, "sliver/glass").first_face)].material)];
    EXPECT_FALSE(m.dielectric);
    expect_rgb(m.diffuse, {0.3, 0.3, 0.3});
    EXPECT_TRUE(has_note(s, "material 'glass': illum 7 made glass of ior 1.5"));
    EXPECT_TRUE(has_note(s,
                         "sliver.obj: material 'glass': not made glass after all: its faces "
                         "are not closed once repaired"));
    EXPECT_EQ(object_named(s, "sliver/glass").face_count, 13);  // one-sided, the sliver dropped
}

// A closed cube of MTL glass imports as the scene file's own dielectric on the same mesh: the
// same light on every texel of the room after three cycles, to rounding (1e-9 of the
// brightest texel: the two loaders' vertices round apart by about 1e-13; a wrong index,
// a missing inner face or a double-sided cube moves texels by 1e-3 and more).
TEST(SceneImport, MtlGlassPropagatesAsTheSceneFilesDielectric) {
    TempDir dir("glass-cube");
    dir.write("glass.mtl", "newmtl glass\nKd 0.1 0.1 0.1\nNi 1.6\nillum 4\n");
    std::string cube = test::read_text(test::source_path("tests/scenes/winding-cube.obj"));
    cube.replace(cube.find("mtllib winding.mtl"), 18, "mtllib glass.mtl");
    cube.replace(cube.find("usemtl glow"), 11, "usemtl glass");
    dir.write("cube.obj", cube);
    auto room = [&](const std::string& cube_object) {
        return load_scene_from_string(
            R"({"settings": {"texel_size": 0.5},
                "materials": {"white": {"diffuse": [0.7, 0.6, 0.5]},
                              "lamp": {"emission": [8, 8, 8], "diffuse": [0.2, 0.2, 0.2]},
                              "glass": {"dielectric": {"ior": 1.6}}},
                "objects": [
                  {"type": "box", "min": [-1, 0, 1], "max": [4, 5, 6], "flip": true,
                   "material": "white"},
                  {"type": "polygon", "material": "lamp", "vertices": [[1, 4.99, 3], [2, 4.99, 3],
                   [2, 4.99, 4], [1, 4.99, 4]]},)" +
                cube_object + "]}",
            "room.json", dir.path.string());
    };
    const Scene imported = room(R"({"type": "import", "name": "cube", "file": "cube.obj"})");
    const Scene written =
        room(R"({"type": "mesh", "name": "cube", "file": "cube.obj", "material": "glass"})");
    ASSERT_TRUE(material_named(imported, "cube/glass").dielectric);
    ASSERT_EQ(imported.faces.size(), written.faces.size());
    const PropagateParams p = test::params(129, 16, 4, 3);
    const auto a = test::run_transport(imported, p);
    const auto b = test::run_transport(written, p);
    const auto& ta = a->texture_maps().total;
    const auto& tb = b->texture_maps().total;
    ASSERT_EQ(ta.size(), tb.size());
    double most = 0.0;
    for (const auto& v : tb) most = std::max(most, double(v.x));
    ASSERT_GT(most, 0.0);
    for (size_t k = 0; k < ta.size(); ++k)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(double(ta[k][c]), double(tb[k][c]), 1e-9 * most) << "texel " << k;
}

// ---- glTF: materials, node transforms, cameras ------------------------------------------

TEST(SceneImport, GltfMaterialsNodesAndCamera) {
    TempDir dir("gltf");
    const std::string file = dir.write("quads.gltf", quad_gltf());
    const Scene s = load_scene(file);
    expect_rgb(material_named(s, "quads/paint").diffuse, {0.5, 0.6, 0.7});
    const Material& glow = material_named(s, "quads/glow");
    expect_rgb(glow.emission, {4, 2, 1});
    expect_rgb(glow.diffuse, {0, 0, 0});
    const Material& chrome = material_named(s, "quads/chrome");
    expect_rgb(chrome.specular, {0.9, 0.8, 0.7});
    expect_rgb(chrome.diffuse, {0, 0, 0});
    // The lamp is turned upside down at y = 1; the mirror, under a mirroring scale, still
    // faces up (its winding is reversed with the transform).
    auto normal_of = [&](const std::string& name) {
        return s.faces[size_t(object_named(s, name).first_face)].normal;
    };
    EXPECT_NEAR(normal_of("quads/glow").y, -1.0, 1e-9);
    EXPECT_NEAR(normal_of("quads/paint").y, 1.0, 1e-9);
    EXPECT_NEAR(normal_of("quads/chrome").y, 1.0, 1e-9);
    const SceneObject& lamp = object_named(s, "quads/glow");
    const Vec3 p = s.normalisation.to_user(s.faces[size_t(lamp.first_face)].vertices[0]);
    EXPECT_NEAR(p.y, 1.0, 1e-6);
    double mirror_area = 0;
    const SceneObject& mirror = object_named(s, "quads/chrome");
    for (int k = 0; k < mirror.face_count; ++k)
        mirror_area += s.faces[size_t(mirror.first_face + k)].area;
    const double scale = s.normalisation.scale;
    EXPECT_NEAR(mirror_area / (scale * scale), 4.0 * 0.25 * 0.25, 1e-6);

    ASSERT_EQ(s.cameras.size(), 1u);
    const Camera& c = s.cameras[0];
    EXPECT_EQ(c.name, "quads/view");
    EXPECT_NEAR(glm::length(c.eye - Vec3(0, 0.5, 3)), 0.0, 1e-6);
    const Vec3 d = glm::normalize(c.look_at - c.eye);
    EXPECT_NEAR(d.z, -1.0, 1e-6);
    EXPECT_NEAR(c.fov_y_deg, 0.8 * 180.0 / kPi, 1e-3);  // glTF's yfov
}

// glTF transmission (KHR_materials_transmission) is kept in the material for dielectrics and
// noted as not propagated.
TEST(SceneImport, GltfTransmissionIsKeptAndNoted) {
    TempDir dir("transmission");
    nlohmann::json g = nlohmann::json::parse(quad_gltf());
    g["extensionsUsed"].push_back("KHR_materials_transmission");
    g["materials"][0]["extensions"] = {
        {"KHR_materials_transmission", {{"transmissionFactor", 0.9}}}};
    const Scene s = load_scene(dir.write("glass.gltf", g.dump()));
    EXPECT_NEAR(material_named(s, "glass/paint").transmission, 0.9, 1e-6);
    EXPECT_TRUE(has_note(s, "transmission 0.9"));
}

// A glTF cube of 2 units (8 shared corners, 12 triangles wound outward) of one material
// `cube`, the material's JSON given, with the unit quad of quad_gltf() above it as a lamp.
std::string glass_cube_gltf(const nlohmann::json& material) {
    nlohmann::json g = nlohmann::json::parse(quad_gltf());
    const float pos[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                           -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    const uint16_t idx[36] = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                              3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    std::string bytes(sizeof pos + sizeof idx, '\0');
    std::memcpy(bytes.data(), pos, sizeof pos);
    std::memcpy(bytes.data() + sizeof pos, idx, sizeof idx);
    g["buffers"].push_back({{"byteLength", bytes.size()},
                            {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
    g["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", sizeof pos}});
    g["bufferViews"].push_back(
        {{"buffer", 1}, {"byteOffset", sizeof pos}, {"byteLength", sizeof idx}});
    g["accessors"].push_back({{"bufferView", 2},
                              {"componentType", 5126},
                              {"count", 8},
                              {"type", "VEC3"},
                              {"min", {-1, -1, -1}},
                              {"max", {1, 1, 1}}});
    g["accessors"].push_back(
        {{"bufferView", 3}, {"componentType", 5123}, {"count", 36}, {"type", "SCALAR"}});
    nlohmann::json m = material;
    m["name"] = "cube";
    g["materials"].push_back(m);
    g["meshes"].push_back(
        {{"name", "cube"},
         {"primitives", {{{"attributes", {{"POSITION", 2}}}, {"indices", 3}, {"material", 3}}}}});
    g["nodes"].push_back({{"mesh", 3}, {"translation", {0, 3, 0}}});
    g["scenes"][0]["nodes"].push_back(g["nodes"].size() - 1);
    for (const char* e :
         {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"})
        g["extensionsUsed"].push_back(e);
    return g.dump(1);
}

// Transmission with a volume (KHR_materials_volume) on a closed mesh is glass: its index from
// KHR_materials_ior and its absorption from the attenuation colour reached at the
// attenuation distance, per file unit, over the import object's scale; without a volume
// (thin-walled) it stays diffuse and is noted. Double-sided glass is one-sided (a solid).
TEST(SceneImport, GltfTransmissionWithAVolumeIsGlass) {
    TempDir dir("gltf-glass");
    const nlohmann::json solid = nlohmann::json::parse(R"({
        "doubleSided": true,
        "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                 "roughnessFactor": 0.05},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                       "KHR_materials_ior": {"ior": 1.45},
                       "KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationDistance": 0.8,
                                                "attenuationColor": [0.5, 0.25, 1]}}})");
    dir.write("solid.gltf", glass_cube_gltf(solid));
    const Scene s = load_scene_from_string(
        R"({"materials": {}, "objects": [{"type": "import", "name": "m", "file": "solid.gltf",
            "scale": 2}]})",
        "solid.json", dir.path.string());
    const Material& glass = material_named(s, "m/cube");
    EXPECT_TRUE(glass.dielectric);
    EXPECT_NEAR(glass.ior, 1.45, 1e-12);
    // Per user unit: the file's -ln(colour) / 0.8, over the scale of 2.
    expect_rgb(glass.absorption, {std::log(2.0) / 1.6, std::log(4.0) / 1.6, 0.0}, 1e-12);
    EXPECT_TRUE(
        has_note(s, "material 'cube': transmission 1 with a volume made glass of ior 1.45"));
    EXPECT_TRUE(has_note(s, "left out: roughness 0.05 (taken as smooth glass)"));
    const SceneObject& cube = object_named(s, "m/cube");
    EXPECT_EQ(cube.face_count, 24);  // 12 outer faces and their inner twins, not 2 x 2 x 12
    for (int k = 0; k < cube.face_count / 2; ++k) {
        const Face& f = s.faces[size_t(cube.first_face + k)];
        const Vec3 centre = s.normalisation.to_normalised({0.0, 6.0, 0.0});
        EXPECT_GT(glm::dot(f.normal, polygon_centroid(f.vertices) - centre), 0) << "face " << k;
    }

    nlohmann::json thin = solid;
    thin["extensions"].erase("KHR_materials_volume");
    const Scene t = load_scene(dir.write("thin.gltf", glass_cube_gltf(thin)));
    const Material& pane = material_named(t, "thin/cube");
    EXPECT_FALSE(pane.dielectric);
    EXPECT_NEAR(pane.transmission, 1.0, 1e-12);
    expect_rgb(pane.diffuse, {1, 1, 1});
    EXPECT_TRUE(has_note(t, "transmission 1, ior 1.45 (thin-walled: no KHR_materials_volume"));
}

// ---- glTF lights (KHR_lights_punctual) ---------------------------------------------------

const Light& light_named(const Scene& s, const std::string& name) {
    for (const Light& l : s.lights)
        if (l.name == name) return l;
    ADD_FAILURE() << "no light " << name;
    return s.lights.front();
}

// quad_gltf() lit by KHR_lights_punctual lights (its lamp dark, so only the lights emit): a
// point light "bulb" (colour [1, 0.5, 0.25] x 8 cd, range 10) at (0.25, 2, -0.5) in a node
// under a parent translated by (1, 0, 0); a spot "cone" (3 cd, half-angles 0.2 and 0.6 rad)
// at (0, 3, 0) turned -90 degrees about x so it shines down; a directional "sun" (2 lux x
// [1, 1, 0.5]) turned -45 degrees about x, travelling along (0, -1, -1) / sqrt 2; and a
// point light of zero intensity.
std::string lights_gltf() {
    nlohmann::json g = nlohmann::json::parse(quad_gltf());
    g["materials"][1]["emissiveFactor"] = {0, 0, 0};
    g["extensionsUsed"].push_back("KHR_lights_punctual");
    g["extensions"]["KHR_lights_punctual"]["lights"] = nlohmann::json::parse(R"([
        {"name": "bulb", "type": "point", "color": [1, 0.5, 0.25], "intensity": 8, "range": 10},
        {"type": "spot", "intensity": 3, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"type": "directional", "color": [1, 1, 0.5], "intensity": 2},
        {"type": "point", "intensity": 0}])");
    auto& nodes = g["nodes"];
    const size_t first = nodes.size();
    nodes.push_back(nlohmann::json::parse(R"({"name": "holder", "translation": [1, 0, 0]})"));
    nodes.back()["children"] = {first + 1};
    for (
        const char* n : {
            R"({"name": "bulb", "translation": [0.25, 2, -0.5],
                 "extensions": {"KHR_lights_punctual": {"light": 0}}})",
            R"({"name": "cone", "translation": [0, 3, 0], "rotation": [-0.70710678, 0, 0, 0.70710678],
                 "extensions": {"KHR_lights_punctual": {"light": 1}}})",
            R"({"name": "sun", "rotation": [-0.38268343, 0, 0, 0.92387953],
                 "extensions": {"KHR_lights_punctual": {"light": 2}}})",
            R"({"name": "off", "translation": [0, 1, 0],
                 "extensions": {"KHR_lights_punctual": {"light": 3}}})"})
        nodes.push_back(nlohmann::json::parse(n));
    for (size_t k : {first, first + 2, first + 3, first + 4}) g["scenes"][0]["nodes"].push_back(k);
    return g.dump(1);
}

TEST(SceneImport, GltfLightsWithNodeTransformsUnitsAndNotes) {
    TempDir dir("lights");
    const std::string file = dir.write("lit.gltf", lights_gltf());
    const Scene s = load_scene(file);  // loads: the lights are its only emitters
    ASSERT_EQ(s.lights.size(), 3u);

    const Light& bulb = light_named(s, "lit/bulb");
    EXPECT_EQ(bulb.type, LightType::Point);
    EXPECT_NEAR(glm::length(bulb.position - Vec3(1.25, 2, -0.5)), 0.0, 1e-6);
    expect_rgb(bulb.intensity, {8, 4, 2});  // colour x intensity, 1 cd -> 1 W/sr

    const Light& cone = light_named(s, "lit/cone");
    EXPECT_EQ(cone.type, LightType::Spot);
    EXPECT_NEAR(glm::length(cone.position - Vec3(0, 3, 0)), 0.0, 1e-6);
    EXPECT_NEAR(glm::length(cone.direction - Vec3(0, -1, 0)), 0.0, 1e-6);
    expect_rgb(cone.intensity, {3, 3, 3});
    // glTF's cone angles are half-angles, taken as they are.
    EXPECT_NEAR(cone.cos_inner, std::cos(0.2), 1e-6);
    EXPECT_NEAR(cone.cos_outer, std::cos(0.6), 1e-6);

    const Light& sun = light_named(s, "lit/sun");
    EXPECT_EQ(sun.type, LightType::Directional);
    EXPECT_NEAR(glm::length(sun.direction - Vec3(0, -1, -1) / std::sqrt(2.0)), 0.0, 1e-6);
    expect_rgb(sun.irradiance, {2, 2, 1});  // 1 lux -> 1 W per square unit

    EXPECT_TRUE(has_note(s, "lit.gltf: left out: light 'off' (point): zero intensity"));
    EXPECT_TRUE(has_note(s, "lit.gltf: light 'bulb' (point): range 10 not kept"));
    EXPECT_TRUE(has_note(s,
                         "lit.gltf: light strengths taken as they are: "
                         "KHR_lights_punctual's candela as W/sr"));
    int unit_notes = 0;
    for (const std::string& n : s.load_notes) unit_notes += n.find("candela") != std::string::npos;
    EXPECT_EQ(unit_notes, 1);
    EXPECT_FALSE(has_note(s, "attenuation"));  // glTF's lights are inverse square
}

// COLLADA (through assimp's other readers): full cone angles halved, a constant fall-off
// replaced by the inverse square law (noted), a quadratic one divided out, ambient left out.
TEST(SceneImport, ColladaLightsAttenuationAndFullConeAngles) {
    TempDir dir("dae");
    const std::string file = dir.write("lit.dae", R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_lights>
    <light id="lamp" name="lamp"><technique_common><point><color>2 2 2</color>
      <constant_attenuation>1</constant_attenuation><linear_attenuation>0</linear_attenuation>
      <quadratic_attenuation>0</quadratic_attenuation></point></technique_common></light>
    <light id="cone" name="cone"><technique_common><spot><color>1 1 1</color>
      <constant_attenuation>0</constant_attenuation><linear_attenuation>0</linear_attenuation>
      <quadratic_attenuation>2</quadratic_attenuation><falloff_angle>60</falloff_angle>
      <falloff_exponent>0</falloff_exponent><outer_cone>90</outer_cone></spot></technique_common>
    </light>
    <light id="sky" name="sky"><technique_common><ambient><color>0.1 0.1 0.1</color></ambient>
    </technique_common></light>
  </library_lights>
  <library_geometries><geometry id="quad"><mesh>
    <source id="p"><float_array id="pa" count="12">-1 0 -1 -1 0 1 1 0 1 1 0 -1</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/>
        <param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
    </source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <polylist count="1"><input semantic="VERTEX" source="#v" offset="0"/><vcount>4</vcount>
      <p>0 1 2 3</p></polylist>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s">
    <node id="floor" name="floor"><instance_geometry url="#quad"/></node>
    <node id="lampnode" name="lampnode"><translate>0 2 0</translate><instance_light url="#lamp"/></node>
    <node id="conenode" name="conenode"><translate>0 3 0</translate><rotate>1 0 0 -90</rotate>
      <instance_light url="#cone"/></node>
    <node id="skynode" name="skynode"><instance_light url="#sky"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)");
    const Scene s = load_scene(file);
    ASSERT_EQ(s.lights.size(), 2u);
    const Light& lamp = light_named(s, "lit/lampnode");
    EXPECT_NEAR(glm::length(lamp.position - Vec3(0, 2, 0)), 0.0, 1e-6);
    expect_rgb(lamp.intensity, {2, 2, 2});
    EXPECT_TRUE(has_note(s,
                         "lit.dae: light 'lampnode' (point): attenuation 1 / (1 + 0 d + 0 d^2) "
                         "replaced by the inverse square law"));
    const Light& cone = light_named(s, "lit/conenode");
    expect_rgb(cone.intensity, {0.5, 0.5, 0.5});  // 1 / (2 d^2): half the colour
    EXPECT_NEAR(glm::length(cone.direction - Vec3(0, -1, 0)), 0.0, 1e-6);
    EXPECT_NEAR(cone.cos_inner, std::cos(kPi / 6), 1e-6);  // 60 degrees across
    EXPECT_NEAR(cone.cos_outer, std::cos(kPi / 4), 1e-6);  // 90 degrees across
    EXPECT_FALSE(has_note(s, "light 'conenode' (spot): attenuation"));
    EXPECT_TRUE(has_note(s, "lit.dae: left out: light 'skynode' (ambient)"));
    EXPECT_TRUE(has_note(s, "lit.dae: light strengths (colour x intensity) taken as they are"));
}

// An import object's transform moves the file's lights (positions, directions) as it moves its
// geometry and cameras; names are prefixed with the object's and stay unique.
TEST(SceneImport, JsonImportObjectMovesAndNamesTheLights) {
    TempDir dir("json_lights");
    dir.write("lit.gltf", lights_gltf());
    const Scene s = load_scene(dir.write("s.json", R"({
        "materials": {},
        "objects": [{"type": "import", "file": "lit.gltf", "name": "set",
                     "rotate_y_deg": 90, "translate": [10, 0, 0]}],
        "lights": [{"name": "set/bulb", "type": "point", "position": [0, 5, 0],
                    "intensity": [1, 1, 1]}]})"));
    ASSERT_EQ(s.lights.size(), 4u);
    EXPECT_EQ(s.lights[0].name, "set/bulb");  // the scene's own, first
    // Rotating (x, y, z) by 90 degrees about y gives (z, y, -x).
    const Light& bulb = light_named(s, "set/bulb#2");
    EXPECT_NEAR(glm::length(bulb.position - Vec3(10 - 0.5, 2, -1.25)), 0.0, 1e-6);
    const Light& cone = light_named(s, "set/cone");
    EXPECT_NEAR(glm::length(cone.position - Vec3(10, 3, 0)), 0.0, 1e-6);
    EXPECT_NEAR(glm::length(cone.direction - Vec3(0, -1, 0)), 0.0, 1e-6);
    const Light& sun = light_named(s, "set/sun");
    EXPECT_NEAR(glm::length(sun.direction - Vec3(-1, -1, 0) / std::sqrt(2.0)), 0.0, 1e-6);
    EXPECT_NEAR(glm::length(sun.position), 0.0, 1e-12);  // not moved: it has none
}

// ---- JSON "import" objects: transform, overrides ----------------------------------------

TEST(SceneImport, JsonImportObjectWithTransformAndOverrides) {
    TempDir dir("json");
    dir.write("quads.gltf", quad_gltf());
    const std::string scene = dir.write("s.json", R"({
        "materials": {"grey": {"diffuse": [0.3, 0.3, 0.3]}},
        "objects": [{"type": "import", "file": "quads.gltf", "name": "set",
                     "translate": [10, 0, 0], "materials": {"paint": "grey"}}]})");
    const Scene s = load_scene(scene);
    const SceneObject& floor = object_named(s, "set/paint");
    const Face& f = s.faces[size_t(floor.first_face)];
    EXPECT_EQ(s.materials[size_t(f.material)].name, "grey");
    EXPECT_NEAR(s.normalisation.to_user(polygon_centroid(f.vertices)).x, 10.0, 1.0);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].name, "set/view");
    EXPECT_NEAR(s.cameras[0].eye.x, 10.0, 1e-9);

    const std::string bad = dir.write("b.json", R"({
        "materials": {"grey": {"diffuse": [0.3, 0.3, 0.3]}},
        "objects": [{"type": "import", "file": "quads.gltf", "materials": {"pain": "grey"}}]})");
    try {
        load_scene(bad);
        FAIL() << "expected an error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(bad + ": objects[0].materials: no material 'pain' in "
                                                   "'quads.gltf'"),
                  std::string::npos)
            << e.what();
    }
}

// ---- bad files: one clear line naming the file and the place ----------------------------

void expect_load_error(const std::string& path, const std::string& expected) {
    try {
        load_scene(path);
        ADD_FAILURE() << "no error, expected: " << expected;
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
            << "message: " << e.what() << "\nexpected to contain: " << expected;
    }
}

TEST(SceneImport, ObjVertexThatIsNotFiniteNamesItsLine) {
    TempDir dir("nan");
    const std::string lamp = "v 0 1 0\nv 0 1 1\nv 1 1 1\nf 1 2 3\n";
    for (const char* bad : {"nan", "inf", "1e39", "-1e400"}) {
        const std::string obj = dir.write(
            "m.obj", "v 0 0 0\nv 1 0 0\nv " + std::string(bad) + " 1 0\nv 0 1 0\nf 1 2 4\n");
        expect_load_error(
            obj, obj + ":3: vertex coordinate '" + std::string(bad) + "' is not a finite number");
        const std::string json =
            dir.write("s.json", R"({"materials": {"l": {"emission": [1, 1, 1]}}, "objects": [
                {"type": "mesh", "file": "m.obj", "material": "l"}]})");
        expect_load_error(json, json + ": objects[0].file: " + obj + ":3: vertex coordinate");
    }
}

TEST(SceneImport, ObjFaceWithTooFewOrRepeatedVerticesIsAnErrorForMeshes) {
    TempDir dir("faces");
    const std::string json =
        dir.write("s.json", R"({"materials": {"l": {"emission": [1, 1, 1]}}, "objects": [
            {"type": "mesh", "file": "m.obj", "material": "l"}]})");
    const std::string two =
        dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4\n");
    expect_load_error(json, two + ":6: face has 2 vertex index(es)");
    const std::string rep =
        dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 -3\nf 1 2 3\n");
    expect_load_error(json, rep + ":5: face repeats a vertex index");
}

TEST(SceneImport, MissingDirectoryAndUnknownFormat) {
    TempDir dir("missing");
    expect_load_error((dir.path / "none.glb").string(), "does not exist");
    std::filesystem::create_directories(dir.path / "folder.obj");
    expect_load_error((dir.path / "folder.obj").string(), "is a directory, not a file");
    const std::string json =
        dir.write("s.json", R"({"materials": {"l": {"emission": [1, 1, 1]}}, "objects": [
            {"type": "import", "file": "x.notaformat"}]})");
    expect_load_error(json, json + ": objects[0].file: 'x.notaformat': no importer reads");
}

TEST(SceneImport, MalformedFilesAndKeysAreNamed) {
    TempDir dir("malformed");
    // A glTF extension value that is not a number.
    std::string g = quad_gltf();
    const std::string strength = "\"emissiveStrength\": 4";
    g.replace(g.find(strength), strength.size(), "\"emissiveStrength\": \"x\"");
    expect_load_error(dir.write("q.gltf", g),
                      "materials[1].extensions.KHR_materials_emissive_strength.emissiveStrength: "
                      "expected a number >= 0");
    // An OBJ face naming a vertex that does not exist (import and mesh objects alike).
    dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    expect_load_error(dir.write("a.json", R"({"materials": {"l": {"emission": [1, 1, 1]}},
        "objects": [{"type": "mesh", "file": "m.obj", "material": "l"}]})"),
                      "m.obj:4: face vertex '7' is not one of the 3 vertices so far");
    // An imported OFF whose body is shorter than its header.
    dir.write("s.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n");
    expect_load_error(dir.write("b.json", R"({"materials": {"l": {"emission": [1, 1, 1]}},
        "objects": [{"type": "import", "file": "s.off", "material": "l"}]})"),
                      "OFF header says 3 faces, the file has 2");
    // "material" and "materials" together.
    dir.write("quads.gltf", quad_gltf());
    expect_load_error(dir.write("c.json", R"({"materials": {"l": {"emission": [1, 1, 1]}},
        "objects": [{"type": "import", "file": "quads.gltf", "material": "l",
                     "materials": {"paint": "l"}}]})"),
                      "objects[0].materials: cannot be combined with \"material\"");
    // A colour OFF (COFF) is OpenMesh's to read: not refused by the plain-OFF check.
    dir.write("c.off",
              "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n0 1 0 255 0 0 255\n3 0 1 2\n");
    EXPECT_NO_THROW(load_scene(dir.write("d.json", R"({"materials": {"l": {"emission": [1, 1, 1]}},
        "objects": [{"type": "mesh", "file": "c.off", "material": "l"}]})")));
}

// A file's light beyond the loader's bound names the file and the light.
TEST(SceneImport, LightStrengthOutOfRangeIsNamed) {
    TempDir dir("light_range");
    nlohmann::json g = nlohmann::json::parse(lights_gltf());
    g["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = 1e21;
    const std::string file = dir.write("hot.gltf", g.dump());
    expect_load_error(file, file +
                                ": light 'bulb' (point): strength [1e+21, 5e+20, 2.5e+20] is "
                                "out of range (at most 1e20)");
}

TEST(SceneImport, MeshFilesThatReadersWouldPadOrEmptyAreNamed) {
    TempDir dir("meshfiles");
    const std::string json_head = R"({"materials": {"l": {"emission": [1, 1, 1]}}, "objects": [
            {"type": "mesh", "material": "l", "file": ")";
    // An OFF header that promises more faces than follow (OpenMesh pads with copies).
    dir.write("short.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n");
    expect_load_error(dir.write("a.json", json_head + R"(short.off"}]})"),
                      "OFF header says 3 faces, the file has 2");
    // A binary STL whose count does not match its size.
    std::string stl(80, '\0');
    const uint32_t count = 3;
    stl.append(reinterpret_cast<const char*>(&count), 4);
    const float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    stl.append(reinterpret_cast<const char*>(tri), sizeof tri);
    stl.append(2, '\0');
    dir.write("bad.stl", stl);
    expect_load_error(dir.write("b.json", json_head + R"(bad.stl"}]})"),
                      "binary STL says 3 triangles, its 134 bytes hold 1");
    // PLY triangle strips (OpenMesh skips them and finds no faces).
    dir.write("strip.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    expect_load_error(dir.write("c.json", json_head + R"(strip.ply"}]})"),
                      "PLY triangle strips ('element tristrips') are not read");
}

// ---- winding: faces turned to agree, closed parts to face outward (winding.hpp) ----------

const std::string kWinding = std::string(VLF_SOURCE_DIR) + "/tests/scenes";

// The notes about turned faces (the loader's, for the file's material 'glow').
std::vector<std::string> winding_notes(const Scene& s) {
    std::vector<std::string> out;
    for (const std::string& n : s.load_notes)
        if (n.find("turned") != std::string::npos || n.find("one way") != std::string::npos)
            out.push_back(n);
    return out;
}

// Every face's normal points away from the centre of the unit cube [1,2] x [2,3] x [3,4].
void expect_outward(const Scene& s) {
    const Vec3 centre = s.normalisation.to_normalised({1.5, 2.5, 3.5});
    ASSERT_EQ(s.faces.size(), 12u);
    for (const Face& f : s.faces)
        EXPECT_GT(glm::dot(f.normal, polygon_centroid(f.vertices) - centre), 0) << "face " << f.id;
}

TEST(SceneImportWinding, ClosedCubeWithSomeFacesReversedFacesOutward) {
    const Scene s = load_scene(kWinding + "/winding-mixed-cube.obj");
    const std::string file = "winding-mixed-cube.obj";  // the note names it as the scene does
    expect_outward(s);
    const auto notes = winding_notes(s);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0],
              file + ": material 'glow': 4 of 12 face(s) turned to agree with their neighbours");
}

TEST(SceneImportWinding, InwardClosedCubeIsTurnedOutward) {
    const Scene s = load_scene(kWinding + "/winding-inward-cube.obj");
    const std::string file = "winding-inward-cube.obj";  // the note names it as the scene does
    expect_outward(s);
    const auto notes = winding_notes(s);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0], file +
                            ": material 'glow': 1 closed part(s) turned to face outward (12 of 12 "
                            "face(s) turned)");
}

// The same file placed in a JSON scene whose camera looks from inside it (moved and scaled
// with the import object): a room seen from inside, it keeps facing inward.
TEST(SceneImportWinding, SceneCameraInsideKeepsARoomInward) {
    const Scene s = load_scene_from_string(
        R"({"materials": {}, "objects": [{"type": "import", "name": "room",
              "file": "winding-inward-cube.obj", "scale": 2, "translate": [10, 0, 0]}],
            "cameras": [{"eye": [13, 5, 7], "look_at": [13, 5, 8], "fov_y_deg": 40}]})",
        "room.json", kWinding);
    const Vec3 centre = s.normalisation.to_normalised({13.0, 5.0, 7.0});
    for (const Face& f : s.faces) EXPECT_GT(glm::dot(f.normal, centre - f.vertices[0]), 0);
    EXPECT_TRUE(winding_notes(s).empty());
}

TEST(SceneImportWinding, OpenGridAgreesWithItsMajority) {
    // The first triangle (the walk's seed) is the reversed one: the area decides, not the seed.
    const Scene s = load_scene(kWinding + "/winding-grid.obj");
    const std::string file = "winding-grid.obj";  // the note names it as the scene does
    ASSERT_EQ(s.faces.size(), 8u);
    for (const Face& f : s.faces) EXPECT_GT(f.normal.y, 0.999) << "face " << f.id;
    const auto notes = winding_notes(s);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0],
              file + ": material 'glow': 1 of 8 face(s) turned to agree with their neighbours");
}

TEST(SceneImportWinding, ConsistentCubeIsUnchangedAndUnnoted) {
    const std::string file = kWinding + "/winding-cube.obj";
    // The file's triangles, corner by corner (its vertex numbers, 1-based).
    const int tris[12][3] = {{1, 4, 3}, {1, 3, 2}, {5, 6, 7}, {5, 7, 8}, {1, 2, 6}, {1, 6, 5},
                             {4, 8, 7}, {4, 7, 3}, {1, 5, 8}, {1, 8, 4}, {2, 3, 7}, {2, 7, 6}};
    const Vec3 v[8] = {{1, 2, 3}, {2, 2, 3}, {2, 3, 3}, {1, 3, 3},
                       {1, 2, 4}, {2, 2, 4}, {2, 3, 4}, {1, 3, 4}};
    const ImportedScene imported = import_scene_file(file);
    ASSERT_EQ(imported.groups.size(), 1u);
    const ImportedMesh& mesh = imported.groups[0].mesh;
    ASSERT_EQ(mesh.faces.size(), 12u);
    for (size_t f = 0; f < 12; ++f) {
        ASSERT_EQ(mesh.faces[f].size(), 3u);
        for (size_t k = 0; k < 3; ++k)
            EXPECT_EQ(mesh.vertices[size_t(mesh.faces[f][k])], v[tris[f][k] - 1])
                << "face " << f << " corner " << k;
    }
    EXPECT_TRUE(imported.notes.empty());
    const Scene s = load_scene(file);
    expect_outward(s);
    EXPECT_TRUE(winding_notes(s).empty());
}

// The unit cube as an ImportedMesh of 6 quads, outward or inward, its quads split apart
// (their own vertices: parts are found by welding positions).
ImportedMesh quad_cube(bool inward) {
    const Vec3 corner[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    ImportedMesh m;
    for (const auto& q : quads) {
        std::vector<int> face;
        for (int c : q) {
            face.push_back(int(m.vertices.size()));
            m.vertices.push_back(corner[c]);
        }
        if (inward) std::reverse(face.begin(), face.end());
        m.faces.push_back(face);
    }
    return m;
}

double signed_volume(const ImportedMesh& m) {
    double v = 0.0;
    for (const auto& f : m.faces)
        for (size_t k = 1; k + 1 < f.size(); ++k)
            v += glm::dot(m.vertices[size_t(f[0])],
                          glm::cross(m.vertices[size_t(f[k])], m.vertices[size_t(f[k + 1])])) /
                 6.0;
    return v;
}

TEST(SceneImportWinding, ClosedPartAroundAViewpointFacesInward) {
    // A room seen from inside (a camera or light of the file in it) keeps facing inward.
    ImportedMesh room = quad_cube(true);
    const auto before = room.faces;
    std::vector<ImportedMesh*> meshes = {&room};
    auto c = orient_faces(meshes, {Vec3(0.5, 0.5, 0.5)});
    EXPECT_EQ(room.faces, before);
    EXPECT_FALSE(c[0].changed());
    // Wound outward around the viewpoint: turned inward, counted as a whole part.
    ImportedMesh box = quad_cube(false);
    meshes = {&box};
    c = orient_faces(meshes, {Vec3(0.5, 0.5, 0.5), Vec3(5, 5, 5)});
    EXPECT_NEAR(signed_volume(box), -1.0, 1e-12);
    EXPECT_EQ(c[0].inward_parts, 1u);
    EXPECT_EQ(c[0].inward_faces, 6u);
    EXPECT_EQ(c[0].agreed, 0u);
    // A viewpoint outside changes nothing: outward stays outward.
    box = quad_cube(false);
    c = orient_faces(meshes, {Vec3(5, 0.5, 0.5)});
    EXPECT_NEAR(signed_volume(box), 1.0, 1e-12);
    EXPECT_FALSE(c[0].changed());
}

TEST(SceneImportWinding, PartsSpanMeshesAndPerVertexUvsFollow) {
    // The inward cube split over two meshes (materials): one closed part, turned in both.
    ImportedMesh a = quad_cube(true), b;
    for (size_t f = 3; f < 6; ++f) {
        std::vector<int> face;
        for (int v : a.faces[f]) {
            face.push_back(int(b.vertices.size()));
            b.vertices.push_back(a.vertices[size_t(v)]);
        }
        b.faces.push_back(face);
    }
    a.faces.resize(3);
    a.uvs.resize(a.vertices.size());
    for (size_t v = 0; v < a.uvs.size(); ++v) a.uvs[v] = Vec2(double(v), 0.0);
    const auto uvs = a.uvs;
    std::vector<ImportedMesh*> meshes = {&a, &b};
    const auto c = orient_faces(meshes, {});
    EXPECT_NEAR(signed_volume(a) + signed_volume(b), 1.0, 1e-12);
    for (const auto* m : {&c[0], &c[1]}) {
        EXPECT_EQ(m->outward_parts, 1u);
        EXPECT_EQ(m->outward_faces, 3u);
    }
    // Texture coordinates are per vertex: a turned face's corners keep theirs.
    EXPECT_EQ(a.uvs, uvs);
    EXPECT_EQ(a.faces[0], (std::vector<int>{0, 1, 2, 3}));  // quad_cube(false)'s first face
}

TEST(SceneImportWinding, MoebiusStripKeepsOneAssignmentAndIsNoted) {
    // 8 quads around a circle of radius 2, the strip's width turning by half a turn: no
    // winding agrees throughout; one edge is left with disagreeing faces.
    const int n = 8;
    ImportedMesh m;
    for (int k = 0; k < n; ++k) {
        const double t = 2.0 * kPi * k / n;
        const Vec3 centre(2.0 * std::cos(t), 2.0 * std::sin(t), 0.0);
        const Vec3 width = 0.5 * (std::cos(t / 2) * Vec3(std::cos(t), std::sin(t), 0.0) +
                                  std::sin(t / 2) * Vec3(0, 0, 1));
        m.vertices.push_back(centre + width);  // 2k: top
        m.vertices.push_back(centre - width);  // 2k + 1: bottom
    }
    for (int k = 0; k + 1 < n; ++k) m.faces.push_back({2 * k, 2 * k + 1, 2 * k + 3, 2 * k + 2});
    m.faces.push_back({2 * (n - 1), 2 * (n - 1) + 1, 0, 1});  // top meets bottom: the twist
    std::vector<ImportedMesh*> meshes = {&m};
    const auto c = orient_faces(meshes, {});
    EXPECT_EQ(c[0].non_orientable, 1u);
    EXPECT_EQ(c[0].disagreeing_edges, 1u);
    EXPECT_TRUE(c[0].changed());
}

}  // namespace
}  // namespace vlf
