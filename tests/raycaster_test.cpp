// Ray casting (RayCaster over Embree), bilinear P^T lookup (lightmap) and the backward
// ray-traced re-sampling of specular L_T (VLF §5, §6.3).
#include "vlf/scene/raycaster.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/lightmap.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/scene/texel_frame.hpp"
#include "vlf/transport/propagation.hpp"
#include "vlf/transport/resample.hpp"

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

// ---------------------------------------------------------------------------------------

Face textured_face(const std::vector<Vec3>& vertices, double texel) {
    Face f = test::make_face(vertices);
    build_texel_frame(f, texel, 512);
    return f;
}

TEST(Lightmap, LinearRadianceIsReproducedInside) {
    // A tilted rectangle, 10 x 6 full texels.
    const Vec3 a(0.1, -0.2, 0.3), eu = glm::normalize(Vec3(1, 0.2, -0.1));
    const Vec3 ev = glm::normalize(glm::cross(Vec3(0.3, 0.1, 1.0), eu));
    const double texel = 0.05;
    const Face f = textured_face({a, a + 0.5 * eu, a + 0.5 * eu + 0.3 * ev, a + 0.3 * ev}, texel);
    ASSERT_GE(f.texels.width, 6);
    ASSERT_GE(f.texels.height, 6);
    const Vec3 gx(2.0, -1.0, 0.5), gy(-0.3, 4.0, 1.0), gz(1.0, 1.0, -2.0);
    auto L = [&](const Vec3& p) {
        return Rgb(1.0 + glm::dot(gx, p), 2.0 + glm::dot(gy, p), 3.0 + glm::dot(gz, p));
    };
    std::vector<Rgb> rad(f.texels.count());
    for (int j = 0; j < f.texels.height; ++j)
        for (int i = 0; i < f.texels.width; ++i)
            rad[size_t(j) * f.texels.width + i] = L(f.texels.to_plane({i + 0.5, j + 0.5}));
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int tested = 0;
    for (int k = 0; k < 2000; ++k) {
        // Points between the texel centres of texels wholly inside the face.
        const Vec2 t(0.5 + u(rng) * (f.texels.width - 1.0), 0.5 + u(rng) * (f.texels.height - 1.0));
        const int i0 = std::min(int(t.x - 0.5), f.texels.width - 2);
        const int j0 = std::min(int(t.y - 0.5), f.texels.height - 2);
        const double full = texel * texel * (1 - 1e-9);
        bool inside = true;
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                inside &= f.texel_area[size_t(j0 + b) * f.texels.width + i0 + c] >= full;
        if (!inside) continue;
        const Vec3 p = f.texels.to_plane(t);
        const Rgb got = sample_lightmap(f, rad.data(), p);
        const Rgb want = L(p);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * (1 + std::abs(want[c])));
        ++tested;
    }
    EXPECT_GT(tested, 500);
    // At a texel centre: exactly that texel. Beyond the border: clamped to the border.
    EXPECT_EQ(sample_lightmap(f, rad.data(), f.texels.to_plane({2.5, 3.5})),
              rad[size_t(3) * f.texels.width + 2]);
    const Rgb border = sample_lightmap(f, rad.data(), f.texels.to_plane({0.5, 2.5}));
    const Rgb outside = sample_lightmap(f, rad.data(), f.texels.to_plane({-3.0, 2.5}));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(outside[c], border[c], 1e-12);
}

TEST(Lightmap, UnreliableRimTexelsGetNoWeight) {
    // A right triangle: texels along the hypotenuse are partly outside; those below 25%
    // carry an absurd radiance that must never show.
    const Face f = textured_face({{0, 0, 0}, {0.4, 0, 0}, {0, 0.3, 0}}, 0.023);
    const double reliable = kReliableTexelFraction * f.texels.size * f.texels.size;
    std::vector<Rgb> rad(f.texels.count());
    int unreliable = 0;
    for (int k = 0; k < f.texels.count(); ++k) {
        const bool ok = f.texel_area[k] >= reliable;
        rad[k] = ok ? Rgb(1.0 + 0.01 * (k % 7), 2.0, 3.0) : Rgb(1e9);
        unreliable += f.texel_area[k] > 0 && !ok;
    }
    ASSERT_GT(unreliable, 3);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 0.4);
    for (int k = 0; k < 3000; ++k) {
        const double x = u(rng), y = u(rng);
        if (x / 0.4 + y / 0.3 > 1.0) continue;  // on the face
        const Rgb v =
            sample_lightmap(f, rad.data(), f.texels.to_plane(f.texels.to_texel({x, y, 0})));
        EXPECT_GE(v.x, 1.0 - 1e-12);
        EXPECT_LE(v.x, 1.06 + 1e-12);
        EXPECT_NEAR(v.y, 2.0, 1e-12);
    }
    // A sliver face with no reliable texel falls back to its largest texel.
    const Face s = textured_face({{0, 0, 0}, {0.4, 0, 0}, {0.4, 0.004, 0}, {0, 0.004, 0}}, 0.05);
    ASSERT_GT(s.texels.width, 2);
    std::vector<Rgb> srad(s.texels.count());
    for (size_t k = 0; k < srad.size(); ++k) srad[k] = Rgb(double(k) + 1.0);
    const Vec3 at(0.2, 0.002, 0);
    const Rgb v = sample_lightmap(s, srad.data(), at);
    const double k = v.x - 1.0;  // the texel it took: one of the two nearest along u
    EXPECT_EQ(k, std::floor(k));
    EXPECT_LE(std::abs(k + 0.5 - s.texels.to_texel(at).x), 1.0);
    EXPECT_EQ(v, srad[size_t(k)]);
}

TEST(Lightmap, TexelRadianceIsPowerOverPiArea) {
    const Scene s = load_scene(test::source_path("scenes/closed-box.json"));
    TextureMaps maps(s);
    for (size_t k = 0; k < maps.texels(); ++k) maps.total[k] = Rgb(1.0 + k % 5, 2.0, 0.5);
    const std::vector<Rgb> r = texel_radiance(s, maps);
    ASSERT_EQ(r.size(), maps.texels());
    for (const Face& f : s.faces)
        for (size_t t = 0; t < maps.count(f.id); ++t) {
            const Rgb want = f.texel_area[t] > 0
                                 ? maps.total[maps.begin(f.id) + t] / (kPi * f.texel_area[t])
                                 : Rgb(0.0);
            EXPECT_EQ(r[maps.begin(f.id) + t], want);
        }
}

// ---------------------------------------------------------------------------------------

// A closed room with a lamp, a diffuse block and one mirror panel on a wall. The block
// floats 1 cm above the floor: a face lying on another (coincident and coplanar) gives a
// ray caster no defined closest hit.
const char* kRoomWithMirror = R"({
  "materials": {
    "white": {"diffuse": [0.7, 0.6, 0.5]},
    "grey": {"diffuse": [0.4, 0.5, 0.3]},
    "mirror": {"specular": [0.9, 0.8, 0.95]},
    "lamp": {"diffuse": [0.5, 0.5, 0.5], "emission": [5, 4, 3]}
  },
  "objects": [
    {"type": "box", "min": [-1, 0, -1], "max": [1, 2, 1], "flip": true, "material": "white"},
    {"type": "polygon", "material": "lamp",
     "vertices": [[0.2, 1.99, -0.2], [0.2, 1.99, 0.2], [-0.2, 1.99, 0.2], [-0.2, 1.99, -0.2]]},
    {"type": "polygon", "material": "mirror",
     "vertices": [[0.99, 0.3, -0.6], [0.99, 0.3, 0.6], [0.99, 1.5, 0.6], [0.99, 1.5, -0.6]]},
    {"type": "box", "min": [-0.6, 0.01, -0.5], "max": [-0.1, 0.5, 0.0], "rotate_y_deg": 15.0,
     "material": "grey"}
  ]
})";

struct Baked {
    Scene scene;
    Propagation run;  // its Transport refers to `scene`: a Baked never moves
};

std::unique_ptr<Baked> bake_mirror_room() {
    auto b = std::make_unique<Baked>();
    b->scene =
        load_scene_from_string(kRoomWithMirror, "mirror-room.json", test::source_path("scenes"));
    PropagateParams p;
    p.field.directions = 129;
    p.field.resolution = 32;
    p.field.tile = 8;
    p.cycles = 3;
    p.resample = false;
    b->run = propagate(b->scene, p, RunOptions{});
    return b;
}

// The mirror's rays in PSF d, computed here from the raster (face-local ray order).
std::vector<Vec3> ray_points(const Face& face, const Mat3& rot, int N, int m, int& facing) {
    FaceRaster fr;
    rasterise_face(face, rot, N, m, fr);
    facing = fr.facing;
    std::vector<Vec3> pts;
    for (const FaceFragment& ff : fr.fragments)
        fr.edge_table(ff).for_each_ray([&](int u, int v, int) {
            const double x = (2.0 * (ff.s * m + u) + 1.0) / N - 1.0;
            const double y = (2.0 * (ff.t * m + v) + 1.0) / N - 1.0;
            const double z = plane_depth(face, rot, x, y);
            pts.push_back(glm::transpose(rot) * Vec3(x, y, z));
        });
    return pts;
}

TEST(Resample, MirrorRaysSeeTheReflectedDiffuseSurface) {
    const auto b = bake_mirror_room();
    Transport& t = *b->run.transport;
    const Scene& s = b->scene;
    const RayCaster rc(s);
    const RadianceMaps& maps = t.specular_maps();
    ASSERT_EQ(maps.faces.size(), 1u);
    const int mirror = maps.faces[0];
    const Face& mf = s.faces[mirror];
    const Rgb rho_s = s.material_of(mf).specular;
    // The propagated estimate of the mirror's outgoing radiance: L_T plus the reflections
    // received in the last cycle, still unshot in L_U (VLF §4.1: they would join L_T when
    // shot). P^T, which resampling reads, holds one bounce more than even that, so the
    // resampled maps come out somewhat brighter after only 3 cycles (more so for red, whose
    // walls reflect most).
    std::vector<RgbF> before = maps.total;
    for (size_t k = 0; k < before.size(); ++k) before[k] += maps.unshot[k];

    resample_specular(t, rc, 0);

    const std::vector<Rgb> rad = texel_radiance(s, t.texture_maps());
    const int N = t.params().field.resolution, m = t.params().field.tile;
    Rgb sum_before(0.0), sum_after(0.0);
    double abs_diff = 0.0;
    size_t rays = 0, zero = 0;
    for (int d = 0; d < t.directions().size(); ++d) {
        const uint64_t n = maps.count(d, mirror), base = maps.begin(d, mirror);
        if (n == 0) continue;
        int facing = 0;
        const std::vector<Vec3> pts = ray_points(mf, t.rotations()[d], N, m, facing);
        ASSERT_EQ(pts.size(), n);
        const Vec3 out = double(facing) * t.directions().direction(d);  // leaves the mirror
        ASSERT_GT(glm::dot(out, mf.normal), 0.0);
        // The light leaving along `out` arrived along reflect(out); look back along it.
        const Vec3 arrived = glm::reflect(out, mf.normal);
        const Vec3 back = -arrived;
        for (uint64_t k = 0; k < n; ++k) {
            RayHit h;
            Vec3 o = pts[k] + 1e-6 * back;
            bool found = rc.intersect(o, back, 0.0, 1e30, h);
            while (found && h.face == mirror)
                found = rc.intersect(h.point + 1e-6 * back, back, 0.0, 1e30, h);
            Rgb want(0.0);
            if (found && glm::dot(s.faces[h.face].normal, back) < 0.0)
                want =
                    rho_s * sample_lightmap(s.faces[h.face],
                                            rad.data() + t.texture_maps().begin(h.face), h.point);
            const Rgb got(maps.total[base + k]);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(got[c], want[c], 1e-5 * std::abs(want[c]) + 1e-12)
                    << "direction " << d << " ray " << k << " channel " << c;
            zero += want.x == 0.0;
            sum_before += Rgb(before[base + k]);
            sum_after += got;
            abs_diff += std::abs(double(before[base + k].x) - got.x);
            ++rays;
        }
    }
    ASSERT_GT(rays, 1000u);
    EXPECT_EQ(zero, 0u);  // a closed room: every mirror ray sees a lit front face
    // The propagated maps estimate the same radiance, blurred by the direction set.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum_after[c] / sum_before[c], 1.0, 0.2) << c;
    RecordProperty("mean_ratio_r", std::to_string(sum_after.x / sum_before.x));
    RecordProperty("mean_abs_rel_diff_r", std::to_string(abs_diff / sum_before.x));
    std::printf("resample: %zu rays, mean after/before = %.4f %.4f %.4f, mean |diff|/mean = %.4f\n",
                rays, sum_after.x / sum_before.x, sum_after.y / sum_before.y,
                sum_after.z / sum_before.z, abs_diff / sum_before.x);
}

TEST(Resample, SameOnOneAndTwoThreads) {
    const auto b = bake_mirror_room();
    Transport& t = *b->run.transport;
    const RayCaster rc(b->scene);
    std::vector<RgbF> one, two;
    {
        ThreadLimit limit(1);
        resample_specular(t, rc, 1);
        one = t.specular_maps().total;
    }
    for (auto& v : t.specular_maps().total) v = RgbF(-1.0f);  // resampling rewrites every ray
    {
        ThreadLimit limit(2);
        resample_specular(t, rc, 2);
        two = t.specular_maps().total;
    }
    ASSERT_EQ(one.size(), two.size());
    for (size_t k = 0; k < one.size(); ++k) ASSERT_EQ(one[k], two[k]) << k;
    for (const RgbF& v : two) ASSERT_GE(v.x, 0.0f);
}

TEST(Resample, MirrorsSeenInMirrorsAndMixedMaterials) {
    // Two facing mirrors (one mixed) in a room: paths bounce between them; the value must
    // still be the own diffuse part + rho_s * the traced value, checked one step deep.
    const char* json = R"({
      "materials": {
        "white": {"diffuse": [0.7, 0.6, 0.5]},
        "mirror": {"specular": [0.9, 0.9, 0.9]},
        "mixed": {"diffuse": [0.2, 0.2, 0.2], "specular": [0.6, 0.6, 0.6]},
        "lamp": {"diffuse": [0.5, 0.5, 0.5], "emission": [5, 4, 3]}
      },
      "objects": [
        {"type": "box", "min": [-1, 0, -1], "max": [1, 2, 1], "flip": true, "material": "white"},
        {"type": "polygon", "material": "lamp",
         "vertices": [[0.2, 1.99, -0.2], [0.2, 1.99, 0.2], [-0.2, 1.99, 0.2], [-0.2, 1.99, -0.2]]},
        {"type": "polygon", "material": "mirror",
         "vertices": [[0.99, 0.3, -0.6], [0.99, 0.3, 0.6], [0.99, 1.5, 0.6], [0.99, 1.5, -0.6]]},
        {"type": "polygon", "material": "mixed",
         "vertices": [[-0.99, 0.3, -0.6], [-0.99, 1.5, -0.6], [-0.99, 1.5, 0.6], [-0.99, 0.3, 0.6]]}
      ]
    })";
    const Scene s = load_scene_from_string(json, "two-mirrors.json", test::source_path("scenes"));
    PropagateParams p;
    p.field.directions = 33;
    p.field.resolution = 32;
    p.field.tile = 8;
    p.cycles = 2;
    p.resample = false;
    Propagation run = propagate(s, p, RunOptions{});
    Transport& t = *run.transport;
    const RayCaster rc(s);
    resample_specular(t, rc, 0);
    const std::vector<Rgb> rad = texel_radiance(s, t.texture_maps());
    const auto& off = t.texture_maps().offset;
    const RadianceMaps& maps = t.specular_maps();
    ASSERT_EQ(maps.faces.size(), 2u);
    int checked = 0, via_mirror = 0;
    for (int d = 0; d < t.directions().size(); ++d)
        for (int f : maps.faces) {
            const uint64_t n = maps.count(d, f);
            if (n == 0) continue;
            int facing = 0;
            const Face& face = s.faces[f];
            const Material& mat = s.material_of(face);
            const std::vector<Vec3> pts = ray_points(face, t.rotations()[d], 32, 8, facing);
            const Vec3 out = double(facing) * t.directions().direction(d);
            const Vec3 back = -glm::reflect(out, face.normal);
            for (uint64_t k = 0; k < n; k += 7) {
                Rgb want = mat.is_diffuse() ? sample_lightmap(face, rad.data() + off[f], pts[k])
                                            : Rgb(0.0);
                RayHit h;
                if (rc.intersect(pts[k] + 1e-6 * back, back, 0.0, 1e30, h) && h.face != f &&
                    glm::dot(s.faces[h.face].normal, back) < 0.0) {
                    via_mirror += s.material_of(s.faces[h.face]).is_specular();
                    want += mat.specular * specular_path_radiance(s, rc, rad, off, h.face, h.point,
                                                                  -back, kResampleMaxBounces - 1);
                }
                const Rgb got(maps.total[maps.begin(d, f) + k]);
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(got[c], want[c], 1e-5 * want[c] + 1e-12)
                        << "face " << f << " dir " << d << " ray " << k << " hit " << h.face
                        << " t " << h.t << " out.n " << glm::dot(out, face.normal);
                ++checked;
            }
        }
    EXPECT_GT(checked, 100);
    EXPECT_GT(via_mirror, 10);
}

}  // namespace
}  // namespace vlf
