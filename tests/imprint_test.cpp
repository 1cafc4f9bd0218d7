// imprint_test.cpp — contact lines cut the surfaces they run across (scene/imprint.hpp,
// docs/charts.md "Contact lines"): a room halved by a two-sided divider keeps its dark half
// dark, and partial contacts cut nothing.
#include "vlf/scene/imprint.hpp"

#include <gtest/gtest.h>

#include <string>

#include "test_util.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

// A closed 2 x 2 x 2 room halved at z = 0 by a two-sided divider, the lamp under the
// ceiling on the +z side. `divider` spans x and y: beyond the walls (piercing them) or
// exactly to them (a T-junction).
std::string divided_room(const std::string& divider) {
    return R"({
      "materials": {"white": {"diffuse": [0.7, 0.7, 0.7]}, "lamp": {"emission": [10, 10, 10]}},
      "objects": [
        {"name": "room", "type": "box", "min": [-1, 0, -1], "max": [1, 2, 1], "flip": true,
         "material": "white"},
        {"name": "divider", "type": "polygon", "two_sided": true, "material": "white",
         "vertices": )" +
           divider + R"(},
        {"name": "lamp", "type": "polygon", "material": "lamp",
         "vertices": [[-0.2, 1.99, 0.3], [0.2, 1.99, 0.3], [0.2, 1.99, 0.7], [-0.2, 1.99, 0.7]]}
      ]
    })";
}

// Area-weighted mean radiance of the room's texels on each side of z = 0, by the texel's
// centre; texels within a texel of the plane count on neither side.
struct Sides {
    double lit = 0.0, dark = 0.0;
};
Sides side_radiance(const Scene& scene, const Transport& t) {
    const TextureMaps& tex = t.texture_maps();
    double lit = 0.0, lit_area = 0.0, dark = 0.0, dark_area = 0.0;
    for (const Chart& c : scene.charts) {
        if (scene.objects[size_t(scene.faces[size_t(c.faces[0])].object)].name != "room") continue;
        const double edge = c.texels.size / scene.normalisation.scale;
        for (int j = 0; j < c.texels.height; ++j)
            for (int i = 0; i < c.texels.width; ++i) {
                const size_t k = size_t(j) * size_t(c.texels.width) + size_t(i);
                const double z =
                    scene.normalisation.to_user(c.texels.to_plane({i + 0.5, j + 0.5})).z;
                const double a = c.texel_area[k], L = tex.radiance(c, k).x;
                if (z > edge) {
                    lit += a * L;
                    lit_area += a;
                } else if (z < -edge) {
                    dark += a * L;
                    dark_area += a;
                }
            }
    }
    return {lit / lit_area, dark / dark_area};
}

// The path tracer finds no light at all in the dark half (the divider closes it). Before the
// walls, floor and ceiling were cut along the divider, their texels straddling it carried
// the lit side's light over: the dark half read 1.4 % of the lit half. Bound: 0.1 %.
TEST(Imprint, TwoSidedDividerKeepsTheDarkHalfDark) {
    for (const char* divider :
         {"[[-1.2, -0.2, 0], [1.2, -0.2, 0], [1.2, 2.2, 0], [-1.2, 2.2, 0]]",  // piercing
          "[[-1, 0, 0], [1, 0, 0], [1, 2, 0], [-1, 2, 0]]"}) {                 // T-junctions
        const Scene scene = test::scene_from_json(divided_room(divider));
        // Floor, ceiling and the two side walls are cut in two; the end walls are not.
        int room_faces = 0;
        double room_area = 0.0;
        for (const Face& f : scene.faces)
            if (scene.objects[size_t(f.object)].name == "room") {
                ++room_faces;
                room_area += f.area;
            }
        EXPECT_EQ(room_faces, 10) << divider;
        const double s = scene.normalisation.scale;
        EXPECT_NEAR(room_area / (s * s), 24.0, 1e-9) << divider;  // the surface is unchanged
        PropagateParams p;
        p.cycles = 8;
        const auto t = test::run_transport(scene, p);
        for (const LedgerEntry& e : t->ledger()) EXPECT_LE(e.relative_error(), 1e-9);
        const Sides r = side_radiance(scene, *t);
        EXPECT_GT(r.lit, 0.05) << divider;
        EXPECT_LT(r.dark, 1e-3 * r.lit) << divider << ": dark " << r.dark << ", lit " << r.lit;
    }
}

// A box standing on the floor touches it along lines that do not run across it: nothing is
// cut (nor in the paper's Cornell box, whose blocks stand on its floor).
TEST(Imprint, PartialContactsCutNothing) {
    const Scene scene = test::scene_from_json(R"({
      "materials": {"white": {"diffuse": [0.7, 0.7, 0.7]}, "lamp": {"emission": [10, 10, 10]}},
      "objects": [
        {"name": "room", "type": "box", "min": [-1, 0, -1], "max": [1, 2, 1], "flip": true,
         "material": "white"},
        {"name": "block", "type": "box", "min": [-0.3, 0, -0.3], "max": [0.3, 0.6, 0.3],
         "material": "white"},
        {"name": "lamp", "type": "polygon", "material": "lamp",
         "vertices": [[-0.2, 1.99, 0.3], [0.2, 1.99, 0.3], [0.2, 1.99, 0.7], [-0.2, 1.99, 0.7]]}
      ]
    })");
    EXPECT_EQ(scene.faces.size(), 13u);
    for (const std::string& note : scene.load_notes)
        EXPECT_EQ(note.find("cut into"), std::string::npos) << note;
    const Scene cornell = load_scene(test::source_path("scenes/cornell.json"));
    for (const std::string& note : cornell.load_notes)
        EXPECT_EQ(note.find("cut into"), std::string::npos) << note;
}

}  // namespace
}  // namespace vlf
