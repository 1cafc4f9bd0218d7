// face_probe.cpp — per-face comparison of a bake with the path tracer (face_probe.hpp).
#include "vlf/render/face_probe.hpp"

#include <cmath>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

double channel_mean(const Rgb& c) {
    return (c.x + c.y + c.z) / 3.0;
}

}  // namespace

std::vector<PrimaryRay> face_probe_rays(const Scene& scene, const std::vector<int>& faces) {
    std::vector<PrimaryRay> rays;
    rays.reserve(faces.size());
    for (int id : faces) {
        const Face& f = scene.faces.at(size_t(id));
        Vec3 c(0.0);
        for (const Vec3& v : f.vertices) c += v;
        c /= double(f.vertices.size());
        rays.push_back({c + kProbeLift * f.normal, -f.normal});
    }
    return rays;
}

std::vector<FaceProbe> probe_faces(const Renderer& renderer, const std::vector<int>& faces,
                                   RenderMode mode, int spp, int batches) {
    if (batches < 2) throw ParameterError("probe_faces: at least two batches");
    const std::vector<PrimaryRay> rays = face_probe_rays(renderer.bake().scene, faces);
    RenderSettings s;
    s.mode = mode;
    const std::vector<Rgb> value = renderer.shade(rays, s);
    s.mode = RenderMode::Pathtrace;
    s.spp = spp;
    std::vector<double> sum(faces.size(), 0.0), sum2(faces.size(), 0.0);
    for (int b = 0; b < batches; ++b) {
        s.seed = uint64_t(b) + 1;
        const std::vector<Rgb> pt = renderer.shade(rays, s);
        for (size_t i = 0; i < faces.size(); ++i) {
            const double v = channel_mean(pt[i]);
            sum[i] += v;
            sum2[i] += v * v;
        }
    }
    std::vector<FaceProbe> out(faces.size());
    for (size_t i = 0; i < faces.size(); ++i) {
        const double mean = sum[i] / batches;
        const double var = std::max(0.0, (sum2[i] - batches * mean * mean) / (batches - 1));
        out[i] = {faces[i], channel_mean(value[i]), mean, std::sqrt(var / batches)};
    }
    return out;
}

std::vector<FaceProbe> darker_than(const std::vector<FaceProbe>& probes, double fraction,
                                   double sigmas) {
    std::vector<FaceProbe> out;
    for (const FaceProbe& p : probes)
        if (p.value < fraction * (p.reference - sigmas * p.std_error)) out.push_back(p);
    return out;
}

}  // namespace vlf
