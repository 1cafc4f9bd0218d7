// Glass and smooth shading normals in the walkthrough's modes (render/render.hpp, issue 14
// items 3 and 5): raytrace through glass slabs against the Fresnel series in closed form, a
// smooth sphere mirror's reflection against its interpolated and its analytic normal, the
// scene file's "smooth" key (scene_loader.cpp) and the vertex normals' round trip through
// geometry.bin. Suites: RenderGlass (rendering), SceneSmooth (loading), BakeSmooth (the bake).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "test_util.hpp"
#include "vlf/bake/geometry_bin.hpp"
#include "vlf/bake/scene_json.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/fresnel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/render/render.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

// The message of the SceneError that loading `json` throws ("" when it loads).
std::string load_error(const std::string& json, const std::string& dir = ".") {
    try {
        load_scene_from_string(json, "t.json", dir);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// A bake of `scene` whose only light is the given radiance on every texel of the charts of
// `material`'s faces (a function of the texel centre, user units): a lit backdrop.
template <class Radiance>
Bake lit_bake(const Scene& scene, int material, Radiance radiance) {
    Bake b = test::scene_only_bake(scene);
    for (const Chart& c : scene.charts) {
        if (c.material != material) continue;
        for (int j = 0; j < c.texels.height; ++j)
            for (int i = 0; i < c.texels.width; ++i) {
                const Vec3 centre = c.texels.to_plane(Vec2(i + 0.5, j + 0.5));
                b.lightmap_radiance[b.texel_offset[size_t(c.id)] + size_t(j) * c.texels.width +
                                    size_t(i)] = radiance(scene.normalisation.to_user(centre));
            }
    }
    return b;
}

int material_index(const Scene& s, const std::string& name) {
    for (size_t k = 0; k < s.materials.size(); ++k)
        if (s.materials[k].name == name) return int(k);
    ADD_FAILURE() << "no material " << name;
    return 0;
}

// Radiance along one ray given in user units, in raytrace mode.
Rgb raytraced(const Renderer& r, const Scene& s, const Vec3& origin_user, const Vec3& dir) {
    RenderSettings rs;
    rs.mode = RenderMode::Raytrace;
    PrimaryRay ray;
    ray.origin = s.normalisation.to_normalised(origin_user);
    ray.dir = glm::normalize(dir);
    return r.shade({ray}, rs)[0];
}

// A glass slab 0.2 thick (z from 0.9 to 1.1 before its rotation about y) in front of a lamp
// wall at z = 2 facing the eye at the origin.
std::string slab_scene(double rotate_y_deg, double absorption) {
    return fmt::format(R"({{
  "materials": {{"glass": {{"dielectric": {{"ior": 1.5, "absorption": [{0}, {0}, {0}]}}}},
                 "wall": {{"emission": [1, 1, 1]}}}},
  "objects": [
    {{"type": "box", "min": [-0.5, -0.5, 0.9], "max": [0.5, 0.5, 1.1], "rotate_y_deg": {1},
      "material": "glass"}},
    {{"type": "polygon", "material": "wall",
      "vertices": [[-2, -2, 2], [-2, 2, 2], [2, 2, 2], [2, -2, 2]]}}]
}})",
                       absorption, rotate_y_deg);
}

// Normal incidence: the eye sees the wall through two interfaces of R = ((n-1)/(n+1))^2
// and the light reflected back and forth inside, each crossing attenuated by a = exp(-s d).
// The closed form of the series is T = (1-R)^2 a / (1 - R^2 a^2). The recursion follows a
// branch while its throughput is >= 1e-4 (render.cpp kMinBranchWeight): here the direct
// path and the one with two internal reflections, T_2 = (1-R)^2 a (1 + R^2 a^2), exactly;
// the next term, R^4 a^4 relative, is cut. One interface's factor alone, (1-R)^2 a, would
// be 0.16 % low: the test tells the three apart.
TEST(RenderGlass, SlabAtNormalIncidenceTransmitsTheFresnelSeries) {
    for (const double a : {1.0, 0.5}) {
        const double sigma = -std::log(a) / 0.2;  // per user unit; the slab is 0.2 thick
        const Scene s = load_scene_from_string(slab_scene(0, sigma), "slab.json", ".");
        const Rgb wall(1.0, 2.0, 4.0);
        const Bake b = lit_bake(s, material_index(s, "wall"), [&](const Vec3&) { return wall; });
        const Renderer r(b);
        const Rgb L = raytraced(r, s, Vec3(0.01, 0.02, 0), Vec3(0, 0, 1));
        const double R = (0.5 / 2.5) * (0.5 / 2.5);
        const double single = (1 - R) * (1 - R) * a;
        const double two = single * (1 + R * R * a * a);
        const double closed = single / (1 - R * R * a * a);
        for (int c = 0; c < 3; ++c) {
            const double T = L[c] / wall[c];
            EXPECT_NEAR(T, two, 1e-12 * two) << "a=" << a << " channel " << c;
            EXPECT_NEAR(T, closed, 1.01 * std::pow(R * a, 4) * closed);
            EXPECT_GT(T - single, 0.5 * single * R * R * a * a);
        }
    }
}

// Oblique incidence (the slab turned 30 degrees about y): Snell shifts the ray sideways, so
// on a wall whose radiance grows with x the eye sees L(x_k) for the exit point x_k of the
// path with 2k internal reflections, weighted (1-R)^2 R^{2k} (R unpolarised at 30 degrees,
// the same inside by reciprocity). Straight through (no refraction) it would see L(0).
TEST(RenderGlass, ObliqueSlabShiftsTheRayAsSnellSays) {
    const Scene s = load_scene_from_string(slab_scene(30, 0.0), "slab.json", ".");
    auto wall = [](const Vec3& p) { return Rgb(10.0 + 4.0 * p.x, 10.0, 10.0 - 4.0 * p.x); };
    const Bake b = lit_bake(s, material_index(s, "wall"), wall);
    const Renderer r(b);
    const Rgb L = raytraced(r, s, Vec3(0.0), Vec3(0, 0, 1));

    // The geometry in user units: the front face's outward normal, the entry point.
    const double phi = 30.0 * kPi / 180.0, c = std::cos(phi), sn = std::sin(phi);
    const Vec3 front(-sn, 0.0, -c);
    const Vec3 entry(0.0, 0.0, 1.0 - 0.1 / c);
    const double n = 1.5, d = 0.2;
    const double sin_t = sn / n, cos_t = std::sqrt(1 - sin_t * sin_t);
    // Inside, the ray runs at theta_t to the inward normal -front, tilted towards +x along
    // the face: u is the unit tangent in the plane of incidence.
    const Vec3 u = glm::normalize(Vec3(0, 0, 1) - glm::dot(Vec3(0, 0, 1), front) * front);
    const double R = fresnel_dielectric(c, 1.0 / n);
    EXPECT_NEAR(fresnel_dielectric(cos_t, n), R, 1e-12);
    Rgb expect(0.0);
    for (int k = 0; k <= 1; ++k) {
        const Vec3 exit = entry + (2 * k + 1) * d * (sin_t / cos_t) * u - d * front;
        expect += (1 - R) * (1 - R) * std::pow(R, 2 * k) * wall(exit);
    }
    // Rays leave a surface 1e-5 normalised units off it (render.cpp kEps, here 3e-5 user
    // units), which moves the exit points by as much: 1e-4 in x, 4e-4 in L. The second
    // term alone is 0.016, the shift's effect 0.14.
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(L[ch], expect[ch], 4e-4) << ch;
    EXPECT_GT((1 - R) * (1 - R) * R * R * 10.0, 30 * 4e-4);
    // The direct path's exit: the textbook lateral shift d sin(theta - theta_t) / cos(theta_t).
    const double shift = d * std::sin(phi - std::asin(sin_t)) / cos_t;
    EXPECT_NEAR((entry + d * (sin_t / cos_t) * u - d * front).x, shift, 1e-12);
    // Straight through would read the wall at x = 0: far off.
    EXPECT_GT(std::abs(L.x - (1 - R) * (1 - R) * wall(Vec3(0.0)).x), 100e-6 * L.x);
}

// Glass only redistributes light: with the wall the only light (radiance 1), what the eye
// sees through a slab turned 50 degrees, across its faces, edges and narrow sides (where
// rays meet total internal reflection), stays finite and in [0, 1].
TEST(RenderGlass, RaytraceThroughGlassNeverAddsLight) {
    const Scene s = load_scene_from_string(slab_scene(50, 0.0), "slab.json", ".");
    const Bake b = lit_bake(s, material_index(s, "wall"), [](const Vec3&) { return Rgb(1.0); });
    const Renderer r(b);
    for (int k = 0; k < 40; ++k) {
        const double x = -0.6 + 0.03 * k;
        const Rgb L = raytraced(r, s, Vec3(0.0), Vec3(x, 0.05, 1.0));
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(L[c]));
            EXPECT_LE(L[c], 1.0 + 1e-12) << x;
            EXPECT_GE(L[c], 0.0);
        }
    }
}

// A mirror sphere of 80 facets in front of a wall lit with radiance (5 + x, 5 + y, 1) (user
// units): the colour of the reflection says where the reflected ray met the wall. Smooth,
// the ray aimed near a vertex reflects about the barycentric mix of the vertex normals (to
// rounding), which for vertices on the sphere is the sphere's normal at the hit point's
// direction from the centre; flat, about the facet's normal, degrees off it.
TEST(RenderGlass, SmoothSphereMirrorReflectsAboutTheSphereNormal) {
    for (const bool smooth : {true, false}) {
        const std::string json = fmt::format(R"({{
  "materials": {{"mirror": {{"specular": [0.9, 0.9, 0.9]}}, "wall": {{"emission": [1, 1, 1]}}}},
  "objects": [
    {{"type": "sphere", "radius": 1, "subdivisions": 1, "material": "mirror", "smooth": {}}},
    {{"type": "polygon", "material": "wall",
      "vertices": [[-20, -20, -3], [20, -20, -3], [20, 20, -3], [-20, 20, -3]]}}]
}})",
                                             smooth ? "true" : "false");
        const Scene s = load_scene_from_string(json, "sphere.json", ".");
        auto wall = [](const Vec3& p) { return Rgb(5.0 + p.x, 5.0 + p.y, 1.0); };
        const Bake b = lit_bake(s, material_index(s, "wall"), wall);
        const Renderer r(b);
        // The facet facing the eye (at z = -2.5) most squarely, a point near its vertex 0.
        const int mirror = material_index(s, "mirror");
        const Face* best = nullptr;
        for (const Face& f : s.faces)
            if (f.material == mirror && (!best || f.normal.z < best->normal.z)) best = &f;
        ASSERT_NE(best, nullptr);
        EXPECT_EQ(best->vertex_normals.size(), smooth ? 3u : 0u);
        const Normalisation& nm = s.normalisation;
        const Vec3 q = nm.to_user(0.9 * best->vertices[0] + 0.07 * best->vertices[1] +
                                  0.03 * best->vertices[2]);
        const Vec3 eye(0.0, 0.0, -2.5);
        const Vec3 dir = glm::normalize(q - eye);
        const Rgb L = raytraced(r, s, eye, dir);
        const Vec3 seen(L.x / 0.9 - 5.0, L.y / 0.9 - 5.0, -3.0);  // where it met the wall
        ASSERT_NEAR(L.z, 0.9, 1e-9);
        auto wall_hit = [&](const Vec3& normal) {
            const Vec3 out = reflect(dir, normal);
            return q + ((-3.0 - q.z) / out.z) * out;
        };
        const Vec3 interpolated =
            glm::normalize(0.9 * glm::normalize(s.normalisation.to_user(best->vertices[0])) +
                           0.07 * glm::normalize(s.normalisation.to_user(best->vertices[1])) +
                           0.03 * glm::normalize(s.normalisation.to_user(best->vertices[2])));
        const Vec3 analytic = glm::normalize(q);  // the sphere's centre is the origin
        const double off = std::acos(std::min(1.0, glm::dot(analytic, best->normal)));
        EXPECT_GT(off * 180 / kPi, 5.0) << "the facet's normal is degrees off the sphere's";
        EXPECT_LT(std::acos(std::min(1.0, glm::dot(analytic, interpolated))) * 180 / kPi, 0.7);
        const Vec3 expect = wall_hit(smooth ? interpolated : best->normal);
        // Rays leave the mirror 1e-5 normalised units (3e-4 user units here) off it.
        EXPECT_NEAR(seen.x, expect.x, 3e-3) << smooth;
        EXPECT_NEAR(seen.y, expect.y, 3e-3) << smooth;
        const Vec3 other = wall_hit(smooth ? best->normal : interpolated);
        EXPECT_GT(glm::length(seen - other), 0.1) << smooth;
        const Vec3 true_sphere = wall_hit(analytic);
        if (smooth) {
            EXPECT_LT(glm::length(seen - true_sphere), 0.1 * glm::length(other - true_sphere));
        }
    }
}

// Rays mode reads a smooth surface's light from the rays of the whole surface around a point,
// not of its facet only (render.cpp Impl::sample; docs/rendering.md §6.1). A smooth mirror
// of two parallel sheets, y = 0 over 0 <= x, z <= 1 and y = -0.3 over 0 <= x <= 2, cut into
// triangles narrower than a ray (1/30 against rays 0.038 apart); the upper sheet has a
// square hole, and in the hole lie a coplanar patch of another mirror object and, 0.01
// below it, a facet of the sheets' own object that faces down. The stored rays are written
// by hand: each sample is the value of a linear function of where its ray meets the face,
// plus 10 on the lower sheet, 100 on the other object and 1000 on the downward face.
// - Farther than three rays from every rim, bilinear interpolation reproduces the linear
//   function exactly, so rays mode must give it to float precision: with a facet's own rays
//   it gives a patchwork of the few rays each facet has (and where a facet has none, the
//   traced mirror's black), and with the rays of the wrong sheet 10 more.
// - Next to the hole, where some of the four nearest rays meet only the patch, the downward
//   facet or the lower sheet, none of those may be taken: the weights renormalised over the
//   rays of the sheet err by at most the function's change across a ray's diagonal, where
//   taking any of them adds at least a tenth of 10.
// Texture mode traces a smooth mirror (VLF §6.2 by §6.3): it gives what raytrace mode gives.
TEST(RenderGlass, SmoothSurfaceIsLookedUpAcrossItsFacets) {
    test::TempDir dir("smooth_sheets");
    const int cells = 30, hole0 = 13, hole1 = 17;  // the hole: cells [13, 17)^2 of the upper sheet
    auto in_hole = [&](int a, int c) { return a >= hole0 && a < hole1 && c >= hole0 && c < hole1; };
    // Appends to `obj`, whose vertices so far number `vertices`, the cells of a sheet at
    // height y with `columns` cells along x that `take` keeps; its faces look up (normal 1)
    // or down (normal 2).
    auto sheet = [&](std::string& obj, int& vertices, double y, int columns, auto take, bool up) {
        for (int a = 0; a < columns; ++a)
            for (int c = 0; c < cells; ++c) {
                if (!take(a, c)) continue;
                const double x0 = double(a) / cells, x1 = double(a + 1) / cells;
                const double z0 = double(c) / cells, z1 = double(c + 1) / cells;
                obj += fmt::format("v {} {} {}\nv {} {} {}\nv {} {} {}\nv {} {} {}\n", x0, y, z0,
                                   x0, y, z1, x1, y, z0, x1, y, z1);
                const int v = vertices + 1;
                // Counter-clockwise seen from +y: the faces look up.
                if (up)
                    obj += fmt::format("f {0}//1 {1}//1 {2}//1\nf {2}//1 {1}//1 {3}//1\n", v, v + 1,
                                       v + 2, v + 3);
                else
                    obj += fmt::format("f {0}//2 {2}//2 {1}//2\nf {2}//2 {3}//2 {1}//2\n", v, v + 1,
                                       v + 2, v + 3);
                vertices += 4;
            }
    };
    auto all = [](int, int) { return true; };
    std::string sheets = "vn 0 1 0\nvn 0 -1 0\n", patch = "vn 0 1 0\n";
    int sheet_vertices = 0, patch_vertices = 0;
    sheet(
        sheets, sheet_vertices, 0.0, cells, [&](int a, int c) { return !in_hole(a, c); }, true);
    sheet(sheets, sheet_vertices, -0.3, 2 * cells, all, true);
    sheet(sheets, sheet_vertices, -0.01, cells, in_hole, false);
    sheet(patch, patch_vertices, 0.0, cells, in_hole, true);
    dir.write("sheets.obj", sheets);
    dir.write("patch.obj", patch);
    const Scene s = load_scene_from_string(
        R"({"materials": {"mirror": {"specular": [1, 1, 1]}, "lamp": {"emission": [1, 1, 1]}},
            "objects": [{"type": "mesh", "file": "sheets.obj", "material": "mirror"},
                        {"type": "mesh", "file": "patch.obj", "material": "mirror"},
                        {"type": "polygon", "material": "lamp",
                         "vertices": [[0, 1.8, 0], [2, 1.8, 0], [2, 1.8, 1], [0, 1.8, 1]]}]})",
        "sheets.json", dir.path.string());
    int downward = 0;
    for (const Face& f : s.faces) downward += f.object == 0 && f.normal.y < 0.0;
    ASSERT_EQ(downward, 2 * (hole1 - hole0) * (hole1 - hole0));
    const Normalisation& nm = s.normalisation;
    auto linear = [](const Vec3& p) {  // p in user units
        return Rgb(1.0 + p.x, 2.0 + p.z, 3.0 + p.x + 2.0 * p.z);
    };
    auto value = [&](const Face& f, const Vec3& p) {
        if (f.object == 1) return linear(p) + Rgb(100.0);
        if (f.normal.y < 0.0) return linear(p) + Rgb(1000.0);
        return p.y > -0.15 ? linear(p) : linear(p) + Rgb(10.0);
    };
    Bake b = test::scene_only_bake(s);
    const int l = 33, N = 80;
    b.directions = DirectionSet(l);
    RayImages& rays = b.rays;
    rays.directions = l;
    rays.resolution = N;
    rays.tile = 4;
    rays.pixel_offset.assign(1, 0);
    const int mirror = material_index(s, "mirror");
    for (int d = 0; d < l; ++d) {
        const Mat3 R = rotation_to_z(b.directions.direction(d));
        // Per pixel of PSF d, its samples in ascending face order: each mirror face is
        // rasterised at the pixel centres inside it.
        std::vector<std::vector<std::pair<int, Rgb>>> pixels(size_t(N) * N);
        for (const Face& f : s.faces) {
            const Vec3 n = R * f.normal;
            if (f.material != mirror || n.z == 0.0) continue;
            const Vec3 v[3] = {R * f.vertices[0], R * f.vertices[1], R * f.vertices[2]};
            auto pixel = [&](double q) { return (q + 1.0) * N * 0.5 - 0.5; };
            const double lo_x = std::min({v[0].x, v[1].x, v[2].x}),
                         hi_x = std::max({v[0].x, v[1].x, v[2].x});
            const double lo_y = std::min({v[0].y, v[1].y, v[2].y}),
                         hi_y = std::max({v[0].y, v[1].y, v[2].y});
            for (int j = std::max(0, int(std::ceil(pixel(lo_y))));
                 j <= std::min(N - 1, int(std::floor(pixel(hi_y)))); ++j)
                for (int i = std::max(0, int(std::ceil(pixel(lo_x))));
                     i <= std::min(N - 1, int(std::floor(pixel(hi_x)))); ++i) {
                    const double px = ray_coord(i, N), py = ray_coord(j, N);
                    auto edge = [&](const Vec3& a, const Vec3& c) {
                        return (c.x - a.x) * (py - a.y) - (c.y - a.y) * (px - a.x);
                    };
                    const double e0 = edge(v[0], v[1]), e1 = edge(v[1], v[2]),
                                 e2 = edge(v[2], v[0]);
                    if (!((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0)))
                        continue;
                    const Vec3 at = nm.to_user(PlaneInPsf(f, R, N).point(i, j));
                    pixels[size_t(j) * N + size_t(i)].emplace_back(f.id, value(f, at));
                }
        }
        for (const auto& samples : pixels) {
            for (const auto& [face, L] : samples) {
                rays.face.push_back(face);
                rays.radiance.push_back(RgbF(L));
            }
            rays.pixel_offset.push_back(rays.face.size());
        }
    }
    const Renderer r(b);
    const double spacing = (2.0 / N) / nm.scale;  // between rays, user units
    const double margin = 3.0 * spacing;
    ASSERT_LT(margin, 0.15);
    const double h0 = double(hole0) / cells, h1 = double(hole1) / cells;
    // How far p lies outside the hole's square (Chebyshev), negative inside.
    auto outside_hole = [&](double x, double z) {
        return std::max({h0 - x, x - h1, h0 - z, z - h1});
    };
    const Vec3 eye(1.0, 1.5, 0.5);
    std::vector<PrimaryRay> primary;
    std::vector<Rgb> expect;
    for (int a = 0; a <= 40; ++a)
        for (int c = 0; c <= 20; ++c) {
            const double x = 0.15 + (2.0 - 0.3) * a / 40.0, z = 0.15 + 0.7 * c / 20.0;
            const bool up = x < 1.0;
            if ((x > 1.0 - margin && x < 1.0 + margin) || (up && outside_hole(x, z) < margin))
                continue;
            const Vec3 p(x, up ? 0.0 : -0.3, z);
            primary.push_back({nm.to_normalised(eye), glm::normalize(p - eye)});
            expect.push_back(up ? linear(p) : linear(p) + Rgb(10.0));
        }
    RenderSettings rs;
    rs.mode = RenderMode::Rays;
    const std::vector<Rgb> got = r.shade(primary, rs);
    double worst = 0.0;
    for (size_t k = 0; k < got.size(); ++k)
        for (int ch = 0; ch < 3; ++ch)
            worst = std::max(worst, std::abs(got[k][ch] / expect[k][ch] - 1.0));
    EXPECT_LT(worst, 1e-5) << "of " << got.size() << " points";
    // Next to the hole: per channel, the change of the linear function across a ray's
    // diagonal on the sheet (the ray spacing over the cosine of the steepest PSF direction
    // used), relative to its value.
    const Vec3 gradient[3] = {{1, 0, 0}, {0, 0, 1}, {1, 0, 2}};
    std::vector<PrimaryRay> near;
    std::vector<Vec3> at;
    for (int k = 0; k < 3; ++k) {
        const double off = (0.25 + 0.3 * k) * margin;  // beyond the hole's rim
        for (int t = 0; t <= 16; ++t) {
            const double u = h0 - off + (h1 - h0 + 2.0 * off) * t / 16.0;
            for (const Vec2& xz :
                 {Vec2(u, h0 - off), Vec2(u, h1 + off), Vec2(h0 - off, u), Vec2(h1 + off, u)}) {
                at.emplace_back(xz.x, 0.0, xz.y);
                near.push_back({nm.to_normalised(eye), glm::normalize(at.back() - eye)});
            }
        }
    }
    const std::vector<Rgb> rim = r.shade(near, rs);
    int over = 0;
    double worst_rim = 0.0;
    for (size_t k = 0; k < rim.size(); ++k) {
        const EnclosingTriangle e = b.directions.enclosing(-near[k].dir);
        double steepest = 1.0;
        for (int v = 0; v < 3; ++v)
            if (e.weight[v] > 0.0)
                steepest = std::min(steepest, std::abs(b.directions.direction(e.index[v]).y));
        const Rgb f = linear(at[k]);
        for (int ch = 0; ch < 3; ++ch) {
            const double bound = glm::length(gradient[ch]) * std::sqrt(2.0) * spacing / steepest;
            const double err = std::abs(rim[k][ch] - f[ch]);
            worst_rim = std::max(worst_rim, err / bound);
            over += err > bound;
        }
    }
    EXPECT_EQ(over, 0) << "of " << rim.size() << " points next to the hole; worst " << worst_rim
                       << " of the bound";
    rs.mode = RenderMode::Texture;
    const std::vector<Rgb> texture = r.shade(primary, rs);
    rs.mode = RenderMode::Raytrace;
    const std::vector<Rgb> traced = r.shade(primary, rs);
    for (size_t k = 0; k < got.size(); ++k) ASSERT_EQ(texture[k], traced[k]) << k;
}

// ---- loading ------------------------------------------------------------------------------

constexpr const char* kLamp = R"({"type": "polygon", "material": "lamp",
  "vertices": [[-3, 3, -3], [3, 3, -3], [3, 3, 3], [-3, 3, 3]]})";

std::string one_object(const std::string& object, const std::string& extra_materials = "") {
    return std::string(
               R"({"materials": {"lamp": {"emission": [1, 1, 1]}, "white": {"diffuse": [0.5, 0.5, 0.5]},
  "mirror": {"specular": [0.9, 0.9, 0.9]}, "glass": {"dielectric": {"ior": 1.5}})") +
           extra_materials + R"(}, "objects": [)" + object + ", " + kLamp + "]}";
}

TEST(SceneSmooth, SpheresAndCylinderWallsAreSmoothByDefault) {
    const Scene s = load_scene_from_string(
        one_object(R"({"type": "sphere", "center": [1, 0, 0], "radius": 0.5, "material": "white"},
                      {"type": "cylinder", "radius": 0.4, "height": 1, "segments": 12,
                       "center": [-1, -1, 0], "rotate_x_deg": 20, "material": "white"},
                      {"type": "box", "min": [0, -2, 0], "max": [1, -1.5, 1], "material": "white"})"),
        "t.json", ".");
    ASSERT_EQ(s.objects.size(), 4u);
    const SceneObject& sphere = s.objects[0];
    const Vec3 centre = s.normalisation.to_normalised(Vec3(1, 0, 0));
    for (int k = 0; k < sphere.face_count; ++k) {
        const Face& f = s.faces[size_t(sphere.first_face + k)];
        ASSERT_EQ(f.vertex_normals.size(), 3u);
        for (size_t v = 0; v < 3; ++v) {
            const Vec3 want = glm::normalize(f.vertices[v] - centre);
            EXPECT_NEAR(glm::length(f.vertex_normals[v] - want), 0.0, 1e-12);
            // At a vertex the shading normal is the vertex's.
            EXPECT_NEAR(glm::length(s.shading_normal(f, f.vertices[v]) - want), 0.0, 1e-12);
        }
    }
    // Cylinder: 12 wall quads (smooth, radial about the turned axis), 24 cap triangles (flat).
    const SceneObject& cyl = s.objects[1];
    ASSERT_EQ(cyl.face_count, 36);
    const double a = 20.0 * kPi / 180.0;
    const Vec3 axis(0.0, std::cos(a), std::sin(a));  // +y turned 20 degrees about x
    for (int k = 0; k < cyl.face_count; ++k) {
        const Face& f = s.faces[size_t(cyl.first_face + k)];
        if (k >= 12) {
            EXPECT_TRUE(f.vertex_normals.empty()) << k;
            EXPECT_EQ(s.shading_normal(f, f.vertices[0]), f.normal);
            continue;
        }
        ASSERT_EQ(f.vertex_normals.size(), 4u);
        for (const Vec3& n : f.vertex_normals) EXPECT_NEAR(glm::dot(n, axis), 0.0, 1e-12);
        // Mean value coordinates at the quad's centre: the radial direction half-way.
        Vec3 c(0.0);
        for (const Vec3& v : f.vertices) c += 0.25 * v;
        const Vec3 mid = glm::normalize(f.vertex_normals[0] + f.vertex_normals[3]);
        EXPECT_NEAR(glm::length(s.shading_normal(f, c) - mid), 0.0, 1e-12) << k;
        // Along an edge: the two ends' mix.
        const Vec3 e = 0.5 * (f.vertices[0] + f.vertices[1]);
        EXPECT_NEAR(glm::length(s.shading_normal(f, e) -
                                glm::normalize(f.vertex_normals[0] + f.vertex_normals[1])),
                    0.0, 1e-12);
    }
    for (int k = 0; k < s.objects[2].face_count; ++k)
        EXPECT_TRUE(s.faces[size_t(s.objects[2].first_face + k)].vertex_normals.empty());
}

TEST(SceneSmooth, FlipTwinsAndGlassKeepNormalsInFront) {
    const Scene s = load_scene_from_string(
        one_object(R"({"type": "sphere", "radius": 0.5, "subdivisions": 1, "material": "white",
                       "flip": true},
                      {"type": "sphere", "center": [2, 0, 0], "radius": 0.5, "subdivisions": 1,
                       "material": "glass"},
                      {"type": "sphere", "center": [-2, 0, 0], "radius": 0.5, "subdivisions": 1,
                       "material": "white", "two_sided": true, "smooth": false})"),
        "t.json", ".");
    for (const Face& f : s.faces) {
        for (const Vec3& n : f.vertex_normals) EXPECT_GT(glm::dot(n, f.normal), 0.5);
        if (f.twin < 0 || f.vertex_normals.empty()) continue;
        const Face& t = s.faces[size_t(f.twin)];
        ASSERT_EQ(t.vertex_normals.size(), f.vertex_normals.size());
        for (size_t v = 0; v < 3; ++v) EXPECT_EQ(t.vertex_normals[2 - v], -f.vertex_normals[v]);
        const Vec3 x = (f.vertices[0] + 2.0 * f.vertices[1] + 3.0 * f.vertices[2]) / 6.0;
        EXPECT_NEAR(glm::length(s.shading_normal(t, x) + s.shading_normal(f, x)), 0.0, 1e-12);
        if (t.inner) {
            EXPECT_EQ(s.shading_normal(t, x), -s.shading_normal(f, x));
        }
    }
    // The flipped sphere's normals point at its centre; the glass's inner twins too.
    const Face& flipped = s.faces[0];
    const Vec3 centre = s.normalisation.to_normalised(Vec3(0.0));
    EXPECT_LT(glm::dot(flipped.vertex_normals[0], flipped.vertices[0] - centre), 0.0);
    int inner = 0, flat = 0;
    for (const Face& f : s.faces) inner += f.inner && f.vertex_normals.size() == 3;
    for (int k = 0; k < s.objects[2].face_count; ++k)
        flat += s.faces[size_t(s.objects[2].first_face + k)].vertex_normals.empty();
    EXPECT_EQ(inner, 80);
    EXPECT_EQ(flat, 160);  // 80 faces and their twins, "smooth": false
}

TEST(SceneSmooth, KeyErrorsNameTheirPlace) {
    EXPECT_NE(
        load_error(one_object(
                       R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "white",
                      "smooth": true})"))
            .find("t.json: objects[0].smooth: a box has no vertex normals"),
        std::string::npos);
    EXPECT_NE(load_error(one_object(R"({"type": "polygon", "material": "white", "smooth": true,
                      "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})"))
                  .find("objects[0].smooth: a polygon has no vertex normals"),
              std::string::npos);
    EXPECT_NE(load_error(one_object(R"({"type": "sphere", "radius": 1, "material": "white",
                      "smooth": "yes"})"))
                  .find("objects[0].smooth: expected true or false"),
              std::string::npos)
        << load_error(one_object(
               R"({"type": "sphere", "radius": 1, "material": "white", "smooth": "yes"})"));
    // "smooth": false is fine anywhere.
    EXPECT_EQ(load_error(one_object(
                  R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "white",
                      "smooth": false})")),
              "");
}

// A quad of a mesh file with vertex normals: read, kept per vertex, smooth by default; a
// file without normals cannot be made smooth; normals turned to the back are dropped with a
// note.
TEST(SceneSmooth, MeshFilesGiveTheirNormals) {
    test::TempDir dir("smooth_mesh");
    dir.write("bent.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
              "vn -0.3 0 1\nvn 0.3 0 1\nvn 0.3 0 1\nvn -0.3 0 1\n"
              "f 1//1 2//2 3//3 4//4\n");
    dir.write("back.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
              "vn 0 0 1\nvn 0 0 -1\n"
              "f 1//1 2//1 3//2 4//1\n");
    dir.write("plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    dir.write("hard.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 -1\n"
              "vn 0 0 1\nvn 0 1 0\n"
              "f 1//1 2//1 3//1 4//1\nf 1//2 5//2 2//2\n");
    const std::string d = dir.path.string();
    for (const char* type : {"mesh", "import"}) {
        const Scene s = load_scene_from_string(
            one_object(
                fmt::format(R"({{"type": "{}", "file": "bent.obj", "material": "white"}})", type)),
            "t.json", d);
        const Face& f = s.faces[0];
        ASSERT_EQ(f.vertex_normals.size(), f.vertices.size()) << type;
        for (size_t v = 0; v < f.vertices.size(); ++v) {
            const double side = s.normalisation.to_user(f.vertices[v]).x < 0.5 ? -1.0 : 1.0;
            EXPECT_NEAR(glm::length(f.vertex_normals[v] - glm::normalize(Vec3(0.3 * side, 0, 1))),
                        0.0, 1e-6)
                << type;
        }
        const Scene flat = load_scene_from_string(
            one_object(fmt::format(
                R"({{"type": "{}", "file": "bent.obj", "material": "white", "smooth": false}})",
                type)),
            "t.json", d);
        EXPECT_TRUE(flat.faces[0].vertex_normals.empty()) << type;
        const Scene plain = load_scene_from_string(
            one_object(
                fmt::format(R"({{"type": "{}", "file": "plain.obj", "material": "white"}})", type)),
            "t.json", d);
        EXPECT_TRUE(plain.faces[0].vertex_normals.empty()) << type;
        EXPECT_NE(load_error(one_object(fmt::format(
                                 R"({{"type": "{}", "file": "plain.obj", "material": "white",
                                      "smooth": true}})",
                                 type)),
                             d)
                      .find("objects[0].smooth: 'plain.obj' has no vertex normals"),
                  std::string::npos)
            << type;
    }
    const Scene back = load_scene_from_string(
        one_object(R"({"type": "mesh", "file": "back.obj", "material": "white"})"), "t.json", d);
    EXPECT_TRUE(back.faces[0].vertex_normals.empty());
    bool noted = false;
    for (const std::string& n : back.load_notes)
        noted = noted || n.find("1 of 1 face(s) kept flat") != std::string::npos;
    EXPECT_TRUE(noted);
    const Scene hard = load_scene_from_string(
        one_object(R"({"type": "mesh", "file": "hard.obj", "material": "white"})"), "t.json", d);
    EXPECT_TRUE(hard.faces[0].vertex_normals.empty());
    noted = false;
    for (const std::string& n : hard.load_notes)
        noted = noted || n.find("vertex normals left out") != std::string::npos;
    EXPECT_TRUE(noted);
}

// ---- the bake -----------------------------------------------------------------------------

TEST(BakeSmooth, VertexNormalsRoundTripAndDamageIsRefused) {
    Scene a = load_scene_from_string(
        one_object(R"({"type": "sphere", "radius": 0.5, "subdivisions": 1, "material": "glass"},
                      {"type": "cylinder", "radius": 0.3, "height": 1, "center": [1, 0, 0],
                       "segments": 8, "material": "mirror"})"),
        "t.json", ".");
    const fs::path file =
        fs::temp_directory_path() / ("vlf-bake-smooth-" + std::to_string(::getpid()) + ".bin");
    write_geometry(file.string(), a);
    Scene b = vlf::scene_from_json(scene_to_json(a), "scene.json");
    read_geometry(file.string(), b);
    ASSERT_EQ(b.faces.size(), a.faces.size());
    size_t normals = 0;
    for (size_t f = 0; f < a.faces.size(); ++f) {
        ASSERT_EQ(b.faces[f].vertex_normals.size(), a.faces[f].vertex_normals.size()) << f;
        for (size_t v = 0; v < a.faces[f].vertex_normals.size(); ++v)
            EXPECT_EQ(b.faces[f].vertex_normals[v], a.faces[f].vertex_normals[v]);
        normals += a.faces[f].vertex_normals.size();
        EXPECT_EQ(b.faces[f].inner, a.faces[f].inner);
    }
    EXPECT_EQ(normals, 2u * 80 * 3 + 8 * 4);  // glass and its twins, the cylinder's walls
    auto refused = [&](Scene damaged, const std::string& why) {
        write_geometry(file.string(), damaged);
        Scene c = vlf::scene_from_json(scene_to_json(damaged), "scene.json");
        try {
            read_geometry(file.string(), c);
            ADD_FAILURE() << "accepted: " << why;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
        }
    };
    Scene d = a;
    d.faces[3].vertex_normals[1] = -d.faces[3].vertex_normals[1];
    refused(d, "face vertex normal of 3 points to the back of the face");
    d = a;
    d.faces[5].vertex_normals[0] =
        glm::normalize(d.faces[5].vertex_normals[0] + 0.01 * d.faces[5].normal);
    refused(d, "face vertex normals of 5: its twin");
    d = a;
    d.faces[2].vertex_normals[0] *= 1.5;
    refused(d, "face vertex normal of 2 is not unit");
    // A file of the first format is named as such.
    write_geometry(file.string(), a);
    {
        std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
        io.seekp(7);
        io.put('1');
    }
    Scene e = vlf::scene_from_json(scene_to_json(a), "scene.json");
    try {
        read_geometry(file.string(), e);
        ADD_FAILURE() << "format 01 accepted";
    } catch (const Error& err) {
        EXPECT_NE(std::string(err.what()).find("geometry format 01 is not supported"),
                  std::string::npos)
            << err.what();
    }
    fs::remove(file);
}

}  // namespace
}  // namespace vlf
