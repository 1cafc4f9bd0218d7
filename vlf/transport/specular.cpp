#include "vlf/transport/specular.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/primitives.hpp"

namespace vlf {

namespace {

// The face that carries light leaving f's front along PSF line d, travelling along `omega`
// (that line in its sense): f when it shows its front there and has rays, else the nearest
// face of f's chart that does; -1 when none can.
int specular_target_face(const Scene& scene, const Face& f, int d, const Vec3& omega,
                         const Coverage& coverage) {
    auto usable = [&](const Face& g) {
        return glm::dot(g.normal, omega) > 1e-12 && coverage(d, g.id) > 0;
    };
    if (usable(f)) return f.id;
    const Vec3 centre = polygon_centroid(f.vertices);
    int face = -1;
    double best = std::numeric_limits<double>::infinity();
    for (int g : scene.chart_of(f).faces) {  // the nearest face of the chart with rays there
        const Face& other = scene.faces[size_t(g)];
        if (!usable(other)) continue;
        const double dist = glm::length(polygon_centroid(other.vertices) - centre);
        if (dist < best) best = dist, face = g;
    }
    return face;
}

}  // namespace

int chart_specular_targets(const Scene& scene, const DirectionSet& dirs, const Face& f,
                           const Vec3& outgoing, const Coverage& coverage,
                           std::array<SpecularTarget, 3>& out) {
    const EnclosingTriangle tri = dirs.enclosing(glm::normalize(outgoing));
    int k = 0;
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
        const int d = tri.index[i];
        if (tri.weight[i] <= 0.0) continue;
        const int face =
            specular_target_face(scene, f, d, dirs.direction(d) * double(tri.sense[i]), coverage);
        if (face < 0) continue;
        bool merged = false;  // the same line can appear twice near the equator
        for (int j = 0; j < k; ++j)
            if (out[size_t(j)].direction == d && out[size_t(j)].face == face) {
                out[size_t(j)].weight += tri.weight[i];
                merged = true;
            }
        if (!merged) out[size_t(k++)] = {face, d, tri.weight[i]};
        sum += tri.weight[i];
    }
    for (int j = 0; j < k; ++j) out[size_t(j)].weight /= sum;
    return k;
}

namespace {

struct TargetRef {
    int face;
    uint32_t source;
    int target;  // its index among the source's targets
};

// Incoming radiance of the source at pixel (i, j): the covered pixel itself, else the
// mean of covered 8-neighbours (the beam hit the face there but the centre fell just
// outside).
bool sample_source(const SpecularSource& s, int i, int j, RgbF& value) {
    const int x = i - s.i0, y = j - s.j0;
    auto at = [&](int a, int b) { return size_t(b) * s.width + a; };
    if (x >= 0 && y >= 0 && x < s.width && y < s.height && s.covered[at(x, y)]) {
        value = s.radiance[at(x, y)];
        return true;
    }
    RgbF sum(0.0f);
    int n = 0;
    for (int b = y - 1; b <= y + 1; ++b)
        for (int a = x - 1; a <= x + 1; ++a)
            if (a >= 0 && b >= 0 && a < s.width && b < s.height && s.covered[at(a, b)]) {
                sum += s.radiance[at(a, b)];
                ++n;
            }
    if (n == 0) return false;
    value = sum / float(n);
    return true;
}

}  // namespace

std::vector<Rgb> gather_specular(const Scene& scene, const DirectionSet& dirs,
                                 const std::vector<Mat3>& rotations, int N, int m,
                                 const std::vector<SpecularSource>& sources, RadianceMaps& maps) {
    // Invert: per target direction, (face, source, weight) in source order; only the
    // directions the maps hold (a rank's own, issue 13: the deposits into the others are
    // their owners' to make, in this same order).
    std::vector<std::vector<TargetRef>> by_direction(dirs.size());
    for (uint32_t s = 0; s < sources.size(); ++s)
        for (int k = 0; k < sources[s].targets; ++k)
            if (maps.holds(sources[s].target_direction[k]))
                by_direction[sources[s].target_direction[k]].push_back({sources[s].face, s, k});
    for (auto& v : by_direction)
        std::stable_sort(v.begin(), v.end(),
                         [](const TargetRef& a, const TargetRef& b) { return a.face < b.face; });

    const double a = ray_area(N);
    std::vector<Rgb> rounding(size_t(maps.last - maps.first), Rgb(0.0));  // per held direction
    parallel_for(maps.first, maps.last, [&](long d) {
        const auto& refs = by_direction[d];
        if (refs.empty()) return;
        const Mat3& rot = rotations[d];
        const double beam = a * dirs.solid_angle(static_cast<int>(d));  // a * Delta
        FaceRaster fr;
        std::vector<Vec3> points;  // scene-frame points of the face's rays
        std::vector<Rgb> acc, g;
        size_t r = 0;
        while (r < refs.size()) {
            const int fid = refs[r].face;
            const Face& face = scene.faces[fid];
            rasterise_face(face, rot, N, m, fr);
            const uint64_t base = maps.begin(static_cast<int>(d), fid);
            VLF_CHECK(maps.count(static_cast<int>(d), fid) == fr.covered);
            // Points of the face's rays, in its face-local ray order.
            points.clear();
            const PlaneInPsf plane(face, rot, N);
            for (const FaceFragment& ff : fr.fragments)
                fr.edge_table(ff).for_each_ray([&](int u, int v, int) {
                    points.push_back(plane.point(ff.s * m + u, ff.t * m + v));
                });
            acc.assign(points.size(), Rgb(0.0));
            g.resize(points.size());
            for (; r < refs.size() && refs[r].face == fid; ++r) {
                const SpecularSource& src = sources[refs[r].source];
                Rgb total(0.0);
                for (size_t k = 0; k < points.size(); ++k) {
                    const Vec3 q = src.rotation * points[k];
                    const int i = static_cast<int>(std::floor((q.x + 1.0) * 0.5 * src.resolution));
                    const int j = static_cast<int>(std::floor((q.y + 1.0) * 0.5 * src.resolution));
                    RgbF value;
                    g[k] = sample_source(src, i, j, value) ? Rgb(value) : Rgb(0.0);
                    total += g[k];
                }
                const Rgb deposit = src.target_power[size_t(refs[r].target)];
                for (int c = 0; c < 3; ++c) {
                    if (deposit[c] <= 0.0) continue;
                    if (total[c] > 0.0) {
                        const double scale = deposit[c] / (total[c] * beam);
                        for (size_t k = 0; k < points.size(); ++k) acc[k][c] += g[k][c] * scale;
                    } else {  // nothing to map back: spread evenly (energy is still exact)
                        const double each = deposit[c] / (double(points.size()) * beam);
                        for (size_t k = 0; k < points.size(); ++k) acc[k][c] += each;
                    }
                }
            }
            for (size_t k = 0; k < points.size(); ++k) {
                const RgbF before = maps.unshot_next[base + k];
                maps.unshot_next[base + k] += RgbF(acc[k]);
                // What single precision kept of the deposit, against what was deposited.
                rounding[d - maps.first] +=
                    (acc[k] - (Rgb(maps.unshot_next[base + k]) - Rgb(before))) * beam;
            }
        }
    });
    return rounding;
}

}  // namespace vlf
