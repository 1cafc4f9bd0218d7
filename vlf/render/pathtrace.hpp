// pathtrace.hpp — the Monte-Carlo reference renderer (DESIGN §7 `pathtrace`, §8 "image
// error of each walkthrough mode against pathtrace"): an unbiased path tracer over the
// same scene, materials, one-sided Lambertian emitters and delta lights (light.hpp) the
// propagation uses.
//
// Estimator (normalised scene coordinates; radiance in W m^-2 sr^-1, m = the scene's unit):
//  * a path vertex on the back side of a face ends the path with nothing (faces are
//    one-sided: their back absorbs and emits nothing — as in the propagation);
//  * emission Le of a hit face counts in full on the camera ray and after a mirror bounce;
//    at every diffuse vertex, next-event estimation (uniform area sampling of all emitting
//    polygons, a shadow ray, cosines at both ends, one-sided emitters) is combined with
//    the emission found by the Lambertian bounce by multiple importance sampling (power
//    heuristic) — corners, where 1/r^2 makes light sampling noisy, stay well behaved;
//  * delta lights (Scene::lights) no bounce can find: at every diffuse vertex x each light
//    adds rho_d/pi x its irradiance E at x (delta_irradiance), deterministically but for
//    the sun's disc — directly (a shadow ray; E = I(w) cos_x / r^2 for a point or spot,
//    E cos_x for a directional light) and through up to kMaxMirrorOrder ideal planar
//    mirror faces by image sources (the light reflected in the mirrors' planes, the
//    unfolded path checked face by face; rho_s of each mirror on the way). Without those
//    a delta light seen in a mirror would light nothing. Paths through more mirrors than
//    that are missing (a bias of order rho_s^3); so are second-order images when the
//    scene's mirror faces form more than kMaxMirrorPairs facing pairs (a tessellated
//    concave mirror: the pair loop would cost more than the rest of the path);
//  * one lobe per bounce, chosen with probability proportional to the mean of rho_d
//    (Lambertian, cosine-weighted sampling) and rho_s (ideal mirror), weight divided by
//    that probability;
//  * Russian roulette from the fourth vertex on (survival = max throughput channel,
//    capped at 0.95) — so the estimate stays unbiased. A hard cap of kMaxPathVertices
//    vertices exists only as a safety net (its bias is below rho^1024).
// A scene may have no emitting face (lit by its lights alone) or no light.
// Random streams are seeded per pixel from (seed, pixel index): images do not depend on
// the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

inline constexpr int kMaxPathVertices = 1024;
// Delta lights are followed through at most this many mirror reflections (image sources).
inline constexpr int kMaxMirrorOrder = 2;
// Second-order image sources only while the ordered pairs of mirror faces that could see
// each other (each has a vertex in front of the other's plane) are at most this many; and
// the pairs are looked for only among at most kMaxMirrorFacesForPairs mirror faces.
inline constexpr int kMaxMirrorPairs = 4096;
inline constexpr int kMaxMirrorFacesForPairs = 1024;

// PCG32 (O'Neill), seeded by SplitMix64 from (seed, stream).
class Pcg32 {
  public:
    Pcg32(uint64_t seed, uint64_t stream);
    uint32_t next_u32();
    double uniform();  // [0, 1)

  private:
    uint64_t m_state = 0, m_inc = 1;
};

class PathTracer {
  public:
    // The scene and caster must outlive the tracer.
    PathTracer(const Scene& scene, const RayCaster& caster);

    // One path's estimate of the radiance arriving at `origin` from direction `dir`
    // (unit; the path leaves along dir), normalised coordinates.
    Rgb radiance(const Vec3& origin, const Vec3& dir, Pcg32& rng) const;

    // Mean of `spp` paths through pixel (x, y): stratified jittered positions on a
    // floor(sqrt(spp))^2 grid, the remainder uniformly jittered. Stream = pixel index.
    Rgb pixel(const PinholeCamera& camera, int x, int y, int width, int spp, uint64_t seed) const;

    // The irradiance at x (normalised coordinates, on a surface with unit front normal n)
    // from the scene's delta lights, directly and through up to kMaxMirrorOrder mirror
    // faces, W per square scene unit (the rho_d/pi of a Lambertian surface turns it into
    // radiance). Light arriving at the back of the surface counts nothing. Deterministic
    // but for a directional light with an angular diameter: one direction of its disc per
    // call, drawn from rng.
    Rgb delta_irradiance(const Vec3& x, const Vec3& n, Pcg32& rng) const;

    int emitter_triangles() const { return static_cast<int>(m_lights.size()); }
    double emitter_area() const { return m_light_area; }
    int mirror_faces() const { return static_cast<int>(m_mirrors.size()); }
    // Ordered pairs of mirror faces used for second-order image sources (0 beyond the caps).
    int mirror_pairs() const { return static_cast<int>(m_mirror_pairs.size() / 2); }

  private:
    struct LightTriangle {
        Vec3 a, b, c;
        int face = 0;
        double cdf = 0.0;  // cumulative area up to and including this triangle
    };
    // Next-event estimate at a Lambertian surface point x with normal n, without the
    // rho_d/pi factor: integral of Le cos_x cos_y / r^2 dA over all emitters, one sample,
    // MIS-weighted (power heuristic) against the Lambertian lobe chosen with probability
    // bsdf_pdf_scale.
    Rgb direct(const Vec3& x, const Vec3& n, double bsdf_pdf_scale, Pcg32& rng) const;

    // A delta light as one sample: a position (point, spot; normalised) or a direction of
    // travel (directional: the disc's sampled direction) with the irradiance it brings.
    struct DeltaSource {
        const Light* light = nullptr;
        bool parallel = false;
        Vec3 position{0.0};     // point, spot: normalised coordinates
        Vec3 travel{0, -1, 0};  // directional: the way this sample's light travels, unit
        Rgb irradiance{0.0};    // directional: W per square unit on a plane facing `travel`
    };
    DeltaSource delta_source(const Light& light, Pcg32& rng) const;
    // The irradiance at x (normal n) brought by `source` along the path that reflects in
    // the mirror faces chain[0], ..., chain[k-1] in that order seen from x (k = 0: the
    // direct path), times their rho_s; zero where that path does not exist or is blocked.
    Rgb delta_path(const DeltaSource& source, const Vec3& x, const Vec3& n, const int* chain,
                   int k) const;
    // Whether the segment from o to y (normalised) crosses no face, y itself excluded.
    bool segment_clear(const Vec3& o, const Vec3& y) const;

    const Scene& m_scene;
    const RayCaster& m_caster;
    std::vector<LightTriangle> m_lights;
    double m_light_area = 0.0;
    // Faces whose material has rho_s > 0, and the ordered pairs (first seen from the
    // receiver, second) for second-order image sources, flattened.
    std::vector<int> m_mirrors;
    std::vector<int> m_mirror_pairs;
    double m_scale2 = 1.0;  // (normalised / user length)^2: I / r_user^2 = I scale^2 / r_n^2
};

}  // namespace vlf
