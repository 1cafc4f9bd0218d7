// Charts (scene/charts.hpp, docs/charts.md): texels belong to surfaces, not to how a
// surface is cut into triangles.
#include "vlf/scene/charts.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "test_util.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

// A floor 2 x 1.5 at y = 0, facing up, as an OBJ: a jittered grid of nx x nz cells, each
// cut along a random diagonal (2 nx nz triangles covering the rectangle exactly).
void write_floor_obj(const fs::path& file, int nx, int nz, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    std::bernoulli_distribution coin(0.5);
    const double dx = 2.0 / nx, dz = 1.5 / nz;
    std::ofstream out(file);
    out.precision(17);
    for (int j = 0; j <= nz; ++j)
        for (int i = 0; i <= nx; ++i) {
            // Points inside move in both directions, points on the rim only along it.
            const double ju = jitter(rng), jv = jitter(rng);
            const double x = (i + (i > 0 && i < nx ? ju : 0.0)) * dx;
            const double z = (j + (j > 0 && j < nz ? jv : 0.0)) * dz;
            out << "v " << x << " 0 " << z << "\n";
        }
    auto id = [&](int i, int j) { return j * (nx + 1) + i + 1; };
    for (int j = 0; j < nz; ++j)
        for (int i = 0; i < nx; ++i) {
            const int p00 = id(i, j), p10 = id(i + 1, j), p11 = id(i + 1, j + 1),
                      p01 = id(i, j + 1);
            // Counter-clockwise seen from +y: p00, p01, p11, p10.
            if (coin(rng))
                out << "f " << p00 << " " << p01 << " " << p11 << "\nf " << p00 << " " << p11 << " "
                    << p10 << "\n";
            else
                out << "f " << p00 << " " << p01 << " " << p10 << "\nf " << p01 << " " << p11 << " "
                    << p10 << "\n";
        }
}

// A closed room 2 x 1.2 x 1.5 with a lamp under its ceiling; its floor is `floor` (a JSON
// object).
Scene room(const std::string& floor, const fs::path& dir, double chart_angle) {
    const std::string text = R"({
      "materials": {"white": {"diffuse": [0.5, 0.5, 0.5]},
                    "grey": {"diffuse": [0.7, 0.6, 0.5]},
                    "lamp": {"emission": [5, 5, 5]}},
      "objects": [
        {"type": "polygon", "material": "white", "vertices": [[0,1.2,0],[2,1.2,0],[2,1.2,1.5],[0,1.2,1.5]]},
        {"type": "polygon", "material": "white", "vertices": [[0,0,0],[0,1.2,0],[0,1.2,1.5],[0,0,1.5]]},
        {"type": "polygon", "material": "white", "vertices": [[2,0,0],[2,0,1.5],[2,1.2,1.5],[2,1.2,0]]},
        {"type": "polygon", "material": "white", "vertices": [[0,0,0],[2,0,0],[2,1.2,0],[0,1.2,0]]},
        {"type": "polygon", "material": "white", "vertices": [[0,0,1.5],[0,1.2,1.5],[2,1.2,1.5],[2,0,1.5]]},
        {"type": "polygon", "material": "lamp", "vertices": [[0.5,1.19,0.3],[0.9,1.19,0.3],[0.9,1.19,0.7],[0.5,1.19,0.7]]},
        )" + floor + R"(],
      "settings": {"texel_size": 0.1}})";
    LoadOptions o;
    o.chart_angle_deg = chart_angle;
    return load_scene_from_string(text, "room.json", dir.string(), o);
}

std::unique_ptr<Transport> propagate(const Scene& scene) {
    auto t = std::make_unique<Transport>(scene, test::params(129, 32, 8, 3));
    for (int c = 1; c <= 3; ++c) t->run_cycle(c == 3);
    return t;
}

const Face& floor_face(const Scene& s) {
    return s.faces[s.objects.back().first_face];
}

TEST(Charts, CoplanarNeighboursOfOneMaterialShareAChart) {
    const fs::path dir = fs::temp_directory_path() / "vlf-charts-share";
    fs::create_directories(dir);
    write_floor_obj(dir / "floor.obj", 4, 3, 1);
    const Scene s = room(R"({"type": "mesh", "file": "floor.obj", "material": "grey"})", dir, 30);
    // Six polygons of their own and the 24 floor triangles in one chart.
    ASSERT_EQ(s.faces.size(), 30u);
    EXPECT_EQ(s.charts.size(), 7u);
    const Chart& floor = s.chart_of(floor_face(s));
    EXPECT_EQ(floor.faces.size(), 24u);
    EXPECT_NEAR(floor.area, 3.0 * s.normalisation.scale * s.normalisation.scale, 1e-12);
    // The grid is the rectangle's: 20 x 15 texels of 0.1 along its sides.
    EXPECT_EQ(floor.texels.width * floor.texels.height, 300);
    // Another material does not join: the same floor in two materials is two charts.
    const Scene t = room(R"({"type": "mesh", "file": "floor.obj", "material": "white"})", dir, 30);
    EXPECT_EQ(t.charts.size(), 7u);  // the walls meet the floor at 90 degrees
    const Scene u = room(R"({"type": "mesh", "file": "floor.obj", "material": "grey"})", dir, 0);
    EXPECT_EQ(u.charts.size(), 30u);  // --chart-angle 0: a chart per face
    fs::remove_all(dir);
}

// VLF §4.4 texel grids per surface: a floor given as one quad and as 10,000 random
// triangles bakes to the same texel radiance within 1 % (issue 11); with a grid per
// triangle (chart angle 0) the triangles' radiance scatters far beyond that.
TEST(Charts, TriangulationDoesNotChangeTheTexels) {
    const fs::path dir = fs::temp_directory_path() / "vlf-charts-invariance";
    fs::create_directories(dir);
    write_floor_obj(dir / "floor.obj", 100, 50, 7);
    const std::string quad =
        R"({"type": "polygon", "material": "grey", "vertices": [[0,0,0],[0,0,1.5],[2,0,1.5],[2,0,0]]})";
    const std::string mesh = R"({"type": "mesh", "file": "floor.obj", "material": "grey"})";
    const Scene a = room(quad, dir, 30), b = room(mesh, dir, 30);
    ASSERT_EQ(b.faces.size(), a.faces.size() - 1 + 10000);
    const Chart& ca = a.chart_of(floor_face(a));
    const Chart& cb = b.chart_of(floor_face(b));
    ASSERT_EQ(cb.faces.size(), 10000u);
    ASSERT_EQ(ca.texels.width, cb.texels.width);
    ASSERT_EQ(ca.texels.height, cb.texels.height);
    EXPECT_LT(glm::length(ca.texels.origin - cb.texels.origin), 1e-9);
    EXPECT_GT(glm::dot(ca.texels.axis_u, cb.texels.axis_u), 1 - 1e-12);
    const auto ta = propagate(a), tb = propagate(b);
    const TextureMaps &ma = ta->texture_maps(), &mb = tb->texture_maps();
    double worst = 0.0;
    int compared = 0;
    for (size_t k = 0; k < ca.texel_area.size(); ++k) {
        if (ca.texel_area[k] <= 0.0) continue;
        EXPECT_NEAR(cb.texel_area[k], ca.texel_area[k], 1e-9 * ca.texel_area[k]);
        const double ra = ma.radiance(ca, k).x, rb = mb.radiance(cb, k).x;
        ASSERT_GT(ra, 0.0);
        worst = std::max(worst, std::abs(rb / ra - 1.0));
        if (std::abs(rb / ra - 1.0) > 0.003)
            std::printf("DBG texel %zu (%zu,%zu) %.4f\n", k, k % ca.texels.width,
                        k / ca.texels.width, rb / ra - 1.0);
        ++compared;
    }
    EXPECT_EQ(compared, 300);
    EXPECT_LE(worst, 0.01) << "worst texel of " << compared;
    std::printf("quad vs 10,000 triangles: worst texel %.3g %% of %d\n", 100 * worst, compared);

    // A grid per triangle: each triangle's mean radiance against the quad's texel under its
    // centroid.
    const Scene c = room(mesh, dir, 0);
    const auto tc = propagate(c);
    const TextureMaps& mc = tc->texture_maps();
    double scatter = 0.0;
    const SceneObject& fo = c.objects.back();
    for (int f = fo.first_face; f < fo.first_face + fo.face_count; ++f) {
        const Chart& ch = c.chart_of(c.faces[f]);
        const Rgb p = TextureMaps::sum(mc.total, mc.begin(ch.id), mc.count(ch.id));
        const double mean = p.x / (kPi * ch.area);
        Vec3 centroid(0.0);
        for (const Vec3& v : c.faces[f].vertices) centroid += v / 3.0;
        const Vec2 uv =
            ca.texels.to_texel(a.normalisation.to_normalised(c.normalisation.to_user(centroid)));
        const size_t k = size_t(std::floor(uv.y)) * ca.texels.width + size_t(std::floor(uv.x));
        scatter = std::max(scatter, std::abs(mean / ma.radiance(ca, k).x - 1.0));
    }
    std::printf("a grid per triangle: worst triangle %.3g %%\n", 100 * scatter);
    EXPECT_GT(scatter, 0.01);
    fs::remove_all(dir);
}

// Issue 11: the same model cut into 4 and 16 times as many triangles bakes to the same
// texels: charts are unions of the same surface, and a triangle's rays no longer decide
// what its texels get. The public Stanford bunny (decimated to 1,000 triangles,
// scenes/meshes/README.md) in the Cornell box.
TEST(Charts, SplittingTheTrianglesOfAModelKeepsItsTexels) {
    const fs::path dir = fs::temp_directory_path() / "vlf-charts-split";
    fs::create_directories(dir);
    std::ifstream in(test::source_path("scenes/bunny.json"));
    const std::string scene((std::istreambuf_iterator<char>(in)), {});
    const std::string mesh = "meshes/stanford-bunny.obj";
    ASSERT_NE(scene.find(mesh), std::string::npos);
    std::vector<Scene> scenes;
    for (int levels : {0, 1, 2}) {
        const fs::path obj = dir / ("bunny-" + std::to_string(levels) + ".obj");
        test::subdivide_obj(test::source_path("scenes/meshes/stanford-bunny-1k.obj"), obj, levels);
        std::string text = scene;
        text.replace(text.find(mesh), mesh.size(), obj.string());
        scenes.push_back(load_scene_from_string(text, "bunny.json", dir.string()));
    }
    const Scene& a = scenes[0];
    const auto ta = propagate(a);
    for (size_t k = 1; k < scenes.size(); ++k) {
        const Scene& b = scenes[k];
        ASSERT_EQ(b.objects.back().face_count, a.objects.back().face_count * (k == 1 ? 4 : 16));
        ASSERT_EQ(b.charts.size(), a.charts.size());
        const auto tb = propagate(b);
        double sq = 0.0, area = 0.0, worst = 0.0;
        for (size_t c = 0; c < a.charts.size(); ++c) {
            const Chart &ca = a.charts[c], &cb = b.charts[c];
            ASSERT_EQ(ca.texels.count(), cb.texels.count()) << "chart " << c;
            const double half = 0.5 * ca.texels.size * ca.texels.size;
            for (size_t t = 0; t < ca.texel_area.size(); ++t) {
                if (ca.texel_area[t] < half) continue;
                const double ra = ta->texture_maps().radiance(ca, t).x;
                const double rb = tb->texture_maps().radiance(cb, t).x;
                const double d = ra > 0 ? rb / ra - 1.0 : (rb > 0 ? 1.0 : 0.0);
                sq += ca.texel_area[t] * d * d;
                area += ca.texel_area[t];
                worst = std::max(worst, std::abs(d));
            }
        }
        const double rms = std::sqrt(sq / area);
        std::printf("bunny split 1 -> %d: texel RMS %.3g %%, worst %.3g %%\n", k == 1 ? 4 : 16,
                    100 * rms, 100 * worst);
        EXPECT_LE(rms, 0.02);
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace vlf
