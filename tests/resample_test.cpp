// Backward ray-traced re-sampling of specular L_T (transport/resample.hpp, VLF §5, §6.3):
// every mirror ray carries what it sees, mirrors seen in mirrors included, on any thread
// count.
#include "vlf/transport/resample.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "test_util.hpp"
#include "vlf/bake/ray_images.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/lightmap.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/propagation.hpp"

namespace vlf {
namespace {

struct Baked {
    Scene scene;
    Propagation run;  // its Transport refers to `scene`: a Baked never moves
};

// tests/scenes/mirror-room.json: a closed room with a lamp, a diffuse block and one mirror
// panel on a wall. The block floats 1 cm above the floor: a face lying on another
// (coincident and coplanar) gives a ray caster no defined closest hit.
std::unique_ptr<Baked> bake_mirror_room() {
    auto b = std::make_unique<Baked>();
    b->scene = load_scene(test::source_path("tests/scenes/mirror-room.json"));
    const PropagateParams p = test::params(129, 32, 8, 3, true);
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
                want = rho_s *
                       sample_lightmap(s.chart_of(s.faces[h.face]),
                                       rad.data() + t.texture_maps().begin(s.faces[h.face].chart),
                                       h.point);
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
    // Two facing mirrors (one mixed) in a room (tests/scenes/two-mirrors.json): paths bounce
    // between them; the value must still be the own diffuse part + rho_s * the traced
    // value, checked one step deep.
    const Scene s = load_scene(test::source_path("tests/scenes/two-mirrors.json"));
    const PropagateParams p = test::params(33, 32, 8, 2, true);
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
                Rgb want = mat.is_diffuse() ? sample_lightmap(s.chart_of(face),
                                                              rad.data() + off[face.chart], pts[k])
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

TEST(Resample, GlassFacesSeenFromOutsideAreTracedInnerFacesKeepTheField) {
    // tests/scenes/glass-room.json: a smooth glass ball and an absorbing glass box. An outer
    // face's traced radiance differs from the field's; an inner face's front looks into the
    // glass (an eye there is the only one that sees it) and keeps the field's L_T.
    const Scene s = load_scene(test::source_path("tests/scenes/glass-room.json"));
    const PropagateParams p = test::params(33, 32, 8, 3, true);
    Propagation run = propagate(s, p, RunOptions{});
    Transport& t = *run.transport;
    const std::vector<RgbF> field = t.specular_maps().total;
    resample_specular(t, RayCaster(s), 0);
    const RadianceMaps& maps = t.specular_maps();
    uint64_t inner = 0, outer = 0, outer_changed = 0;
    for (int d = 0; d < t.directions().size(); ++d)
        for (int f : maps.faces) {
            if (!s.material_of(s.faces[f]).dielectric) continue;
            for (uint64_t k = maps.begin(d, f); k < maps.begin(d, f) + maps.count(d, f); ++k) {
                if (s.faces[f].inner) {
                    ASSERT_EQ(maps.total[k], field[k]) << "inner face " << f << " dir " << d;
                    ++inner;
                } else {
                    ++outer;
                    outer_changed += maps.total[k] != field[k];
                }
            }
        }
    EXPECT_GT(inner, 1000u);
    EXPECT_GT(outer, 1000u);
    EXPECT_GT(double(outer_changed), 0.9 * double(outer));
}

TEST(Resample, InTheBakeWriterAsInPropagateSameRays) {
    // propagate resamples in the bake writer, a direction at a time as it makes the
    // direction's rays (RunOptions::resample_later, resampling_ray_source): the rays must be
    // the bits of resampling all directions first. Glass (outer and inner faces) and a
    // mirror-free box in tests/scenes/glass-room.json.
    const Scene s = load_scene(test::source_path("tests/scenes/glass-room.json"));
    PropagateParams p = test::params(33, 32, 8, 3, true);
    p.resample = true;
    const int l = p.field.directions, N = p.field.resolution, m = p.field.tile;
    Propagation first = propagate(s, p, RunOptions{});
    EXPECT_FALSE(first.resample_pending);
    const RayImages want = gather_rays(ray_source(s, p, *first.transport), l, N, m);
    RunOptions later;
    later.resample_later = true;
    Propagation deferred = propagate(s, p, later);
    ASSERT_TRUE(deferred.resample_pending);
    // Not yet resampled: the field's own L_T differs from the traced one.
    const RayImages field = gather_rays(ray_source(s, p, *deferred.transport), l, N, m);
    ASSERT_EQ(field.face, want.face);
    EXPECT_NE(field.radiance, want.radiance);
    const RayImages got = gather_rays(resampling_ray_source(s, p, *deferred.transport), l, N, m);
    EXPECT_EQ(got.pixel_offset, want.pixel_offset);
    EXPECT_EQ(got.face, want.face);
    ASSERT_EQ(got.radiance.size(), want.radiance.size());
    for (size_t k = 0; k < got.radiance.size(); ++k)
        ASSERT_EQ(got.radiance[k], want.radiance[k]) << k;
    // And the transport's maps are resampled too, as propagate leaves them.
    EXPECT_EQ(deferred.transport->specular_maps().total, first.transport->specular_maps().total);
}

}  // namespace
}  // namespace vlf
