// scene_loader_test.cpp — JSON scenes to vlf::Scene (vlf/scene/scene_loader.hpp): the shipped
// scenes, normalisation, texel frames, mesh import, transforms and every class of bad input.
#include "vlf/scene/scene_loader.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <tuple>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/scene/light.hpp"
#include "vlf/scene/primitives.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/scene/texel_frame.hpp"

namespace vlf {
namespace {

const std::string kSource = VLF_SOURCE_DIR;
const std::string kScenes = kSource + "/scenes";

Scene load_cornell(const LoadOptions& o = {}) {
    return load_scene(kScenes + "/cornell.json", o);
}
Scene load_closed_box() {
    return load_scene(kScenes + "/closed-box.json");
}

using test::vertex_key;

// Every directed edge of the given faces has exactly one reversed partner among them.
bool closed_and_consistent(const Scene& s, int first, int count) {
    std::map<std::pair<test::VertexKey, test::VertexKey>, int> edges;
    for (int f = first; f < first + count; ++f) {
        const auto& v = s.faces[f].vertices;
        for (size_t i = 0; i < v.size(); ++i)
            ++edges[{vertex_key(v[i]), vertex_key(v[(i + 1) % v.size()])}];
    }
    for (const auto& [e, n] : edges) {
        if (n != 1) return false;
        auto it = edges.find({e.second, e.first});
        if (it == edges.end() || it->second != 1) return false;
    }
    return true;
}

double signed_volume(const Scene& s, int first, int count) {
    double v = 0;
    for (int f = first; f < first + count; ++f)
        v += s.faces[f].area * glm::dot(s.faces[f].normal, polygon_centroid(s.faces[f].vertices)) /
             3.0;
    return v;
}

using test::object_named;

double user_area(const Scene& s, const Face& f) {
    return f.area / (s.normalisation.scale * s.normalisation.scale);
}

// ---- the shipped scenes -----------------------------------------------------------------

TEST(SceneCornell, LoadsWithTheExpectedFaces) {
    const Scene s = load_cornell();
    EXPECT_EQ(s.objects.size(), 18u);
    EXPECT_EQ(s.faces.size(), 19u);  // left wall triangulated into 2
    EXPECT_EQ(object_named(s, "left wall").face_count, 2);
    EXPECT_EQ(s.emitter_count(), 1);
    EXPECT_EQ(s.specular_face_count(), 0);
    EXPECT_EQ(s.materials.size(), 4u);
    EXPECT_EQ(s.materials[0].name, "white");  // file order is kept
    EXPECT_EQ(s.units, "mm");
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].name, "default");
    EXPECT_EQ(s.cameras[0].eye, Vec3(278, 273, -800));  // user units
    EXPECT_DOUBLE_EQ(s.cameras[0].fov_y_deg, 39.3);
    for (size_t i = 0; i < s.faces.size(); ++i) {
        const Face& f = s.faces[i];
        EXPECT_EQ(f.id, static_cast<int>(i));
        EXPECT_EQ(s.objects[f.object].first_face <= f.id &&
                      f.id < s.objects[f.object].first_face + s.objects[f.object].face_count,
                  true);
    }
}

TEST(SceneCornell, FacesArePlanarConvexAndInsideTheUnitBall) {
    const Scene s = load_cornell();
    double max_radius = 0;
    for (const Face& f : s.faces) {
        EXPECT_LT(max_plane_deviation(f.vertices), 1e-12) << s.objects[f.object].name;
        EXPECT_FALSE(polygon_problem(f.vertices, 1e-12, 1e-9).has_value())
            << s.objects[f.object].name;
        EXPECT_NEAR(glm::length(f.normal), 1.0, 1e-14);
        EXPECT_NEAR(f.area, polygon_area(f.vertices), 1e-15);
        for (const Vec3& v : f.vertices) {
            EXPECT_NEAR(glm::dot(f.normal, v), f.plane_offset, 1e-12);
            max_radius = std::max(max_radius, glm::length(v));
        }
    }
    EXPECT_LT(max_radius, 1.0);
    EXPECT_NEAR(max_radius, 0.999, 1e-9);  // bounding-box corners are vertices of the room
}

TEST(SceneCornell, RoomWallsFaceInwardAndBlocksAreClosedSolids) {
    const Scene s = load_cornell();
    const Vec3 room_center =
        s.normalisation.to_normalised(0.5 * (s.user_bounds_min + s.user_bounds_max));
    for (const char* wall : {"floor", "ceiling", "back wall", "right wall", "left wall"}) {
        const SceneObject& o = object_named(s, wall);
        for (int k = o.first_face; k < o.first_face + o.face_count; ++k) {
            const Face& f = s.faces[k];
            EXPECT_GT(glm::dot(f.normal, room_center - polygon_centroid(f.vertices)), 0) << wall;
        }
    }
    EXPECT_LT(s.faces[object_named(s, "light").first_face].normal.y, -0.999999);  // faces down
    EXPECT_NEAR(s.faces[object_named(s, "floor").first_face].normal.y, 1.0, 1e-12);
    for (const char* block : {"short block top", "tall block top"}) {
        const int first = object_named(s, block).first_face;
        EXPECT_TRUE(closed_and_consistent(s, first, 6)) << block;
        EXPECT_GT(signed_volume(s, first, 6), 0) << block << " faces point inward";
    }
}

TEST(SceneCornell, AreasAndNormalisationInUserUnits) {
    const Scene s = load_cornell();
    const Face& floor = s.faces[object_named(s, "floor").first_face];
    EXPECT_NEAR(user_area(s, floor), 552.8 * 559.2, 0.01 * 552.8 * 559.2);
    EXPECT_NEAR(user_area(s, floor), 0.5 * (552.8 + 549.6) * 559.2, 1e-6);  // the exact trapezoid
    EXPECT_NEAR(user_area(s, s.faces[object_named(s, "light").first_face]), 130.0 * 105.0, 1e-7);
    EXPECT_NEAR(user_area(s, s.faces[object_named(s, "ceiling").first_face]), 556.0 * 559.2, 1e-6);
    EXPECT_EQ(s.user_bounds_min, Vec3(0, 0, 0));
    EXPECT_EQ(s.user_bounds_max, Vec3(556.0, 548.8, 559.2));
    EXPECT_NEAR(s.normalisation.center.x, 278.0, 1e-12);
    EXPECT_NEAR(s.normalisation.center.y, 274.4, 1e-12);
    EXPECT_NEAR(s.normalisation.center.z, 279.6, 1e-12);
    const double half_diagonal = 0.5 * std::sqrt(556.0 * 556.0 + 548.8 * 548.8 + 559.2 * 559.2);
    EXPECT_NEAR(s.normalisation.scale, 0.999 / half_diagonal, 1e-15);
    EXPECT_NEAR(s.texel_size_user, half_diagonal / 32, 1e-12);  // the default
}

TEST(SceneNormalisation, RoundTrips) {
    const Scene s = load_cornell();
    for (const Vec3& p :
         {Vec3(0, 0, 0), Vec3(556, 548.8, 559.2), Vec3(278, 273, -800), Vec3(-1e4, 3.25, 77.7)}) {
        const Vec3 q = s.normalisation.to_user(s.normalisation.to_normalised(p));
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(q[a], p[a], 1e-12 * (1 + std::abs(p[a])));
    }
    // And the faces really are the user geometry, normalised.
    const Face& light = s.faces[object_named(s, "light").first_face];
    const Vec3 first = s.normalisation.to_user(light.vertices[0]);
    EXPECT_NEAR(first.x, 343.0, 1e-10);
    EXPECT_NEAR(first.y, 548.7, 1e-10);
    EXPECT_NEAR(first.z, 227.0, 1e-10);
}

void expect_texels_cover_faces(const Scene& s, double texel_size_normalised, int cap) {
    size_t in_charts = 0;
    for (const Chart& c : s.charts) {
        const TexelFrame& t = c.texels;
        ASSERT_EQ(c.texel_area.size(), static_cast<size_t>(t.count()));
        EXPECT_GE(t.width, 1);
        EXPECT_GE(t.height, 1);
        EXPECT_LE(t.width, cap);
        EXPECT_LE(t.height, cap);
        EXPECT_GE(t.size, texel_size_normalised * (1 - 1e-12));
        EXPECT_NEAR(glm::dot(t.axis_u, t.axis_v), 0, 1e-14);
        EXPECT_NEAR(glm::length(glm::cross(t.axis_u, t.axis_v) - c.normal), 0, 1e-14);
        double sum = 0, max_scale = 1.0, area = 0.0;
        for (int fi : c.faces) {
            EXPECT_EQ(s.faces[fi].chart, c.id);
            max_scale = std::max(max_scale, projected_area_scale(c, s.faces[fi]));
            area += s.faces[fi].area;
        }
        in_charts += c.faces.size();
        EXPECT_NEAR(area, c.area, 1e-12 * area);
        for (double a : c.texel_area) {
            EXPECT_GE(a, 0);
            EXPECT_LE(a, t.size * t.size * max_scale * (1 + 1e-12));
            sum += a;
        }
        // The texels cover the chart's faces, less what a face right in front of one seals
        // (sealed_areas.hpp; exact figures in tests/sealed_areas_test.cpp).
        bool behind_another = false;
        for (int fi : c.faces)
            for (const Face& g : s.faces) {
                const Face& f = s.faces[fi];
                const double d = g.plane_offset - f.plane_offset;
                behind_another = behind_another || (glm::dot(g.normal, f.normal) > 1 - 1e-6 &&
                                                    d > 0 && d <= s.seal_gap);
            }
        if (behind_another)
            EXPECT_LE(sum, c.area * (1 + 1e-9)) << "chart " << c.id;
        else
            EXPECT_NEAR(sum, c.area, 1e-9 * c.area) << "chart " << c.id;
        for (int fi : c.faces)
            for (const Vec3& v : s.faces[fi].vertices) {
                const Vec2 x = t.to_texel(v);
                EXPECT_GE(x.x, -1e-9);
                EXPECT_GE(x.y, -1e-9);
                EXPECT_LE(x.x, t.width + 1e-9);
                EXPECT_LE(x.y, t.height + 1e-9);
                if (c.planar) {
                    EXPECT_NEAR(glm::length(t.to_plane(x) - v), 0, 1e-12);
                }
            }
    }
    EXPECT_EQ(in_charts, s.faces.size());
}

TEST(SceneTexels, AreasSumToTheFaceArea) {
    const Scene s = load_cornell();
    expect_texels_cover_faces(s, s.texel_size_user * s.normalisation.scale, 512);
    const Face& floor = s.faces[object_named(s, "floor").first_face];
    EXPECT_GT(s.chart_of(floor).texels.width, 30);  // ~552.8 mm / 15 mm
    // A finer grid and a cap that forces some faces to coarser texels.
    LoadOptions o;
    o.texel_size_user = 3.0;
    o.max_texels_per_side = 64;
    const Scene fine = load_cornell(o);
    EXPECT_DOUBLE_EQ(fine.texel_size_user, 3.0);
    expect_texels_cover_faces(fine, 3.0 * fine.normalisation.scale, 64);
    const Face& ffloor = fine.faces[object_named(fine, "floor").first_face];
    const TexelFrame& fgrid = fine.chart_of(ffloor).texels;
    EXPECT_EQ(std::max(fgrid.width, fgrid.height), 64);
    EXPECT_GT(fgrid.size, 3.0 * fine.normalisation.scale);
}

TEST(SceneClosedBox, LoadsClosedAndFacingInward) {
    const Scene s = load_closed_box();
    EXPECT_EQ(s.faces.size(), 18u);
    EXPECT_EQ(s.emitter_count(), 1);
    const SceneObject& room = object_named(s, "room");
    ASSERT_EQ(room.face_count, 6);
    const Vec3 center = s.normalisation.to_normalised(Vec3(0, 1, 0));
    for (int k = room.first_face; k < room.first_face + 6; ++k) {
        const Face& f = s.faces[k];
        EXPECT_GT(glm::dot(f.normal, center - polygon_centroid(f.vertices)), 0);
    }
    EXPECT_LT(signed_volume(s, room.first_face, 6), 0);  // seen from inside
    // The whole scene is closed: every edge is shared by two faces running it both ways.
    EXPECT_TRUE(closed_and_consistent(s, 0, static_cast<int>(s.faces.size())));
    const SceneObject& block = object_named(s, "block");
    EXPECT_GT(signed_volume(s, block.first_face, block.face_count), 0);
    ASSERT_EQ(s.cameras.size(), 1u);
    const Vec3 eye = s.cameras[0].eye;
    EXPECT_TRUE(eye.x > -1 && eye.x < 1 && eye.y > 0 && eye.y < 2 && eye.z > -1 && eye.z < 1);
    expect_texels_cover_faces(s, s.texel_size_user * s.normalisation.scale, 512);
}

// ---- building blocks through the loader ---------------------------------------------------

const std::string kLamp = R"({"type": "polygon", "material": "lamp",
  "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]})";
const std::string kMaterials = R"({"white": {"diffuse": [0.5, 0.5, 0.5]},
  "lamp": {"diffuse": [0.5, 0.5, 0.5], "emission": [1, 1, 1]}})";

Scene load_objects(const std::string& objects, const std::string& extra = "",
                   const LoadOptions& o = {}) {
    const std::string text =
        R"({"materials": )" + kMaterials + R"(, "objects": [)" + objects + "]" + extra + "}";
    return load_scene_from_string(text, "test.json", kScenes, o);
}

TEST(SceneTransform, OrderAndPivot) {
    // Scale 2 about the box centre, rotate 90 deg about y, translate: a 2x4x6 box centred at
    // (10, 1.5, 2.5) -> x/z swapped extents.
    const Scene s =
        load_objects(R"({"type": "box", "min": [0,1,2], "max": [1,2,3], "scale": [2, 4, 6],
        "rotate_y_deg": 90, "translate": [10, 0, 0], "material": "lamp"})");
    EXPECT_NEAR(s.user_bounds_min.x, 10.5 - 3, 1e-12);
    EXPECT_NEAR(s.user_bounds_max.x, 10.5 + 3, 1e-12);
    EXPECT_NEAR(s.user_bounds_min.y, 1.5 - 2, 1e-12);
    EXPECT_NEAR(s.user_bounds_max.y, 1.5 + 2, 1e-12);
    EXPECT_NEAR(s.user_bounds_min.z, 2.5 - 1, 1e-12);
    EXPECT_NEAR(s.user_bounds_max.z, 2.5 + 1, 1e-12);
    EXPECT_EQ(s.faces.size(), 6u);
    EXPECT_GT(signed_volume(s, 0, 6), 0);  // rotation keeps the faces outward
    // Rotations compose x, then y, then z: (1,0,0) -> rot_z(90) -> (0,1,0).
    const Scene r = load_objects(
        R"({"type": "polygon", "material": "lamp", "rotate_x_deg": 90, "rotate_z_deg": 90,
        "vertices": [[0,0,0],[1,0,0],[0,1,0]]})");
    const Vec3 a = r.normalisation.to_user(r.faces[0].vertices[1]);
    EXPECT_NEAR(a.x, 0, 1e-12);
    EXPECT_NEAR(a.y, 1, 1e-12);
    EXPECT_NEAR(a.z, 0, 1e-12);
    // (0,1,0) -> rot_x(90) -> (0,0,1) -> rot_z -> (0,0,1).
    const Vec3 b = r.normalisation.to_user(r.faces[0].vertices[2]);
    EXPECT_NEAR(b.z, 1, 1e-12);
}

TEST(SceneObjects, SphereCylinderFlipTwoSidedAndTriangulate) {
    const Scene s = load_objects(kLamp + R"(,
        {"type": "sphere", "center": [5,5,5], "radius": 2, "subdivisions": 1, "scale": [1, 0.5, 2], "material": "white"},
        {"type": "cylinder", "radius": 1, "inner_radius": 0.5, "height": 2, "segments": 8, "material": "white", "flip": true},
        {"type": "polygon", "material": "white", "two_sided": true, "vertices": [[0,0,2],[1,0,2],[0,1,2]]},
        {"type": "polygon", "material": "white", "triangulate": true,
         "vertices": [[0,0,3],[2,0,3],[2,1,3],[1,1,3],[1,2,3],[0,2,3]]})");
    ASSERT_EQ(s.objects.size(), 5u);
    EXPECT_EQ(s.objects[1].face_count, 80);
    EXPECT_EQ(s.objects[1].name, "sphere#1");
    EXPECT_EQ(s.objects[1].type, "sphere");
    EXPECT_GT(signed_volume(s, s.objects[1].first_face, 80),
              0);  // non-uniform scale: still outward
    EXPECT_EQ(s.objects[2].face_count, 32);
    EXPECT_LT(signed_volume(s, s.objects[2].first_face, 32), 0);  // flipped
    ASSERT_EQ(s.objects[3].face_count, 2);
    const Face& front = s.faces[s.objects[3].first_face];
    const Face& back = s.faces[s.objects[3].first_face + 1];
    EXPECT_NEAR(glm::length(front.normal + back.normal), 0, 1e-14);
    EXPECT_EQ(s.objects[4].face_count, 4);
    for (const Face& f : s.faces) EXPECT_FALSE(polygon_problem(f.vertices, 1e-9, 1e-9).has_value());
}

TEST(SceneSettings, TexelSizeFromTheFileAndTheOptions) {
    const Scene s = load_objects(kLamp, R"(, "settings": {"texel_size": 0.25, "units": "m"})");
    EXPECT_DOUBLE_EQ(s.texel_size_user, 0.25);
    EXPECT_EQ(s.units, "m");
    EXPECT_EQ(s.charts[0].texels.width, 4);
    EXPECT_EQ(s.charts[0].texels.height, 4);
    for (double a : s.charts[0].texel_area) EXPECT_NEAR(a, s.faces[0].area / 16, 1e-12);
    LoadOptions o;
    o.texel_size_user = 0.5;
    EXPECT_DOUBLE_EQ(
        load_objects(kLamp, R"(, "settings": {"texel_size": 0.25})", o).texel_size_user, 0.5);
}

// ---- mesh import -----------------------------------------------------------------------------

double object_user_area(const Scene& s, int object) {
    double a = 0;
    const SceneObject& o = s.objects[object];
    for (int k = o.first_face; k < o.first_face + o.face_count; ++k) a += user_area(s, s.faces[k]);
    return a;
}

TEST(SceneMesh, ImportsObjOffPlyAndStl) {
    const Scene s = load_objects(R"(
        {"type": "mesh", "file": "meshes/tetrahedron.obj", "material": "lamp"},
        {"type": "mesh", "file": "meshes/cube.off", "material": "white", "translate": [3, 0, 0]},
        {"type": "mesh", "file": "meshes/pyramid.ply", "material": "white", "translate": [6, 0, 0]},
        {"type": "mesh", "file": "meshes/tetrahedron.stl", "material": "white", "translate": [9, 0, 0]})");
    ASSERT_EQ(s.objects.size(), 4u);
    EXPECT_EQ(s.objects[3].face_count, 4);
    EXPECT_NEAR(object_user_area(s, 3), 1.5 + std::sqrt(3.0) / 2, 1e-6);
    EXPECT_EQ(s.objects[0].face_count, 4);
    EXPECT_EQ(s.objects[1].face_count, 6);
    EXPECT_EQ(s.objects[2].face_count, 5);
    for (int k = 0; k < s.objects[1].face_count; ++k)
        EXPECT_EQ(s.faces[s.objects[1].first_face + k].vertices.size(), 4u);
    EXPECT_NEAR(object_user_area(s, 0), 1.5 + std::sqrt(3.0) / 2, 1e-9);
    EXPECT_NEAR(object_user_area(s, 1), 6.0, 1e-9);
    EXPECT_NEAR(object_user_area(s, 2), 1.0 + 2 * std::sqrt(1.25), 1e-6);
    for (int o = 0; o < 4; ++o) {
        EXPECT_TRUE(closed_and_consistent(s, s.objects[o].first_face, s.objects[o].face_count))
            << o;
        EXPECT_GT(signed_volume(s, s.objects[o].first_face, s.objects[o].face_count), 0) << o;
    }
}

using test::TempDir;

TEST(SceneMesh, NonPlanarFaceIsAnErrorUnlessTriangulated) {
    TempDir dir("mesh");
    dir.write("bent.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.3\nv 0 1 0\nv 0 0 1\nf 5 1 2\nf 1 2 3 4\n");
    const std::string scene = dir.write(
        "s.json",
        R"({"materials": )" + kMaterials +
            R"(, "objects": [{"type": "mesh", "file": "bent.obj", "material": "lamp"}]})");
    try {
        load_scene(scene);
        FAIL() << "expected an error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(scene +
                                             ": objects[0] (mesh bent.obj): face 1 is not planar"),
                  std::string::npos)
            << e.what();
    }
    const std::string ok = dir.write(
        "t.json",
        R"({"materials": )" + kMaterials +
            R"(, "objects": [{"type": "mesh", "file": "bent.obj", "material": "lamp", "triangulate": true}]})");
    EXPECT_EQ(load_scene(ok).faces.size(), 3u);
    // A face OpenMesh drops (repeated vertex) is an error, not a silent hole.
    // (OpenMesh's OBJ reader removes repeated indices itself; its OFF reader does not.)
    dir.write("dropped.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n4 0 1 1 3\n");
    const std::string dropped = dir.write(
        "d.json",
        R"({"materials": )" + kMaterials +
            R"(, "objects": [{"type": "mesh", "file": "dropped.off", "material": "lamp"}]})");
    try {
        load_scene(dropped);
        FAIL() << "expected an error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(dropped + ": objects[0].file: mesh file"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("OpenMesh dropped a face"), std::string::npos)
            << e.what();
    }
}

// ---- bad input: one test per class ----------------------------------------------------------

// Loads `text` as "bad.json" and expects a SceneError whose message contains `expected`.
void expect_error(const std::string& text, const std::string& expected) {
    try {
        load_scene_from_string(text, "bad.json", kScenes);
        ADD_FAILURE() << "no error, expected: " << expected;
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
            << "message: " << e.what() << "\nexpected to contain: " << expected;
        EXPECT_EQ(std::string(e.what()).rfind("bad.json: ", 0), 0u) << e.what();
    }
}

std::string with_objects(const std::string& objects, const std::string& materials = kMaterials) {
    return R"({"materials": )" + materials + R"(, "objects": [)" + objects + "]}";
}

TEST(SceneBadInput, MalformedJsonNamesLineAndColumn) {
    expect_error("{\n  \"materials\": {},\n  \"objects\": [ }\n}",
                 "bad.json: line 3, column 16: malformed JSON");
    expect_error("", "bad.json: line 1, column 1: malformed JSON");
    expect_error(R"({"materials": {}, "materials": {}})", "bad.json: materials: duplicate key");
}

TEST(SceneBadInput, UnknownTopLevelKey) {
    expect_error(R"({"materials": {}, "objects": [], "colour": 1})",
                 "bad.json: colour: unknown key (expected one of: $schema, materials, objects, "
                 "cameras, lights, settings)");
}

// "$schema" (docs/scene.schema.json, for editors) is accepted and ignored; nothing else is.
TEST(SceneSchemaKey, IsAcceptedAndIgnored) {
    const std::string scene = R"({"$schema": "../docs/scene.schema.json", "materials": )" +
                              kMaterials + R"(, "objects": [)" + kLamp + "]}";
    EXPECT_EQ(load_scene_from_string(scene, "s.json", kScenes).faces.size(), 1u);
    expect_error(
        R"({"$schema": 2, "materials": )" + kMaterials + R"(, "objects": [)" + kLamp + "]}",
        "bad.json: [\"$schema\"]: expected a string, got 2");
    expect_error(with_objects(kLamp + R"(, {"$schema": "x", "type": "box", "min": [0,0,0],
                                            "max": [1,1,1], "material": "white"})"),
                 "bad.json: objects[1][\"$schema\"]: unknown key for a box");
}

TEST(SceneBadInput, UnknownObjectKey) {
    expect_error(
        with_objects(
            kLamp +
            R"(, {"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "white", "colour": 1})"),
        "bad.json: objects[1].colour: unknown key for a box");
    expect_error(
        with_objects(
            kLamp +
            R"(, {"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "white", "radius": 1})"),
        "bad.json: objects[1].radius: unknown key for a box");
    expect_error(with_objects(kLamp + R"(, {"type": "cone", "material": "white"})"),
                 "bad.json: objects[1].type: unknown type 'cone' (known: polygon, box, sphere, "
                 "cylinder, mesh, import)");
}

// Issue 14: glass is a closed solid whose faces turn outward, of an index in (1, 4], with
// nothing but its Fresnel reflection: anything else is one line naming the place.
TEST(SceneBadInput, DielectricObjectsAreClosedOutwardSolids) {
    const std::string glass = R"({"glass": {"dielectric": {"ior": 1.5}},
        "lamp": {"diffuse": [0.5, 0.5, 0.5], "emission": [1, 1, 1]}})";
    expect_error(with_objects(kLamp + R"(, {"type": "polygon", "name": "pane", "material":
                 "glass", "vertices": [[0,0,1],[1,0,1],[1,1,1],[0,1,1]]})",
                              glass),
                 "bad.json: objects[1] (pane): a dielectric object must be closed, its faces "
                 "turned outward: edge ");
    expect_error(with_objects(kLamp + R"(, {"type": "box", "name": "cube", "min": [0,0,1],
                 "max": [1,1,2], "flip": true, "material": "glass"})",
                              glass),
                 "bad.json: objects[1] (cube): a dielectric object must be closed, its faces "
                 "turned outward: its faces turn inward (they enclose a volume of -1");
    // The same box turned outward loads, with an inner twin for each of its 12 faces.
    const Scene s = load_scene_from_string(
        with_objects(kLamp + R"(, {"type": "box", "name": "cube", "min": [0,0,1],
                     "max": [1,1,2], "material": "glass"})",
                     glass),
        "good.json", kScenes);
    EXPECT_EQ(test::object_named(s, "cube").face_count, 12);
    expect_error(with_objects(kLamp, R"({"lamp": {"emission": [1,1,1]},
                 "glass": {"dielectric": {"ior": 0.9}}})"),
                 "bad.json: materials.glass.dielectric.ior: must be in (1, 4] (got 0.9)");
    expect_error(with_objects(kLamp, R"({"lamp": {"emission": [1,1,1]},
                 "glass": {"diffuse": [0.5, 0.5, 0.5], "dielectric": {"ior": 1.5}}})"),
                 "bad.json: materials.glass.diffuse: a dielectric material has no diffuse");
}

TEST(SceneBadInput, UnknownMaterialKey) {
    expect_error(with_objects(kLamp, R"({"lamp": {"emission": [1,1,1], "glossy": 0.5}})"),
                 "bad.json: materials.lamp.glossy: unknown key");
}

TEST(SceneBadInput, KeysThatAreNotPlainWordsAreQuotedInThePath) {
    expect_error(
        with_objects(kLamp, R"({"lamp": {"emission": [1,1,1]}, "my lamp.2": {"diffuse": 1}})"),
        "bad.json: materials[\"my lamp.2\"].diffuse: expected an array of 3 numbers, got 1");
}

TEST(SceneBadInput, UnknownMaterialName) {
    expect_error(
        with_objects(kLamp +
                     R"(, {"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "glas"})"),
        "bad.json: objects[1].material: unknown material 'glas' (known: white, lamp)");
}

TEST(SceneBadInput, MissingMeshFile) {
    expect_error(
        with_objects(kLamp +
                     R"(, {"type": "mesh", "file": "meshes/nope.obj", "material": "white"})"),
        "bad.json: objects[1].file: mesh file '" + kScenes + "/meshes/nope.obj' does not exist");
}

TEST(SceneBadInput, NonFiniteNumber) {
    expect_error(with_objects(kLamp, R"({"lamp": {"emission": [1, 1e999, 1]}})"),
                 "bad.json: materials.lamp.emission[1]: number is not finite");
    expect_error(
        with_objects(
            R"({"type": "polygon", "material": "lamp", "vertices": [[0,0,0],[1,0,0],[0,-1e999,0]]})"),
        "bad.json: objects[0].vertices[2][1]: number is not finite");
}

TEST(SceneBadInput, ReflectanceAboveOne) {
    expect_error(
        with_objects(
            kLamp,
            R"({"lamp": {"emission": [1,1,1], "diffuse": [0.5, 0.7, 0.5], "specular": [0.4, 0.4, 0.4]}})"),
        "bad.json: materials.lamp: diffuse + specular = 1.1 > 1 in channel 1");
    expect_error(
        with_objects(kLamp, R"({"lamp": {"emission": [1,1,1], "specular": [0.4, 1.2, 0.4]}})"),
        "bad.json: materials.lamp.specular[1]: reflectance must be <= 1");
}

TEST(SceneBadInput, NegativeReflectance) {
    expect_error(
        with_objects(kLamp, R"({"lamp": {"emission": [1,1,1], "diffuse": [0.5, 0.5, -0.1]}})"),
        "bad.json: materials.lamp.diffuse[2]: must be >= 0");
    expect_error(with_objects(kLamp, R"({"lamp": {"emission": [1,-1,1]}})"),
                 "bad.json: materials.lamp.emission[1]: must be >= 0");
}

TEST(SceneBadInput, VectorOfWrongLength) {
    expect_error(
        with_objects(kLamp +
                     R"(, {"type": "box", "min": [0,0], "max": [1,1,1], "material": "white"})"),
        "bad.json: objects[1].min: expected an array of 3 numbers, got an array of 2 elements");
}

TEST(SceneBadInput, WrongType) {
    expect_error(
        with_objects(kLamp + R"(, {"type": "sphere", "radius": "big", "material": "white"})"),
        "bad.json: objects[1].radius: expected a number, got \"big\"");
    expect_error(
        with_objects(kLamp +
                     R"(, {"type": "sphere", "radius": 1, "flip": 1, "material": "white"})"),
        "bad.json: objects[1].flip: expected true or false, got 1");
    expect_error(R"({"materials": [], "objects": []})",
                 "bad.json: materials: expected an object, got an empty array");
}

TEST(SceneBadInput, EmptyObjects) {
    expect_error(R"({"materials": {"lamp": {"emission": [1,1,1]}}, "objects": []})",
                 "bad.json: objects: the scene has no objects");
    expect_error(R"({"materials": {"lamp": {"emission": [1,1,1]}}})",
                 "bad.json: (top level): missing required key 'objects'");
}

TEST(SceneBadInput, NoEmitter) {
    expect_error(
        with_objects(R"({"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "white"})"),
        "bad.json: objects: no emitter");
}

TEST(SceneBadInput, DegeneratePolygon) {
    expect_error(
        with_objects(
            kLamp +
            R"(, {"type": "polygon", "material": "white", "vertices": [[0,0,0],[1,1,1],[2,2,2]]})"),
        "bad.json: objects[1].vertices: polygon is degenerate");
}

TEST(SceneBadInput, NonPlanarPolygon) {
    expect_error(
        with_objects(
            kLamp +
            R"(, {"type": "polygon", "material": "white", "vertices": [[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]]})"),
        "bad.json: objects[1].vertices: polygon is not planar (max deviation 0.118 from its "
        "plane)");
}

TEST(SceneBadInput, NonConvexPolygon) {
    expect_error(
        with_objects(kLamp + R"(, {"type": "polygon", "material": "white",
                 "vertices": [[0,0,0],[2,0,0],[2,1,0],[1,1,0],[1,2,0],[0,2,0]]})"),
        "bad.json: objects[1].vertices: polygon is not convex (turns clockwise at vertex 3)");
}

TEST(SceneBadInput, BadCamera) {
    auto cam = [](const std::string& c) {
        return R"({"materials": )" + kMaterials + R"(, "objects": [)" + kLamp +
               R"(], "cameras": [)" + c + "]}";
    };
    expect_error(cam(R"({"eye": [0,0,0], "look_at": [0,5,0], "up": [0,1,0], "fov_y_deg": 40})"),
                 "bad.json: cameras[0].up: is parallel to the view direction");
    expect_error(cam(R"({"eye": [0,0,0], "look_at": [0,0,0], "fov_y_deg": 40})"),
                 "bad.json: cameras[0].look_at: equals eye");
    expect_error(cam(R"({"eye": [0,0,0], "look_at": [0,0,1], "fov_y_deg": 180})"),
                 "bad.json: cameras[0].fov_y_deg: must be in (0, 180)");
    expect_error(cam(R"({"eye": [0,0,0], "look_at": [0,0,1], "fov_y_deg": 40, "zoom": 2})"),
                 "bad.json: cameras[0].zoom: unknown key");
    // The default up is checked too, and the message says it is the default.
    expect_error(cam(R"({"eye": [0,0,0], "look_at": [0,5,0], "fov_y_deg": 40})"),
                 "bad.json: cameras[0]: the default up [0,1,0] is parallel to the view direction");
    expect_error(cam(R"({"name": "a", "eye": [0,0,0], "look_at": [0,0,1], "fov_y_deg": 40},
                        {"name": "a", "eye": [0,0,0], "look_at": [0,0,1], "fov_y_deg": 40})"),
                 "bad.json: cameras[1].name: duplicate camera name 'a'");
}

// A scene of one closed white room lit only by `lights` (no emissive material).
std::string lit_room(const std::string& lights) {
    return R"({"materials": {"white": {"diffuse": [0.5, 0.5, 0.5]}}, "objects": [
        {"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "white", "flip": true}],
        "lights": [)" +
           lights + "]}";
}

// A point light alone lights the scene: it loads, the light in user units.
TEST(SceneLights, APointLightAloneIsAnEmitter) {
    const Scene s = load_scene_from_string(
        lit_room(R"({"name": "bulb", "type": "point", "position": [0.5, 0.9, 0.5],
                     "power": [4, 8, 12]})"),
        "lit.json", kScenes);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].name, "bulb");
    EXPECT_EQ(s.emitter_count(), 0);
    EXPECT_NEAR(glm::length(s.lights[0].position - Vec3(0.5, 0.9, 0.5)), 0.0, 1e-12);
    EXPECT_NEAR(s.lights[0].intensity.y, 8 / (4 * kPi), 1e-12);  // power = 4 pi I
    EXPECT_NEAR(s.lights[0].power().z, 12, 1e-9);
    // A spot's power spreads over its cone (smoothstep between the half-angles).
    const Scene t = load_scene_from_string(
        lit_room(R"({"type": "spot", "position": [0.5, 0.9, 0.5], "direction": [0, -2, 0],
                     "inner_deg": 20, "outer_deg": 40, "power": [1, 1, 1]})"),
        "lit.json", kScenes);
    const Light& spot = t.lights[0];
    EXPECT_EQ(spot.name, "light#0");
    EXPECT_NEAR(spot.direction.y, -1.0, 1e-12);
    EXPECT_NEAR(spot.cos_outer, std::cos(40 * kPi / 180), 1e-12);
    const double ci = std::cos(20 * kPi / 180), co = std::cos(40 * kPi / 180);
    EXPECT_NEAR(spot.intensity.x * 2 * kPi * ((1 - ci) + (ci - co) / 2), 1.0, 1e-12);
    // Lights that do not emit are no emitter.
    expect_error(lit_room(R"({"type": "point", "position": [0.5, 0.9, 0.5], "power": [0, 0, 0]})"),
                 "bad.json: objects: no emitter");
}

// Every bad light names its place with one clear message.
TEST(SceneBadInput, BadLights) {
    const std::string at = R"("position": [0.5, 0.9, 0.5], )";
    const std::string spot =
        R"({"type": "spot", "position": [0.5, 0.9, 0.5], "power": [1, 1, 1], )";
    expect_error(lit_room(R"({"type": "area", )" + at + R"("power": [1, 1, 1]})"),
                 "bad.json: lights[0].type: unknown light type 'area' (known: point, spot, "
                 "directional)");
    expect_error(
        lit_room(R"({"type": "point", )" + at + R"("power": [1,1,1], "intensity": [1,1,1]})"),
        "bad.json: lights[0].intensity: give either power or intensity, not both");
    expect_error(lit_room(R"({"type": "point", "position": [0.5, 0.9, 0.5]})"),
                 "bad.json: lights[0]: a point or spot light needs power (W) or intensity (W/sr)");
    expect_error(lit_room(R"({"type": "point", )" + at + R"("power": [1, -1, 1]})"),
                 "bad.json: lights[0].power[1]: must be >= 0 (got -1)");
    expect_error(lit_room(R"({"type": "point", )" + at + R"("intensity": [1, 1, 1e21]})"),
                 "bad.json: lights[0].intensity[2]: must be <= 1e20");
    expect_error(lit_room(spot + R"("direction": [0, -1, 0], "outer_deg": 0})"),
                 "bad.json: lights[0].outer_deg: must be in (0, 180] degrees (got 0)");
    expect_error(lit_room(spot + R"("direction": [0, -1, 0], "outer_deg": 181})"),
                 "bad.json: lights[0].outer_deg: must be in (0, 180] degrees (got 181)");
    expect_error(lit_room(spot + R"("direction": [0, -1, 0], "outer_deg": 30, "inner_deg": 40})"),
                 "bad.json: lights[0].inner_deg: must be in [0, outer_deg = 30] degrees (got 40)");
    expect_error(lit_room(spot + R"("direction": [0, 0, 0], "outer_deg": 30})"),
                 "bad.json: lights[0].direction: must be a non-zero direction");
    expect_error(lit_room(R"({"type": "spot", )" + at + R"("power": [1, 1, 1], "outer_deg": 30})"),
                 "bad.json: lights[0]: missing required key 'direction'");
    expect_error(
        lit_room(R"({"type": "directional", "direction": [0, 0, 0], "irradiance": [1, 1, 1]})"),
        "bad.json: lights[0].direction: must be a non-zero direction");
    expect_error(
        lit_room(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1],
                              "angular_diameter_deg": 31})"),
        "bad.json: lights[0].angular_diameter_deg: must be in [0, 30] (got 31)");
    expect_error(lit_room(R"({"type": "point", )" + at + R"("power": [1, 1, 1], "colour": 2})"),
                 "bad.json: lights[0].colour: unknown key for a point light (expected one of: "
                 "type, name, position, power, intensity)");
    expect_error(
        lit_room(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1],
                              "position": [0, 1, 0]})"),
        "bad.json: lights[0].position: unknown key for a directional light");
    expect_error(lit_room(R"({"type": "point", "position": [0, 1e16, 0], "power": [1, 1, 1]})"),
                 "bad.json: lights[0].position[1]: coordinate 1e+16 is beyond +-1e15");
    expect_error(lit_room(R"({"name": "a", "type": "point", )" + at + R"("power": [1, 1, 1]},
                             {"name": "a", "type": "point", )" +
                          at + R"("power": [1, 1, 1]})"),
                 "bad.json: lights[1].name: duplicate light name 'a'");
    expect_error(
        R"({"materials": )" + kMaterials + R"(, "objects": [)" + kLamp + R"(], "lights": {}})",
        "bad.json: lights: expected an array");
}

TEST(SceneBadInput, BadTexelSize) {
    expect_error(R"({"materials": )" + kMaterials + R"(, "objects": [)" + kLamp +
                     R"(], "settings": {"texel_size": 0}})",
                 "bad.json: settings.texel_size: must be > 0");
    expect_error(R"({"materials": )" + kMaterials + R"(, "objects": [)" + kLamp +
                     R"(], "settings": {"texel_size": "1cm"}})",
                 "bad.json: settings.texel_size: expected a number");
}

TEST(SceneBadInput, ErrorsFromAFileNameThePath) {
    TempDir dir("file");
    const std::string path = dir.write(
        "room.json",
        with_objects(kLamp +
                     R"(, {"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "glas"})"));
    try {
        load_scene(path);
        FAIL() << "expected an error";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()),
                  path + ": objects[1].material: unknown material 'glas' (known: white, lamp)");
    }
    try {
        load_scene(dir.path.string() + "/missing.json");
        FAIL() << "expected an error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.json: "), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vlf
