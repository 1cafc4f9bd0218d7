// face_check.cpp — every face of one object of a bake against the path tracer, face by face
// (face_probe.hpp): how many are darker than half the reference, and the distribution of
// the ratio. Usage:
//   vlf_face_check BAKE.vlf OBJECT [SPP_PER_BATCH [BATCHES [MODE]]]
// OBJECT is an object's name in the scene file; MODE texture (default) or rays.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "vlf/bake/bake.hpp"
#include "vlf/core/error.hpp"
#include "vlf/render/face_probe.hpp"
#include "vlf/render/render.hpp"
#include "vlf/scene/primitives.hpp"

int main(int argc, char** argv) try {
    if (argc < 3 || argc > 6) {
        std::fprintf(stderr, "usage: %s BAKE.vlf OBJECT [SPP_PER_BATCH [BATCHES [MODE]]]\n",
                     argv[0]);
        return 2;
    }
    const vlf::Bake bake = vlf::read_bake(argv[1]);
    const std::string name = argv[2];
    const int spp = argc > 3 ? std::atoi(argv[3]) : 256;
    const int batches = argc > 4 ? std::atoi(argv[4]) : 4;
    const vlf::RenderMode mode =
        vlf::render_mode_from_string(argc > 5 ? std::string(argv[5]) : "texture");
    std::vector<int> faces;
    for (const vlf::SceneObject& o : bake.scene.objects)
        if (o.name == name)
            for (int f = o.first_face; f < o.first_face + o.face_count; ++f) faces.push_back(f);
    if (faces.empty()) {
        std::fprintf(stderr, "%s: no object named '%s' with faces\n", argv[1], name.c_str());
        return 2;
    }
    const vlf::Renderer renderer(bake);
    const std::vector<vlf::FaceProbe> probes =
        vlf::probe_faces(renderer, faces, mode, spp, batches);
    std::vector<double> ratio;
    for (const vlf::FaceProbe& p : probes)
        if (p.reference > 0.0) ratio.push_back(p.value / p.reference);
    std::sort(ratio.begin(), ratio.end());
    auto q = [&](double f) { return ratio.empty() ? 0.0 : ratio[size_t(f * (ratio.size() - 1))]; };
    const auto dark = vlf::darker_than(probes, 0.5, 3.0);
    const auto dark_raw = vlf::darker_than(probes, 0.5, 0.0);
    std::printf("%s: %zu faces, %d x %d paths each\n", name.c_str(), faces.size(), batches, spp);
    std::printf(
        "ratio bake/path tracer: min %.3f  1%% %.3f  10%% %.3f  median %.3f  90%% %.3f  "
        "99%% %.3f  max %.3f\n",
        q(0), q(0.01), q(0.1), q(0.5), q(0.9), q(0.99), q(1));
    std::printf("darker than half: %zu (%zu beyond 3 standard errors)\n", dark_raw.size(),
                dark.size());
    // A few paths through a small gap can inflate a reference beyond what its batches'
    // spread shows: the faces flagged are looked at again with 16 times the paths.
    if (!dark.empty()) {
        std::vector<int> again;
        for (const vlf::FaceProbe& p : dark) again.push_back(p.face);
        const auto recheck = vlf::probe_faces(renderer, again, mode, 16 * spp, batches);
        const auto still = vlf::darker_than(recheck, 0.5, 3.0);
        std::printf("  of those, with %d x %d paths each: %zu still darker than half\n", batches,
                    16 * spp, still.size());
        for (const vlf::FaceProbe& p : still)
            std::printf("    face %d: %.4g vs %.4g +- %.2g\n", p.face, p.value, p.reference,
                        p.std_error);
    }
    // The other side: faces brighter than twice the reference beyond 3 standard errors.
    std::vector<vlf::FaceProbe> bright;
    for (const vlf::FaceProbe& p : probes)
        if (p.value > 2.0 * (p.reference + 3.0 * p.std_error)) bright.push_back(p);
    std::sort(bright.begin(), bright.end(), [](const auto& a, const auto& b) {
        return a.value - a.reference > b.value - b.reference;
    });
    std::printf("brighter than twice: %zu beyond 3 standard errors\n", bright.size());
    for (size_t i = 0; i < std::min<size_t>(bright.size(), 5); ++i) {
        const vlf::Face& f = renderer.bake().scene.faces[size_t(bright[i].face)];
        const vlf::Vec3 c =
            renderer.bake().scene.normalisation.to_user(vlf::polygon_centroid(f.vertices));
        std::printf("  face %d: %.4g vs %.4g +- %.2g at (%.1f %.1f %.1f)\n", bright[i].face,
                    bright[i].value, bright[i].reference, bright[i].std_error, c.x, c.y, c.z);
    }
    std::vector<vlf::FaceProbe> worst = dark;
    std::sort(worst.begin(), worst.end(), [](const auto& a, const auto& b) {
        return a.value / std::max(a.reference, 1e-300) < b.value / std::max(b.reference, 1e-300);
    });
    const vlf::Scene& scene = renderer.bake().scene;
    for (size_t i = 0; i < std::min<size_t>(worst.size(), 10); ++i) {
        const vlf::Face& f = scene.faces[size_t(worst[i].face)];
        const vlf::Chart& c = scene.chart_of(f);
        std::printf(
            "  face %d: %.4g vs %.4g +- %.2g  (normal %.3f %.3f %.3f; chart %d of %zu "
            "faces, %d x %d texels, normal %.3f %.3f %.3f)\n",
            worst[i].face, worst[i].value, worst[i].reference, worst[i].std_error, f.normal.x,
            f.normal.y, f.normal.z, c.id, c.faces.size(), c.texels.width, c.texels.height,
            c.normal.x, c.normal.y, c.normal.z);
        const vlf::VertexLight& vl = renderer.bake().vertex_light;
        if (!vl.has(f.id)) continue;
        const vlf::Vec3 mid = scene.normalisation.to_user(vlf::polygon_centroid(f.vertices));
        std::printf("    at (%.1f %.1f %.1f), area %.3g texel^2, gathered E/pi at its vertices:",
                    mid.x, mid.y, mid.z, f.area / (c.texels.size * c.texels.size));
        for (size_t v = 0; v < f.vertices.size(); ++v)
            std::printf(" %.4g", double(vl.incident[size_t(vl.first[size_t(f.id)]) + v].y));
        std::printf("\n");
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
}
