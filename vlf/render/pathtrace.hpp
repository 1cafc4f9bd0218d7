// pathtrace.hpp — the Monte-Carlo reference renderer (DESIGN §7 `pathtrace`, §8 "image
// error of each walkthrough mode against pathtrace"): an unbiased path tracer over the
// same scene, materials and one-sided Lambertian emitters the propagation uses.
//
// Estimator (normalised scene coordinates; radiance in W m^-2 sr^-1):
//  * a path vertex on the back side of a face ends the path with nothing (faces are
//    one-sided: their back absorbs and emits nothing — as in the propagation);
//  * emission Le of a hit face counts in full on the camera ray and after a mirror bounce;
//    at every diffuse vertex, next-event estimation (uniform area sampling of all emitting
//    polygons, a shadow ray, cosines at both ends, one-sided emitters) is combined with
//    the emission found by the Lambertian bounce by multiple importance sampling (power
//    heuristic) — corners, where 1/r^2 makes light sampling noisy, stay well behaved;
//  * one lobe per bounce, chosen with probability proportional to the mean of rho_d
//    (Lambertian, cosine-weighted sampling) and rho_s (ideal mirror), weight divided by
//    that probability;
//  * Russian roulette from the fourth vertex on (survival = max throughput channel,
//    capped at 0.95) — so the estimate stays unbiased. A hard cap of kMaxPathVertices
//    vertices exists only as a safety net (its bias is below rho^1024).
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

    int emitter_triangles() const { return static_cast<int>(m_lights.size()); }
    double emitter_area() const { return m_light_area; }

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

    const Scene& m_scene;
    const RayCaster& m_caster;
    std::vector<LightTriangle> m_lights;
    double m_light_area = 0.0;
};

}  // namespace vlf
