// Exchange buffers: watertight enclosures pair every ray, X(P)=Q <=> X(Q)=P, and the
// depth order decides who sees whom.
#include "vlf/field/exchange.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

#include "test_util.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace vlf {
namespace {

struct PairingTally {
    int64_t rays = 0, paired = 0, escaped = 0, blocked = 0, asymmetric = 0;
};

// Walks every fragment ray of every tile of every direction and checks symmetry.
PairingTally tally_pairings(const Scene& scene, int l, int N, int m) {
    const DirectionSet dirs(l);
    PairingTally t;
    TileExchange x;
    ExchangeScratch scratch;
    for (int d = 0; d < dirs.size(); ++d) {
        const Psf psf = rasterise_psf(scene, dirs.direction(d), d, N, m);
        for (const Tile& tile : psf.tiles) {
            build_exchange(scene, psf, tile, x, scratch);
            for (size_t fi = 0; fi < tile.fragments.size(); ++fi) {
                const Fragment& f = tile.fragments[fi];
                for (uint32_t k = 0; k < f.covered; ++k) {
                    const int32_t q = x.partner[f.ray_offset + k];
                    ++t.rays;
                    if (q == kEscaped) {
                        ++t.escaped;
                    } else if (q == kBlocked) {
                        ++t.blocked;
                    } else {
                        ++t.paired;
                        const Fragment& g = tile.fragments[q];
                        const uint32_t kq = x.partner_ray[f.ray_offset + k];
                        const bool symmetric =
                            kq < g.covered && x.partner[g.ray_offset + kq] == int32_t(fi) &&
                            x.partner_ray[g.ray_offset + kq] == k && g.facing == -f.facing;
                        if (!symmetric) ++t.asymmetric;
                    }
                }
            }
        }
    }
    return t;
}

// Every ray inside a closed enclosure pairs a facing sender and receiver in each sense:
// no fragment ray escapes or sees a back face, for all 513 directions at N = 64.
TEST(ExchangeWatertight, ClosedBoxPairsEveryRay) {
    const Scene scene = load_scene(test::source_path("scenes/closed-box.json"));
    const PairingTally t = tally_pairings(scene, 513, 64, 8);
    EXPECT_GT(t.rays, 1000000);
    EXPECT_EQ(t.escaped, 0);
    EXPECT_EQ(t.blocked, 0);
    EXPECT_EQ(t.asymmetric, 0);
    EXPECT_EQ(t.paired, t.rays);
}

Scene closed_cornell() {
    const std::string path = test::source_path("scenes/cornell.json");
    nlohmann::json j = nlohmann::json::parse(test::read_text(path));
    // Front wall at z = 0, facing +z (into the room), matching the floor, ceiling and side
    // walls' front edges exactly.
    j["objects"].push_back(
        {{"type", "polygon"},
         {"name", "front wall"},
         {"material", j["objects"][0]["material"]},
         {"vertices",
          {{556.0, 548.8, 0.0}, {0.0, 548.8, 0.0}, {0.0, 0.0, 0.0}, {552.8, 0.0, 0.0}}}});
    // The lamp hangs 0.1 mm under the ceiling, one-sided: close it into a solid with a
    // housing just above it facing the ceiling (as a real fixture is), so the ceiling over
    // the lamp does not see the lamp's back.
    j["objects"].push_back({{"type", "polygon"},
                            {"name", "lamp housing"},
                            {"material", j["objects"][0]["material"]},
                            {"vertices",
                             {{213.0, 548.75, 227.0},
                              {213.0, 548.75, 332.0},
                              {343.0, 548.75, 332.0},
                              {343.0, 548.75, 227.0}}}});
    const double y0 = 548.7, y1 = 548.75;
    const std::vector<std::vector<std::array<double, 3>>> sides = {
        {{213, y1, 227}, {343, y1, 227}, {343, y0, 227}, {213, y0, 227}},   // facing -z
        {{343, y0, 332}, {343, y1, 332}, {213, y1, 332}, {213, y0, 332}},   // facing +z
        {{213, y0, 332}, {213, y1, 332}, {213, y1, 227}, {213, y0, 227}},   // facing -x
        {{343, y1, 227}, {343, y1, 332}, {343, y0, 332}, {343, y0, 227}}};  // facing +x
    for (const auto& v : sides)
        j["objects"].push_back(
            {{"type", "polygon"}, {"material", j["objects"][0]["material"]}, {"vertices", v}});
    return load_scene_from_string(j.dump(), "cornell+front.json", test::source_path("scenes"));
}

TEST(ExchangeWatertight, ClosedCornellRoomPairsEveryRay) {
    const Scene scene = closed_cornell();
    const Face* front_ptr = nullptr;
    for (const Face& f : scene.faces)
        if (scene.objects[f.object].name == "front wall") front_ptr = &f;
    ASSERT_NE(front_ptr, nullptr);
    const Face& front = *front_ptr;
    ASSERT_GT(front.normal.z, 0.99);  // faces into the room
    const PairingTally t = tally_pairings(scene, 513, 64, 8);
    EXPECT_GT(t.rays, 1000000);
    EXPECT_EQ(t.escaped, 0);
    EXPECT_EQ(t.blocked, 0);
    EXPECT_EQ(t.asymmetric, 0);
}

// The open room: light escapes through the front, pairs stay symmetric.
TEST(ExchangeSymmetry, OpenCornellRoomIsSymmetricAndLeaks) {
    const Scene scene = load_scene(test::source_path("scenes/cornell.json"));
    const PairingTally t = tally_pairings(scene, 129, 64, 8);
    EXPECT_EQ(t.asymmetric, 0);
    EXPECT_GT(t.escaped, 0);
    EXPECT_GT(t.paired, t.escaped);
}

// Two parallel squares facing each other, a third one between them facing away on one
// side: the depth order decides the partners.
TEST(ExchangeOrder, NearestFacingSurfaceWins) {
    const std::vector<Vec3> bottom_up = {
        {-0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0.5, 0.5, -0.5}, {-0.5, 0.5, -0.5}};
    const std::vector<Vec3> top_down = {
        {-0.5, -0.5, 0.5}, {-0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, {0.5, -0.5, 0.5}};
    // Middle occluder over x in [0, 0.5], facing down (towards the bottom square).
    const std::vector<Vec3> middle_down = {
        {0.0, -0.5, 0.0}, {0.0, 0.5, 0.0}, {0.5, 0.5, 0.0}, {0.5, -0.5, 0.0}};
    const Scene scene = test::make_scene({bottom_up, top_down, middle_down});
    const Psf psf = rasterise_psf(scene, Vec3(0, 0, 1), 0, 16, 16);
    ASSERT_EQ(psf.tiles.size(), 1u);
    const Tile& tile = psf.tiles[0];
    TileExchange x;
    ExchangeScratch scratch;
    build_exchange(scene, psf, tile, x, scratch);
    int saw_top = 0, saw_middle = 0, top_blocked = 0;
    for (size_t fi = 0; fi < tile.fragments.size(); ++fi) {
        const Fragment& f = tile.fragments[fi];
        tile.edge_table(f).for_each_ray([&](int u, int v, int k) {
            const double xr = psf.ray_x(u);
            const int32_t q = x.partner[f.ray_offset + k];
            if (f.face == 0) {  // bottom, facing up
                const int expect = xr > 0.0 ? 2 : 1;
                ASSERT_GE(q, 0);
                EXPECT_EQ(tile.fragments[q].face, expect) << "x = " << xr;
                (expect == 2 ? saw_middle : saw_top)++;
            } else if (f.face == 1) {  // top, facing down: sees the middle's back over x > 0
                if (xr > 0.0) {
                    EXPECT_EQ(q, kBlocked);
                    ++top_blocked;
                } else {
                    ASSERT_GE(q, 0);
                    EXPECT_EQ(tile.fragments[q].face, 0);
                }
            }
        });
    }
    EXPECT_GT(saw_top, 0);
    EXPECT_GT(saw_middle, 0);
    EXPECT_GT(top_blocked, 0);
}

// Coincident opposite-facing surfaces: two solids in contact face into each other and
// pair; the two sides of a two-sided face look away from each other and do not.
TEST(Exchange, ContactsPairAndTwoSidedFacesDoNot) {
    for (bool twins : {false, true}) {
        Scene scene =
            test::make_scene({{{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}},
                              {{-0.5, -0.5, 0}, {-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}}});
        if (twins) {
            scene.faces[0].twin = 1;
            scene.faces[1].twin = 0;
        }
        const DirectionSet dirs(9);
        int d = 0;  // the direction most across the faces
        for (int k = 1; k < dirs.size(); ++k)
            if (std::abs(dirs.direction(k).z) > std::abs(dirs.direction(d).z)) d = k;
        const Psf psf = rasterise_psf(scene, dirs.direction(d), d, 16, 8);
        TileExchange x;
        ExchangeScratch scratch;
        int64_t pairs = 0, rays = 0;
        for (const Tile& tile : psf.tiles) {
            build_exchange(scene, psf, tile, x, scratch);
            for (const Fragment& f : tile.fragments)
                for (uint32_t k = 0; k < f.covered; ++k) {
                    ++rays;
                    pairs += x.partner[f.ray_offset + k] >= 0;
                }
        }
        ASSERT_GT(rays, 0);
        EXPECT_EQ(pairs, twins ? 0 : rays) << (twins ? "two-sided face" : "contact");
    }
}

}  // namespace
}  // namespace vlf
