// final_gather.cpp — the final gather at the vertices of unresolved faces (final_gather.hpp).
#include "vlf/render/final_gather.hpp"

#include <cmath>
#include <unordered_map>

#include "vlf/core/parallel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/render/pathtrace.hpp"
#include "vlf/render/render.hpp"
#include "vlf/scene/primitives.hpp"

namespace vlf {

namespace {

// Gather points sit this far above the surface (normalised units), as the path tracer's rays.
constexpr double kLift = 1e-5;
// Specular events a gather ray follows (RenderSettings::max_depth's default).
constexpr int kGatherDepth = 16;
// A gather point sits this fraction of the way from its vertex towards the mean centroid of
// the faces that share it. At a vertex inside a smooth mesh that is about the vertex; at a
// face's rim (a window frame against its wall, a crease) it moves into the faces: a point on
// a concave edge sees a wedge of the hemisphere that the faces' interiors do not, and the
// interpolated faces would read dark all over (the Godot living room's window frames:
// 0.034 against the path tracer's 0.045 at the vertices themselves).
constexpr double kGatherInset = 0.5;
// Random streams of the gather: distinct from the path tracer's pixel streams.
constexpr uint64_t kGatherSeed = 0x6761746865720001ull;

struct PositionHash {
    size_t operator()(const Vec3& p) const { return size_t(position_hash(p)); }
};

struct GatherPoint {
    Vec3 position{0.0};  // the shared vertex
    Vec3 first_normal{0.0};
    Vec3 normal_sum{0.0};    // area-weighted
    Vec3 centroid_sum{0.0};  // area-weighted centroids of its faces
    double area = 0.0;
    Vec3 normal{0.0};      // unit: normal_sum normalised
    double min_cos = 1.0;  // the least cosine between `normal` and one of its faces' normals
    // Where it gathers: kGatherInset of the way from the vertex towards its faces' mean
    // centroid, taken in the vertex's tangent plane (on a convex patch that mean lies below
    // the faces, inside the model), then raised along `normal` as far as its faces can rise
    // over that distance (on a concave patch they rise above the tangent plane).
    Vec3 site() const {
        if (!(area > 0.0)) return position;
        Vec3 in = kGatherInset * (centroid_sum / area - position);
        in -= glm::dot(in, normal) * normal;
        const double c = std::max(min_cos, 0.5);  // faces share a point within 60 degrees
        return position + in + glm::length(in) * std::sqrt(1.0 - c * c) / c * normal;
    }
};

// E/pi at x (normal n), as final_gather.hpp states it; `backs` counts the rays that met
// the back of a one-sided face first.
Rgb gather_at(const Renderer& renderer, const Scene& scene, const Vec3& x, const Vec3& n, int K,
              bool sun_disc, Pcg32& rng, int& backs) {
    const PathTracer& tracer = renderer.path_tracer();
    Vec3 e1, e2;
    orthonormal_basis(n, e1, e2);
    const Vec3 o = x + kLift * n;
    const int side = static_cast<int>(std::sqrt(double(K)));
    Rgb indirect(0.0);
    for (int k = 0; k < K; ++k) {
        // Stratified on a side x side grid of the unit square, the remainder jittered freely.
        double u1 = rng.uniform(), u2 = rng.uniform();
        if (k < side * side) {
            u1 = ((k % side) + u1) / side;
            u2 = ((k / side) + u2) / side;
        }
        const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
        const double cz = std::sqrt(std::max(0.0, 1.0 - r * r));
        const Vec3 dir = glm::normalize(r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + cz * n);
        bool back = false;
        indirect += renderer.gather_radiance(o, dir, kGatherDepth, &back);
        backs += back ? 1 : 0;
    }
    Rgb direct(0.0);
    if (tracer.emitter_triangles() > 0)
        for (int k = 0; k < K; ++k) direct += tracer.light_sample(x, n, rng);
    Rgb delta(0.0);
    if (!scene.lights.empty()) {
        const int draws = sun_disc ? K : 1;  // the sun's disc is sampled, the rest exact
        for (int k = 0; k < draws; ++k) delta += tracer.delta_irradiance(x, n, rng);
        delta /= double(draws);
    }
    return indirect / double(K) + (direct / double(K) + delta) / kPi;
}

}  // namespace

nlohmann::json to_json(const GatherStats& s) {
    return {{"faces", s.faces}, {"points", s.points}, {"centroids", s.centroids}};
}

std::vector<int> faces_to_gather(const Scene& scene, double below_texels) {
    std::vector<int> out;
    for (const Face& f : scene.faces) {
        const Material& m = scene.material_of(f);
        if (!m.is_diffuse() || m.is_specular()) continue;
        const Chart& c = scene.chart_of(f);
        const double texel = c.texels.size * c.texels.size;
        if (f.area <= kGatherFaceTexels * texel && (c.area < below_texels * texel || !c.planar))
            out.push_back(f.id);
    }
    return out;
}

GatherStats final_gather(Bake& bake) {
    bake.vertex_light = VertexLight{};
    GatherStats stats;
    const int K = bake.params.gather;
    if (K <= 0) return stats;
    const Scene& scene = bake.scene;
    const std::vector<int> faces = faces_to_gather(scene, bake.params.gather_below);
    if (faces.empty()) return stats;

    // Gather points: the faces' vertices, shared by faces at one position that face alike.
    const double share_cos = std::cos(kGatherShareDeg * kPi / 180.0);
    std::vector<GatherPoint> points;
    std::unordered_map<Vec3, std::vector<int>, PositionHash> at_position;
    std::vector<int> corner_point;  // per corner of the gathered faces, in order
    VertexLight light;
    light.first.assign(scene.faces.size(), -1);
    for (int id : faces) {
        const Face& f = scene.faces[size_t(id)];
        light.first[size_t(id)] = int64_t(corner_point.size());
        const Vec3 centroid = polygon_centroid(f.vertices);
        for (const Vec3& p : f.vertices) {
            std::vector<int>& here = at_position[p];
            int found = -1;
            for (int q : here)
                if (glm::dot(points[size_t(q)].first_normal, f.normal) >= share_cos) {
                    found = q;
                    break;
                }
            if (found < 0) {
                found = static_cast<int>(points.size());
                here.push_back(found);
                points.push_back({p, f.normal, Vec3(0.0), Vec3(0.0), 0.0});
            }
            GatherPoint& g = points[size_t(found)];
            g.normal_sum += f.area * f.normal;
            g.centroid_sum += f.area * centroid;
            g.area += f.area;
            corner_point.push_back(found);
        }
    }
    for (GatherPoint& g : points) {
        const double len = glm::length(g.normal_sum);
        g.normal = len > 0.0 ? g.normal_sum / len : g.first_normal;
    }
    for (size_t k = 0, c = 0; k < faces.size(); ++k) {
        const Face& f = scene.faces[size_t(faces[k])];
        for (size_t v = 0; v < f.vertices.size(); ++v, ++c) {
            GatherPoint& g = points[size_t(corner_point[c])];
            g.min_cos = std::min(g.min_cos, glm::dot(g.normal, f.normal));
        }
    }

    bool sun_disc = false;
    for (const Light& l : scene.lights)
        sun_disc = sun_disc || (l.type == LightType::Directional && l.angular_diameter_deg > 0.0);
    const Renderer renderer(bake);  // reads the light maps; bake.vertex_light is still empty
    std::vector<RgbF> value(points.size());
    std::vector<char> inside(points.size(), 0);
    parallel_for(
        0, long(points.size()),
        [&](long i) {
            const GatherPoint& g = points[size_t(i)];
            Pcg32 rng(kGatherSeed, uint64_t(i));
            int backs = 0;
            value[size_t(i)] =
                RgbF(gather_at(renderer, scene, g.site(), g.normal, K, sun_disc, rng, backs));
            inside[size_t(i)] = 2 * backs > K ? 1 : 0;
        },
        64);
    light.incident.resize(corner_point.size());
    for (size_t c = 0; c < corner_point.size(); ++c)
        light.incident[c] = value[size_t(corner_point[c])];

    // A vertex in a fold of the mesh (most of its rays meet the back of a face: the point
    // is inside the model, where the path tracer finds no light either) does not speak for
    // the faces around it: their corners there take a gather at the face's own centroid.
    std::vector<int> refold;
    for (int id : faces) {
        const int64_t first = light.first[size_t(id)];
        for (size_t v = 0; v < scene.faces[size_t(id)].vertices.size(); ++v)
            if (inside[size_t(corner_point[size_t(first) + v])]) {
                refold.push_back(id);
                break;
            }
    }
    std::vector<RgbF> centre(refold.size());
    parallel_for(
        0, long(refold.size()),
        [&](long i) {
            const Face& f = scene.faces[size_t(refold[size_t(i)])];
            const Vec3 c = polygon_centroid(f.vertices);
            Pcg32 rng(kGatherSeed, uint64_t(points.size()) + uint64_t(i));
            int backs = 0;
            centre[size_t(i)] =
                RgbF(gather_at(renderer, scene, c, f.normal, K, sun_disc, rng, backs));
        },
        16);
    for (size_t i = 0; i < refold.size(); ++i) {
        const Face& f = scene.faces[size_t(refold[i])];
        const int64_t first = light.first[size_t(f.id)];
        for (size_t v = 0; v < f.vertices.size(); ++v)
            if (inside[size_t(corner_point[size_t(first) + v])])
                light.incident[size_t(first) + v] = centre[i];
    }
    bake.vertex_light = std::move(light);
    stats.faces = int64_t(faces.size());
    stats.points = int64_t(points.size());
    stats.centroids = int64_t(refold.size());
    return stats;
}

}  // namespace vlf
