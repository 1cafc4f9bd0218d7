// Ray casting (RayCaster over Embree): closest hits from inside and outside a cube, bad
// input, and random rays against a brute-force reference.
#include "vlf/scene/raycaster.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/scene/texel_frame.hpp"

namespace vlf {
namespace {

// An axis-aligned cube [-h, h]^3 with outward normals (counter-clockwise from outside).
Scene make_cube(double h) {
    const std::vector<std::vector<Vec3>> quads = {
        {{h, -h, -h}, {h, h, -h}, {h, h, h}, {h, -h, h}},      // +x
        {{-h, -h, -h}, {-h, -h, h}, {-h, h, h}, {-h, h, -h}},  // -x
        {{-h, h, -h}, {-h, h, h}, {h, h, h}, {h, h, -h}},      // +y
        {{-h, -h, -h}, {h, -h, -h}, {h, -h, h}, {-h, -h, h}},  // -y
        {{-h, -h, h}, {h, -h, h}, {h, h, h}, {-h, h, h}},      // +z
        {{-h, -h, -h}, {-h, h, -h}, {h, h, -h}, {h, -h, -h}},  // -z
    };
    return test::make_scene(quads);
}

// Brute force: ray against a convex planar polygon, in double precision. `slack` widens
// (> 0) or narrows (< 0) the polygon by that distance, to classify rays near edges.
bool hit_polygon(const Face& f, const Vec3& o, const Vec3& d, double slack, double& t) {
    const double nd = glm::dot(f.normal, d);
    if (std::abs(nd) < 1e-15) return false;
    t = (f.plane_offset - glm::dot(f.normal, o)) / nd;
    if (!(t > 0.0)) return false;
    const Vec3 p = o + t * d;
    const size_t n = f.vertices.size();
    for (size_t k = 0; k < n; ++k) {
        const Vec3& a = f.vertices[k];
        const Vec3& b = f.vertices[(k + 1) % n];
        const Vec3 e = glm::normalize(b - a);
        // Signed distance of p inside the edge (positive towards the interior).
        const double s = glm::dot(glm::cross(e, p - a), f.normal);
        if (s < -slack) return false;
    }
    return true;
}

struct BruteHit {
    int face = -1;
    double t = 0;
};

BruteHit brute_force(const Scene& s, const Vec3& o, const Vec3& d, double slack) {
    BruteHit best;
    best.t = 1e300;
    for (const Face& f : s.faces) {
        double t;
        if (hit_polygon(f, o, d, slack, t) && t < best.t) {
            best.t = t;
            best.face = f.id;
        }
    }
    return best;
}

TEST(RayCaster, CubeFromInsideAndOutside) {
    const Scene s = make_cube(0.5);
    const RayCaster rc(s);
    EXPECT_EQ(rc.triangles(), 12);
    RayHit h;
    // From inside: every axis direction hits its face at t = 0.5 (the back of it).
    const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int k = 0; k < 6; ++k) {
        const Vec3 o(0.1, -0.2, 0.05);
        ASSERT_TRUE(rc.intersect(o, axes[k], 0.0, 10.0, h)) << k;
        EXPECT_EQ(h.face, k);
        const double expect = 0.5 - glm::dot(o, axes[k]);
        EXPECT_NEAR(h.t, expect, 1e-12);
        EXPECT_NEAR(glm::dot(h.point, axes[k]), 0.5, 1e-12);
        EXPECT_TRUE(rc.occluded(o, axes[k], 0.0, 10.0));
        EXPECT_FALSE(rc.occluded(o, axes[k], 0.0, expect - 1e-4));
        EXPECT_FALSE(rc.intersect(o, axes[k], 0.0, expect - 1e-4, h));
    }
    // From outside: the front of -x at t = 1.5, then (tmin past it) the back of +x.
    const Vec3 o(-2.0, 0.1, 0.2);
    ASSERT_TRUE(rc.intersect(o, {1, 0, 0}, 0.0, 1e30, h));
    EXPECT_EQ(h.face, 1);
    EXPECT_NEAR(h.t, 1.5, 1e-12);
    ASSERT_TRUE(rc.intersect(o, {1, 0, 0}, 1.6, 1e30, h));
    EXPECT_EQ(h.face, 0);
    EXPECT_NEAR(h.t, 2.5, 1e-12);
    // Unnormalised direction: t in units of |dir|.
    ASSERT_TRUE(rc.intersect(o, {2, 0, 0}, 0.0, 1e30, h));
    EXPECT_NEAR(h.t, 0.75, 1e-12);
    // Misses: beside the cube, pointing away, and a segment ending before it.
    EXPECT_FALSE(rc.intersect({-2, 0.6, 0}, {1, 0, 0}, 0.0, 1e30, h));
    EXPECT_EQ(h.face, -1);
    EXPECT_FALSE(rc.occluded({-2, 0.6, 0}, {1, 0, 0}, 0.0, 1e30));
    EXPECT_FALSE(rc.intersect(o, {-1, 0, 0}, 0.0, 1e30, h));
    EXPECT_FALSE(rc.occluded(o, {-1, 0, 0}, 0.0, 1e30));
    EXPECT_FALSE(rc.intersect(o, {1, 0, 0}, 0.0, 1.4, h));
    EXPECT_FALSE(rc.occluded(o, {1, 0, 0}, 0.0, 1.4));
    // Degenerate queries are misses, not errors.
    EXPECT_FALSE(rc.intersect(o, {0, 0, 0}, 0.0, 1e30, h));
    EXPECT_FALSE(rc.intersect(o, {1, 0, 0}, 2.0, 1.0, h));
}

// A two-sided panel is a face and its reversed twin on one polygon: a ray from either side
// hits the face whose front it meets, never the one it sees from behind (which the
// renderers would shade black).
TEST(RayCaster, TwoSidedPanelShowsTheSideTheRayMeets) {
    const Scene s = load_scene_from_string(R"({
      "materials": {"w": {"diffuse": [0.5, 0.5, 0.5], "emission": [1, 1, 1]}},
      "objects": [{"type": "polygon", "material": "w", "two_sided": true,
                   "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}]
    })",
                                           "two-sided.json", ".");
    ASSERT_EQ(s.faces.size(), 2u);
    ASSERT_EQ(s.faces[0].twin, 1);
    const RayCaster rc(s);
    // The polygon goes into the hierarchy once (two triangles of a fan), not once per side.
    EXPECT_EQ(rc.triangles(), 2);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.3, 0.3);  // the panel spans +-0.707 here
    int hits = 0;
    for (int k = 0; k < 200; ++k)
        for (double side : {1.0, -1.0}) {
            const Vec3 o(u(rng), u(rng), side * 0.5);
            const Vec3 d = Vec3(u(rng), u(rng), -side) - Vec3(0.0);
            RayHit h;
            ASSERT_TRUE(rc.intersect(o, d, 0.0, 1e30, h));
            EXPECT_LT(glm::dot(s.faces[h.face].normal, d), 0.0) << "ray " << k << " side " << side;
            ++hits;
        }
    EXPECT_EQ(hits, 400);
}

TEST(RayCaster, EmptySceneMissesEverything) {
    Scene s;
    const RayCaster rc(s);
    RayHit h;
    EXPECT_FALSE(rc.intersect({0, 0, 0}, {1, 0, 0}, 0, 1e30, h));
    EXPECT_FALSE(rc.occluded({0, 0, 0}, {1, 0, 0}, 0, 1e30));
}

TEST(RayCaster, NonFiniteVertexThrows) {
    Scene s = make_cube(0.5);
    s.faces[2].vertices[1].x = std::nan("");
    EXPECT_THROW({ const RayCaster rc(s); }, Error);
}

TEST(RayCaster, RandomRaysAgreeWithBruteForce) {
    const Scene s = load_scene(test::source_path("scenes/closed-box.json"));
    const RayCaster rc(s);
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int kRays = 10000;
    struct Query {
        Vec3 o, d;
        double tmax;
    };
    std::vector<Query> q(kRays);
    for (Query& r : q) {
        r.o = Vec3(u(rng), u(rng), u(rng)) * 0.7;  // inside the room and outside it
        do r.d = Vec3(u(rng), u(rng), u(rng));
        while (glm::dot(r.d, r.d) > 1.0 || glm::dot(r.d, r.d) < 1e-4);
        r.d = glm::normalize(r.d);
        r.tmax = 3.0 * (u(rng) + 1.0) * 0.5;
    }
    // All queries at once from many threads, compared afterwards.
    std::vector<RayHit> hits(kRays);
    std::vector<uint8_t> hit_ok(kRays), occ(kRays);
    parallel_for(
        0, kRays,
        [&](long i) {
            hit_ok[i] = rc.intersect(q[i].o, q[i].d, 0.0, 1e30, hits[i]);
            occ[i] = rc.occluded(q[i].o, q[i].d, 0.0, q[i].tmax);
        },
        64);

    int hits_n = 0, misses_n = 0, edge_cases = 0;
    for (int i = 0; i < kRays; ++i) {
        const Query& r = q[i];
        const BruteHit strict = brute_force(s, r.o, r.d, -1e-7);
        const BruteHit loose = brute_force(s, r.o, r.d, 1e-7);
        if (strict.face != loose.face || std::abs(strict.t - loose.t) > 1e-9) {
            ++edge_cases;  // passes within 1e-7 of an edge: either answer is right
            if (hit_ok[i]) {
                double t;
                EXPECT_TRUE(hit_polygon(s.faces[hits[i].face], r.o, r.d, 1e-6, t)) << i;
            }
            continue;
        }
        ASSERT_EQ(bool(hit_ok[i]), strict.face >= 0) << "ray " << i;
        if (strict.face < 0) {
            ++misses_n;
            EXPECT_FALSE(occ[i]) << i;
            continue;
        }
        ++hits_n;
        EXPECT_NEAR(hits[i].t, strict.t, 1e-9 * (1.0 + strict.t)) << i;
        EXPECT_NEAR(glm::length(hits[i].point - (r.o + strict.t * r.d)), 0.0, 1e-9) << i;
        if (hits[i].face != strict.face) {
            // Two faces at the same t (a coplanar or touching pair): it must hit both.
            double t;
            ASSERT_TRUE(hit_polygon(s.faces[hits[i].face], r.o, r.d, 1e-7, t)) << i;
            EXPECT_NEAR(t, strict.t, 1e-9) << i;
        }
        if (std::abs(strict.t - r.tmax) > 1e-5) {
            EXPECT_EQ(bool(occ[i]), strict.t <= r.tmax) << i;
        }
    }
    EXPECT_GT(hits_n, 5000);
    EXPECT_GT(misses_n, 200);
    EXPECT_LT(edge_cases, 50);
}

}  // namespace
}  // namespace vlf
