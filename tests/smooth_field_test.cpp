// Smooth specular faces in the field (issue 14 item 3, docs/propagation.md §13): a face with
// per-vertex shading normals turns each ray of the field about the normal at the ray's point,
// as the lights' beams and the walkthrough do, and the ledger stays exact.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "test_util.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/pathtrace.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/transport/lamp_caustics.hpp"
#include "vlf/transport/smooth_surfaces.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

using test::params;
using test::run_transport;
using test::scene_from_json;

using test::object_named;

// A 1 x 1 mirror on the floor plane under a square lamp at height 1.9 (facing down) and a
// diffuse ceiling at height 2 (facing down). The lamp cannot light the ceiling; only what the
// mirror reflects up does.
const char* kTiltedMirror = R"({
  "materials": {"white": {"diffuse": [0.5, 0.5, 0.5]},
                "lamp": {"emission": [10, 10, 10]},
                "mirror": {"specular": [0.9, 0.9, 0.9]}},
  "settings": {"texel_size": 0.05},
  "objects": [
    {"type": "polygon", "material": "mirror", "name": "mirror",
     "vertices": [[-0.5, 0, -0.5], [-0.5, 0, 0.5], [0.5, 0, 0.5], [0.5, 0, -0.5]]},
    {"type": "polygon", "material": "lamp", "name": "lamp",
     "vertices": LAMP},
    {"type": "polygon", "material": "white", "name": "ceiling",
     "vertices": [[-3, 2, -1.5], [3, 2, -1.5], [3, 2, 1.5], [-3, 2, 1.5]]}]})";

// The scene with a lamp of half-width `h` (a square at height 1.9, facing down).
Scene tilted_mirror(double h) {
    std::string text = kTiltedMirror;
    text.replace(
        text.find("LAMP"), 4,
        fmt::format("[[{0}, 1.9, {0}], [{1}, 1.9, {0}], [{1}, 1.9, {1}], [{0}, 1.9, {1}]]", -h, h));
    return scene_from_json(text);
}

// Where, on average over the power, the mirror's reflection of the lamp lands on the ceiling
// (x, user units), when every point of the mirror reflects about the unit normal n: the
// lamp's radiance is uniform, so a pair of points (a on the lamp, b on the mirror) carries
// power in proportion to cos_a cos_b / r^2 (midpoint sums, 40^2 x 40^2 points).
double predicted_centroid(const Vec3& n, double lamp_half = 0.15) {
    const int k = 40;
    double sum = 0.0, moment = 0.0;
    for (int i = 0; i < k * k; ++i) {
        const Vec3 a(-lamp_half + 2.0 * lamp_half * (i % k + 0.5) / k, 1.9,
                     -lamp_half + 2.0 * lamp_half * (i / k + 0.5) / k);
        for (int j = 0; j < k * k; ++j) {
            const Vec3 b(-0.5 + (j % k + 0.5) / k, 0.0, -0.5 + (j / k + 0.5) / k);
            const Vec3 d = b - a;
            const double r2 = glm::dot(d, d), c = -d.y / std::sqrt(r2);
            const double w = c * c / r2;
            const Vec3 u = glm::normalize(d) - 2.0 * glm::dot(glm::normalize(d), n) * n;
            const double x = b.x + u.x * (2.0 - b.y) / u.y, z = b.z + u.z * (2.0 - b.y) / u.y;
            if (std::abs(x) > 3.0 || std::abs(z) > 1.5) continue;
            sum += w;
            moment += w * x;
        }
    }
    return moment / sum;
}

// The power-weighted mean x of what the ceiling received (its texel centres).
double measured_centroid(const Scene& scene, const Transport& t) {
    const SceneObject& o = object_named(scene, "ceiling");
    const Chart& c = scene.chart_of(scene.faces[size_t(o.first_face)]);
    double sum = 0.0, moment = 0.0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        const int i = int(k % c.texels.width), j = int(k / c.texels.width);
        const Vec3 mid = scene.normalisation.to_user(c.texels.to_plane(Vec2(i + 0.5, j + 0.5)));
        const double p = t.texture_maps().total[t.texture_maps().begin(c.id) + k].x;
        sum += p;
        moment += p * mid.x;
    }
    return moment / sum;
}

// A flat mirror given shading normals tilted by 15 degrees about z reflects the lamp 30
// degrees off the vertical, 1.1 m along the ceiling; about its plane's normal it would send
// the light straight back up (cycle 1 brings the lamp's light to the mirror, cycle 2 takes
// it on). Tolerance: half a texel (0.025) plus the bias of sharing each ray among the three
// directions around its own (the mean direction is kept, the landing point is not linear in
// it: about 0.01 here). Measured 0.016 off at l = 513, 0.007 at 129, 0.012 at 2049. The field
// turns that light (caustic_noise 0), and so does the lamp caustics' shot (the default),
// which traces each ray about its own normal.
TEST(SmoothField, MirrorReflectsAboutItsShadingNormal) {
    for (double noise : {0.0, PropagateParams().caustic_noise})
        for (double tilt_deg : {0.0, 15.0}) {
            Scene scene = tilted_mirror(0.15);
            const double a = tilt_deg * M_PI / 180.0;
            const Vec3 n(std::sin(a), std::cos(a), 0.0);
            Face& mirror = scene.faces[size_t(object_named(scene, "mirror").first_face)];
            // Shading normals are direction vectors: the same in the scene's normalised frame.
            if (tilt_deg > 0) mirror.vertex_normals.assign(mirror.vertices.size(), n);
            PropagateParams p = params(513, 128, 8, 2);
            p.caustic_noise = noise;
            const auto t = run_transport(scene, p);
            EXPECT_EQ(t->lamp_caustics().rays > 0, noise > 0 && tilt_deg > 0);
            EXPECT_LE(t->ledger().back().relative_error(), 1e-9)
                << format_ledger(t->ledger().back());
            const double want = predicted_centroid(n), got = measured_centroid(scene, *t);
            std::printf(
                "mirror with shading normals tilted %.0f deg (%s): the ceiling's light centred "
                "at x = %.4f (predicted %.4f)\n",
                tilt_deg, noise > 0 ? "traced on from the lamp" : "the field", got, want);
            EXPECT_NEAR(got, want, 0.035);
        }
}

// The form factor from a point to the rectangle [x1, x2] x [z1, z2] of a parallel plane at
// distance H that the point faces (coordinates from the point's foot on that plane): the
// corner terms of the closed form for a rectangle with a corner at the foot, odd in each side.
double parallel_rectangle_form_factor(double x1, double x2, double z1, double z2, double H) {
    if (x2 <= x1 || z2 <= z1) return 0.0;
    const auto corner = [H](double a, double b) {
        const double ra = std::sqrt(a * a + H * H), rb = std::sqrt(b * b + H * H);
        return (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb)) / (2.0 * M_PI);
    };
    return corner(x2, z2) - corner(x1, z2) - corner(x2, z1) + corner(x1, z1);
}

// The lamp's light that the flat 1 x 1 mirror of tilted_mirror(h) sends to the ceiling
// point (x, 2, z), W/m^2: the mirror image of the lamp (at y = -1.9) seen from there through
// the mirror's square and past the lamp's black back (at y = 1.9, in the way of what comes
// up under it). From the point, both squares project onto the image's plane as squares, so
// what it sees of the image is a rectangle less a rectangle, and E = rho_s L pi F exactly.
double mirrored_lamp_irradiance(double x, double z, double h, double L, double rho_s) {
    const double H = 2.0 + 1.9;              // the point above the image's plane
    const double t = 2.0 / H, tb = 0.1 / H;  // where the mirror's and the lamp's planes cut
    auto seen = [&](double lo, double hi, double c, double at) {  // [lo, hi] at `at`, on the image
        return std::pair{c + (lo - c) / at, c + (hi - c) / at};
    };
    const auto [mx0, mx1] = seen(-0.5, 0.5, x, t);
    const auto [mz0, mz1] = seen(-0.5, 0.5, z, t);
    const auto [bx0, bx1] = seen(-h, h, x, tb);
    const auto [bz0, bz1] = seen(-h, h, z, tb);
    const double x0 = std::max(-h, mx0), x1 = std::min(h, mx1);
    const double z0 = std::max(-h, mz0), z1 = std::min(h, mz1);
    const double open = parallel_rectangle_form_factor(x0 - x, x1 - x, z0 - z, z1 - z, H);
    const double shut =
        parallel_rectangle_form_factor(std::max(x0, bx0) - x, std::min(x1, bx1) - x,
                                       std::max(z0, bz0) - z, std::min(z1, bz1) - z, H);
    return rho_s * L * M_PI * (open - shut);
}

// The lamps' direct light on a smooth surface is traced on from the lamp in cycle 1
// (lamp_caustics.hpp): a flat mirror given shading normals equal to its plane's is such a
// surface, and what it sends to the ceiling is the lamp's mirror image, exact in closed form
// per point (mirrored_lamp_irradiance, integrated over each texel by 8 x 8 midpoints). After
// one cycle the ceiling holds only that light (rho_d of it). The power the lamp sends to the
// mirror, Phi = L pi (integral over the lamp of the point's form factor to the mirror; 64 x 64
// midpoints), is known too. Tolerances:
// - the rays' estimate of Phi within 0.5 % (millions of stratified rays: their sampling
//   error is far smaller); the field's (what it hands over) within 3 %, the field's form
//   factors' bound (TransportFormFactor);
// - the shot carries the handed power, so the ceiling holds the closed form times
//   handed / Phi: its total within 0.5 % of that, and per lit texel (a tenth of the peak or
//   more) RMS within 3 %: the pilot counts the shot's rays for 2 % noise
//   (PropagateParams::caustic_noise), weighted by the texels' light, as if the rays were
//   independent; unweighted over these texels the dimmer ones count more, hence the margin.
// Reflected about the wrong normal, weighted without the lamp's cosine, or landing a texel
// off, it fails by far more.
TEST(SmoothField, LampsLightOnASmoothMirrorLandsAsItsImageSays) {
    const double h = 0.3, L = 10.0, rho_s = 0.9, rho_d = 0.5;
    Scene scene = tilted_mirror(h);
    Face& mirror = scene.faces[size_t(object_named(scene, "mirror").first_face)];
    mirror.vertex_normals.assign(mirror.vertices.size(), Vec3(0, 1, 0));
    const auto t = run_transport(scene, params(513, 128, 8, 1));
    ASSERT_GT(t->lamp_caustics().rays, 0);
    EXPECT_LE(t->ledger().back().relative_error(), 1e-9) << format_ledger(t->ledger().back());
    double phi = 0.0;
    for (int m = 0; m < 64 * 64; ++m) {
        const double x = -h + 2.0 * h * (m % 64 + 0.5) / 64, z = -h + 2.0 * h * (m / 64 + 0.5) / 64;
        phi += L * M_PI *
               parallel_rectangle_form_factor(-0.5 - x, 0.5 - x, -0.5 - z, 0.5 - z, 1.9) *
               (2.0 * h / 64) * (2.0 * h / 64);
    }
    const double handed = t->lamp_caustics().handed.x * t->to_user_power();
    const double estimated = t->lamp_caustics().estimated.x * t->to_user_power();
    const SceneObject& o = object_named(scene, "ceiling");
    const Chart& c = scene.chart_of(scene.faces[size_t(o.first_face)]);
    const double s = scene.normalisation.scale, full = c.texels.size * c.texels.size;
    std::vector<double> want, got;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        if (c.texel_area[k] < 0.999 * full) continue;  // the ceiling's rim: none here
        const int i = int(k % c.texels.width), j = int(k / c.texels.width);
        double E = 0.0;
        for (int m = 0; m < 64; ++m) {
            const Vec3 p = scene.normalisation.to_user(
                c.texels.to_plane(Vec2(i + (m % 8 + 0.5) / 8, j + (m / 8 + 0.5) / 8)));
            E += mirrored_lamp_irradiance(p.x, p.z, h, L, rho_s) / 64.0;
        }
        want.push_back(rho_d * E * c.texel_area[k] / (s * s));
        got.push_back(t->texture_maps().total[t->texture_maps().begin(c.id) + k].x *
                      t->to_user_power());
    }
    double sum_want = 0.0, sum_got = 0.0, peak = 0.0;
    for (size_t k = 0; k < want.size(); ++k) {
        sum_want += want[k];
        sum_got += got[k];
        peak = std::max(peak, want[k]);
    }
    double sq = 0.0, worst = 0.0;
    int lit = 0;
    for (size_t k = 0; k < want.size(); ++k) {
        if (want[k] < 0.1 * peak) continue;
        const double e = got[k] / (want[k] * handed / phi) - 1.0;
        sq += e * e;
        worst = std::max(worst, std::abs(e));
        ++lit;
    }
    const double rms = std::sqrt(sq / lit);
    std::printf(
        "lamp's light on a smooth flat mirror: the rays' estimate %.5f and the field's %.5f of "
        "the closed form; on the ceiling: total %.5f of the closed form x handed, %d lit "
        "texels RMS %.4f, worst %.4f (%lld rays)\n",
        estimated / phi, handed / phi, sum_got / (sum_want * handed / phi), lit, rms, worst,
        (long long)t->lamp_caustics().rays);
    EXPECT_NEAR(estimated / phi, 1.0, 0.005);
    EXPECT_NEAR(handed / phi, 1.0, 0.03);
    EXPECT_NEAR(sum_got / (sum_want * handed / phi), 1.0, 0.005);
    EXPECT_LE(rms, 0.03);
}

// The path-traced reference turns at a smooth mirror about the shading normal too (eye
// paths by specular_turn, as the field and raytrace mode do): the same mirror with normals
// tilted 15 degrees under a 1 m lamp; the ceiling's radiance, traced straight up from just
// under it on a 61 x 15 grid, is centred where the closed form puts the reflection.
// Tolerance: a quarter of the grid step (0.025), against 1.2 m between the tilted and the
// flat reflection.
TEST(SmoothField, PathTracerMirrorReflectsAboutItsShadingNormal) {
    Scene scene = tilted_mirror(0.5);
    // A dark ceiling: what it sends back to itself through the mirror is left out.
    scene.materials[size_t(scene.faces[size_t(object_named(scene, "ceiling").first_face)].material)]
        .diffuse = Rgb(0.02);
    const double a = 15.0 * M_PI / 180.0;
    const Vec3 n(std::sin(a), std::cos(a), 0.0);
    Face& mirror = scene.faces[size_t(object_named(scene, "mirror").first_face)];
    mirror.vertex_normals.assign(mirror.vertices.size(), n);
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    double sum = 0.0, moment = 0.0, sum_want = 0.0, moment_want = 0.0;
    for (int i = 0; i < 61; ++i)
        for (int k = 0; k < 15; ++k) {
            const double x = -3.0 + 0.1 * i, z = -1.4 + 0.2 * k;
            const Vec3 o = scene.normalisation.to_normalised(Vec3(x, 1.99, z));
            Pcg32 rng(7, uint64_t(i * 15 + k));
            double L = 0.0;
            for (int s = 0; s < 4096; ++s) L += tracer.radiance(o, Vec3(0, 1, 0), rng).x;
            sum += L;
            moment += L * x;
            // What the eye sees there: the ceiling's irradiance through the mirror, the
            // mirror's points (midpoints of 40 x 40) that turn the view onto the lamp, by
            // cos at x, cos at the mirror's plane and 1 / r^2, unless the lamp's back is in
            // the way.
            const Vec3 c(x, 2.0, z);
            double E = 0.0;
            for (int j = 0; j < 1600; ++j) {
                const Vec3 b(-0.5 + (j % 40 + 0.5) / 40, 0.0, -0.5 + (j / 40 + 0.5) / 40);
                const Vec3 under = c + 0.05 * (b - c);  // at the lamp's height: its back
                if (std::abs(under.x) < 0.5 && std::abs(under.z) < 0.5) continue;
                const Vec3 d = glm::normalize(b - c);
                const Vec3 u = d - 2.0 * glm::dot(d, n) * n;
                if (u.y <= 0.0) continue;
                const Vec3 hit = b + u * (1.9 / u.y);
                if (std::abs(hit.x) > 0.5 || std::abs(hit.z) > 0.5) continue;
                const double r2 = glm::dot(b - c, b - c);
                E += (-d.y) * (-d.y) / r2;
            }
            sum_want += E;
            moment_want += E * x;
        }
    const double want = moment_want / sum_want, got = moment / sum;
    std::printf(
        "path tracer, mirror with normals tilted 15 deg: ceiling centred at x = %.4f "
        "(predicted %.4f)\n",
        got, want);
    EXPECT_NEAR(got, want, 0.025);
}

// A closed 2 m room under a 0.4 m lamp, with `materials` besides "white" and "lamp" and
// `objects` besides its walls and lamp (JSON fragments).
Scene closed_room(const std::string& materials, const std::string& objects) {
    return scene_from_json(R"({
      "materials": {"white": {"diffuse": [0.5, 0.5, 0.5]}, "lamp": {"emission": [10, 10, 10]},
                    )" + materials +
                           R"(},
      "settings": {"texel_size": 0.1},
      "objects": [
        {"type": "box", "material": "white", "min": [-1, 0, -1], "max": [1, 2, 1],
         "flip": true},
        {"type": "polygon", "material": "lamp",
         "vertices": [[-0.2, 1.99, -0.2], [0.2, 1.99, -0.2], [0.2, 1.99, 0.2], [-0.2, 1.99, 0.2]]},
        )" + objects + "]}");
}

// The room with a smooth glass ball (absorbing), a smooth mirror ball, a smooth glass torus
// (a surface with two sheets facing the same way along many directions: each sheet is its
// own layer, surface_specular.cpp) and a faceted mirror ball (flat-shaded: a source per face,
// but a lens for the lamp caustics' shot, lamp_caustics.hpp caustic_faces).
Scene smooth_room() {
    return closed_room(
        R"("glass": {"dielectric": {"ior": 1.5, "absorption": [0.3, 0.1, 0.0]}},
           "mirror": {"specular": [0.9, 0.9, 0.9]})",
        R"({"type": "sphere", "material": "glass", "center": [-0.4, 0.5, 0], "radius": 0.3,
            "subdivisions": 2},
           {"type": "sphere", "material": "mirror", "center": [0.4, 0.5, 0.2], "radius": 0.3,
            "subdivisions": 2},
           {"type": "sphere", "material": "mirror", "center": [-0.5, 1.4, -0.5], "radius": 0.2,
            "subdivisions": 1, "smooth": false},
           {"type": "mesh", "file": ")" +
            test::source_path("scenes/meshes/torus.obj") +
            R"(", "material": "glass", "scale": 0.3, "rotate_x_deg": 60, "translate": [0, 1.3, 0]})");
}

// Every watt is booked in every cycle, with perturbation, super-sampling and the filter,
// whether the field carries the lamp's light on from the smooth objects or the lamp
// caustics' shot does (lamp_caustics.hpp; it takes exactly what the field handed over).
TEST(SmoothField, LedgerClosesWithSmoothGlassAndMirror) {
    const Scene scene = smooth_room();
    for (double noise : {0.0, PropagateParams().caustic_noise}) {
        PropagateParams p = params(129, 32, 8, 3);
        p.perturbations = 1;
        p.supersample = 2;
        p.filter_sigma = 0.7;
        p.caustic_noise = noise;
        const auto t = run_transport(scene, p);
        EXPECT_EQ(t->lamp_caustics().rays > 0, noise > 0);
        for (const LedgerEntry& e : t->ledger())
            EXPECT_LE(e.relative_error(), 1e-9) << format_ledger(e);
    }
}

// Which faces hand the lamps' light to the shot (caustic_faces): every face of a smooth
// mirror or glass object, and the specular faces of a flat-shaded one whose specular faces
// lie in more than one plane (a faceted ball, a glass box); not a mirror of one plane, even
// two-sided (a face and its twin), nor a diffuse object.
TEST(SmoothField, CurvedMirrorsAndGlassHandTheLampsLightToTheShot) {
    const Scene scene = closed_room(
        R"("glass": {"dielectric": {"ior": 1.5}}, "mirror": {"specular": [0.9, 0.9, 0.9]})",
        R"({"type": "sphere", "material": "glass", "center": [-0.5, 0.5, 0], "radius": 0.2,
            "subdivisions": 1, "name": "smooth glass"},
           {"type": "sphere", "material": "mirror", "center": [0.5, 0.5, 0], "radius": 0.2,
            "subdivisions": 1, "smooth": false, "name": "faceted mirror"},
           {"type": "box", "material": "glass", "min": [-0.2, 0.1, 0.3], "max": [0.2, 0.3, 0.5],
            "name": "glass box"},
           {"type": "polygon", "material": "mirror", "two_sided": true, "name": "flat mirror",
            "vertices": [[-0.9, 0.5, -0.9], [-0.5, 0.5, -0.9], [-0.5, 1.0, -0.9], [-0.9, 1.0, -0.9]]})");
    const auto t = run_transport(scene, params(33, 16, 4, 1));
    const std::vector<uint8_t> hand =
        caustic_faces(scene, find_smooth_surfaces(scene, t->directions(), t->coverage()));
    for (const Face& f : scene.faces) {
        const std::string& name = scene.objects[size_t(f.object)].name;
        const bool want = name == "smooth glass" || name == "faceted mirror" || name == "glass box";
        EXPECT_EQ(hand[size_t(f.id)] != 0, want) << name << " face " << f.id;
    }
}

// A smooth surface carries light wherever it has rays, not where one facet has: a ball of
// 5,120 facets, most smaller than a ray at N = 32, loses nothing for want of a ray
// (lost.grazing_mirror; 9 % of the emission when facets carried their own light).
TEST(SmoothField, FineBallLosesNothingForWantOfAFacetsRay) {
    const Scene scene =
        closed_room(R"("glass": {"dielectric": {"ior": 1.5}})",
                    R"({"type": "sphere", "material": "glass", "center": [0, 0.5, 0], "radius": 0.3,
            "subdivisions": 4})");
    const auto t = run_transport(scene, params(129, 32, 8, 3));
    const LedgerEntry& e = t->ledger().back();
    EXPECT_LE(e.relative_error(), 1e-9) << format_ledger(e);
    EXPECT_EQ(e.lost.grazing_mirror, Rgb(0.0)) << format_ledger(e);
}

// The smooth surfaces' sources are made per chunk and gathered in source order: one thread
// or two, the same maps, bit for bit.
TEST(SmoothField, SameMapsOnOneAndTwoThreads) {
    const Scene scene = smooth_room();
    PropagateParams p = params(129, 32, 8, 3);
    p.perturbations = 1;
    p.supersample = 2;
    std::unique_ptr<Transport> one, two;
    {
        ThreadLimit limit(1);
        one = run_transport(scene, p);
    }
    {
        ThreadLimit limit(2);
        two = run_transport(scene, p);
    }
    ASSERT_GT(one->lamp_caustics().rays, 0);  // the lamp caustics' shot too
    ASSERT_EQ(one->texture_maps().total, two->texture_maps().total);
    ASSERT_EQ(one->specular_maps().total, two->specular_maps().total);
    ASSERT_EQ(one->specular_maps().unshot, two->specular_maps().unshot);
}

}  // namespace
}  // namespace vlf
