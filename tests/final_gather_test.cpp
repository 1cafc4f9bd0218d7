// final_gather_test.cpp — the final gather at the vertices of faces the field cannot resolve
// (vlf/render/final_gather.hpp, docs/charts.md "Final gather"): its estimator against the
// furnace's closed form, the issue-11 bound "no face of a lit model darker than half the
// path tracer's value there" on the Stanford bunny, which faces it covers, its
// determinism, and its round trip through the bake.
#include "vlf/render/final_gather.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_util.hpp"
#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/face_probe.hpp"
#include "vlf/render/image_metrics.hpp"
#include "vlf/render/render.hpp"
#include "vlf/transport/propagation.hpp"

namespace vlf {
namespace {

#if defined(__SANITIZE_ADDRESS__)
#define VLF_SKIP_UNDER_SANITIZER() GTEST_SKIP() << "takes minutes under ASan"
#else
#define VLF_SKIP_UNDER_SANITIZER() static_cast<void>(0)
#endif

PropagateParams field(int l, int N, int m, int cycles, int gather) {
    PropagateParams p = test::params(l, N, m, cycles, /*deferred=*/true);
    p.gather = gather;
    return p;
}

Bake bake_of(const Scene& scene, const PropagateParams& p) {
    const Propagation run = propagate(scene, p, {});
    Bake b = make_bake(scene, p, *run.transport, propagation_report(scene, p, run, 0.0));
    final_gather(b);
    return b;
}

// Every surface of a closed room and a small sphere in it emits Le = 1 and reflects
// rho = 0.6. After C cycles every texel holds Le (1 - rho^(C+1)) / (1 - rho)
// (TransportFurnace); a gathered face reflects what it sees once more, so its radiance is
// Le + rho x that = Le (1 - rho^(C+2)) / (1 - rho) wherever it is. This checks the
// gather's three parts together: the light samples count the lamps' emission (here every
// surface), the gather rays everything else and not the emission again.
constexpr const char* kFurnaceWithSphere = R"({
  "materials": {"f": {"diffuse": [0.6, 0.6, 0.6], "emission": [1, 1, 1]}},
  "objects": [
    {"name": "room", "type": "box", "min": [0, 0, 0], "max": [2, 1.5, 1], "flip": true,
     "material": "f"},
    {"name": "ball", "type": "sphere", "center": [0.7, 0.6, 0.5], "radius": 0.15,
     "subdivisions": 3, "material": "f"}
  ]
})";

TEST(FinalGather, FurnaceSphereReadsTheClosedForm) {
    const Scene scene = test::scene_from_json(kFurnaceWithSphere);
    const int C = 3, K = 256;
    const Bake b = bake_of(scene, field(513, 64, 8, C, K));
    const double rho = 0.6, expect = (1.0 - std::pow(rho, C + 2)) / (1.0 - rho);
    // The room's walls are large planar charts: not gathered. The sphere is.
    int gathered = 0;
    double sum = 0.0, worst = 0.0, sq = 0.0;
    int n = 0;
    for (const Face& f : scene.faces) {
        const bool ball = scene.objects[size_t(f.object)].name == "ball";
        EXPECT_EQ(b.vertex_light.has(f.id), ball) << "face " << f.id;
        if (!b.vertex_light.has(f.id)) continue;
        ++gathered;
        for (size_t v = 0; v < f.vertices.size(); ++v) {
            const double L =
                1.0 +
                rho * b.vertex_light.incident[size_t(b.vertex_light.first[size_t(f.id)]) + v].x;
            sum += L;
            worst = std::max(worst, std::abs(L / expect - 1.0));
            sq += (L / expect - 1.0) * (L / expect - 1.0);
            ++n;
        }
    }
    EXPECT_GT(gathered, 1000);
    // The mean over the sphere's vertices: the field's texels are within 5 % each and their
    // mean exact (TransportFurnace), the light samples' and gather rays' noise averages out
    // over hundreds of gather points: 1 %. (A lost or doubled emission term is 43 % off.)
    EXPECT_NEAR(sum / n / expect, 1.0, 0.01);
    // Each vertex: the light samples of an emitting enclosure (Le cos cos / r^2 over a
    // uniform area pdf, r from 0.15 to 1.4 units) are the noisiest case of the estimator;
    // measured 3.9 % RMS over the vertices at K = 256. Bounds: RMS 5 %, and every vertex
    // within 5 standard deviations of that, 20 %.
    EXPECT_LT(std::sqrt(sq / n), 0.05);
    EXPECT_LT(worst, 0.20);
}

// Issue 11: "no face of a lit model darker than half the path tracer's value there". The
// 69,451-triangle Stanford bunny in the Cornell box at l = 513, N = 64, 4 cycles: every face
// looked at straight on from above its centroid (face_probe.hpp) against 4 batches of 64
// paths. Without the gather 1,217 faces were darker than half beyond 3 standard errors of
// the path tracer (BENCHMARKS.md); with it none may be.
TEST(FinalGather, NoFaceOfTheBunnyDarkerThanHalfThePathTracer) {
    VLF_SKIP_UNDER_SANITIZER();
    const Scene scene = load_scene(test::source_path("scenes/bunny.json"));
    const Bake b = bake_of(scene, field(513, 64, 8, 4, 64));
    std::vector<int> faces;
    for (const SceneObject& o : scene.objects)
        if (o.name == "bunny")
            for (int f = o.first_face; f < o.first_face + o.face_count; ++f) faces.push_back(f);
    ASSERT_GT(faces.size(), 60000u);
    int gathered = 0;
    for (int f : faces) gathered += b.vertex_light.has(f) ? 1 : 0;
    EXPECT_EQ(gathered, int(faces.size()));  // a curved model of small triangles: every face
    const Renderer renderer(b);
    const std::vector<FaceProbe> probes = probe_faces(renderer, faces, RenderMode::Texture, 64, 4);
    const std::vector<FaceProbe> dark = darker_than(probes, 0.5, 3.0);
    EXPECT_TRUE(dark.empty()) << dark.size() << " faces darker than half, the first "
                              << dark[0].face << ": " << dark[0].value << " against "
                              << dark[0].reference;
    // And the model as a whole: the area-weighted mean of the faces within 5 % of the path
    // tracer's (4 cycles leave 4 % of the light unshot: the field reads low by about that).
    double area = 0.0, ratio = 0.0;
    for (const FaceProbe& p : probes) {
        const double a = scene.faces[size_t(p.face)].area;
        area += a * p.reference;
        ratio += a * p.value;
    }
    EXPECT_NEAR(ratio / area, 0.97, 0.03);
}

// Issue 11: the bunny and the bunny split 1 -> 4 and 1 -> 16 render within 2 % of each
// other away from the lamp, with the final gather on every face (its vertices, and so its
// gather points and their noise, differ from split to split). The public bunny decimated to
// 1,000 triangles (scenes/meshes/README.md) in the Cornell box of scenes/bunny.json, the
// scene's camera, texture mode at 128 x 128 with 2 x 2 rays per pixel.
TEST(FinalGather, SplittingTheBunnyKeepsItsImage) {
    VLF_SKIP_UNDER_SANITIZER();
    test::TempDir dir("gather_split");
    const std::string scene = test::read_text(test::source_path("scenes/bunny.json"));
    const std::string mesh = "meshes/stanford-bunny.obj";
    ASSERT_NE(scene.find(mesh), std::string::npos);
    std::vector<Image> images;
    RenderSettings s;
    s.width = s.height = 128;
    s.pixel_samples = 2;
    PixelMask lamp;
    for (int levels : {0, 1, 2}) {
        const auto obj = dir.path / ("bunny-" + std::to_string(levels) + ".obj");
        test::subdivide_obj(test::source_path("scenes/meshes/stanford-bunny-1k.obj"), obj, levels);
        std::string text = scene;
        text.replace(text.find(mesh), mesh.size(), obj.string());
        const Scene sc = load_scene_from_string(text, "bunny.json", dir.path.string());
        const Bake b = bake_of(sc, field(513, 64, 8, 4, 64));
        // The bunny's faces, but for a few of the unsplit model's larger than 2 texels.
        EXPECT_GE(b.vertex_light.face_count(), (size_t(1000) << (2 * levels)) * 99 / 100);
        const Renderer r(b);
        images.push_back(r.render(sc.cameras[0], s));
        if (levels == 0) lamp = r.emitter_mask(sc.cameras[0], s.width, s.height, s.pixel_samples);
    }
    for (size_t k = 1; k < images.size(); ++k) {
        const ImageError e = image_error(images[k], images[0], lamp);
        EXPECT_LT(e.rmse_away, 0.02) << "split 1 -> " << (k == 1 ? 4 : 16);
        std::printf("gathered bunny split 1 -> %d: RMSE %.3g %% away from the lamp\n",
                    k == 1 ? 4 : 16, 100 * e.rmse_away);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.ratio_away[c], 1.0, 0.005);
    }
}

// The paper's scenes (a few large polygons) gather nothing: their bakes are the field's.
TEST(FinalGather, LargePolygonsKeepTheirTexels) {
    const Scene scene = load_scene(test::source_path("scenes/cornell.json"));
    EXPECT_TRUE(faces_to_gather(scene, 16.0).empty());
    // A floor of 10,000 random triangles is one large planar chart: not gathered either.
    const Scene floor = load_scene(test::source_path("scenes/floor-triangles.json"));
    EXPECT_TRUE(faces_to_gather(floor, 16.0).empty());
}

// The same bake with 1 and 2 threads, and off when gather = 0.
TEST(FinalGather, IsDeterministicAndCanBeOff) {
    const Scene scene = test::scene_from_json(kFurnaceWithSphere);
    const PropagateParams p = field(513, 64, 8, 2, 16);
    std::vector<RgbF> with_one, with_two;
    {
        ThreadLimit limit(1);
        with_one = bake_of(scene, p).vertex_light.incident;
    }
    {
        ThreadLimit limit(2);
        with_two = bake_of(scene, p).vertex_light.incident;
    }
    ASSERT_FALSE(with_one.empty());
    EXPECT_EQ(with_one, with_two);
    EXPECT_TRUE(bake_of(scene, field(513, 64, 8, 2, 0)).vertex_light.incident.empty());
}

// vertexlight.bin round-trips bit for bit, and a damaged one is refused naming the part.
TEST(FinalGather, RoundTripsThroughTheBake) {
    const Scene scene = test::scene_from_json(kFurnaceWithSphere);
    const Bake b = bake_of(scene, field(513, 64, 8, 2, 16));
    test::TempDir dir("final_gather");
    const std::string path = (dir.path / "ball.vlf").string();
    write_bake(path, b);
    const Bake back = read_bake(path);
    EXPECT_EQ(back.vertex_light.first, b.vertex_light.first);
    EXPECT_EQ(back.vertex_light.incident, b.vertex_light.incident);
    EXPECT_EQ(back.params.gather, 16);
    // Damage behind a checksum that agrees (a buggy writer): the reader names the part.
    auto forge = [&](const std::string& bytes) {
        const std::string bin = path + "/vertexlight.bin";
        std::ofstream(bin, std::ios::binary | std::ios::trunc) << bytes;
        nlohmann::json m = nlohmann::json::parse(test::read_text(path + "/manifest.json"));
        uint64_t n = 0;
        m["files"]["vertexlight.bin"]["sha256"] = sha256_file(bin, n);
        m["files"]["vertexlight.bin"]["bytes"] = n;
        std::ofstream(path + "/manifest.json", std::ios::trunc) << m.dump(1);
    };
    const std::string original = test::read_text(path + "/vertexlight.bin");
    auto refused = [&](const std::string& want) {
        try {
            read_bake(path);
            ADD_FAILURE() << "accepted; wanted " << want;
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(path + "/vertexlight.bin: ", 0), 0u) << what;
            EXPECT_NE(what.find(want), std::string::npos) << what;
        }
    };
    forge(original.substr(0, original.size() - 2));
    refused("truncated");
    std::string bytes = original;
    const float minus = -1.0f;
    std::memcpy(&bytes[8 + 8 + 4], &minus, 4);  // the first gathered face's first value
    forge(bytes);
    refused("vertex light -1 is not a finite, non-negative radiance");
    forge(original);
    EXPECT_NO_THROW(read_bake(path));
    // Rendering reads it: a gathered face's radiance is its emission + albedo x E/pi.
    const Face& f = scene.faces[size_t(scene.objects[1].first_face)];
    ASSERT_TRUE(back.vertex_light.has(f.id));
    const Rgb at_vertex = back.vertex_light.at(f, f.vertices[0]);
    EXPECT_DOUBLE_EQ(
        at_vertex.x,
        double(back.vertex_light.incident[size_t(back.vertex_light.first[size_t(f.id)])].x));
}

}  // namespace
}  // namespace vlf
