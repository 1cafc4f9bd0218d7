// pathtrace.hpp — the Monte-Carlo reference renderer (DESIGN §7 `pathtrace`, §8 "image
// error of each walkthrough mode against pathtrace"): an unbiased path tracer over the
// same scene, materials, one-sided Lambertian emitters and delta lights (light.hpp) the
// propagation uses.
//
// Estimator (normalised scene coordinates; radiance in W m^-2 sr^-1, m = the scene's unit):
//  * a path vertex on the back side of a face ends the path with nothing (faces are
//    one-sided: their back absorbs and emits nothing — as in the propagation);
//  * emission Le of a hit face counts in full on the camera ray and after a mirror or glass
//    vertex; at every diffuse vertex, next-event estimation (uniform area sampling of all
//    emitting polygons, a shadow ray, cosines at both ends, one-sided emitters) is combined
//    with the emission found by the Lambertian bounce by multiple importance sampling
//    (power heuristic) — corners, where 1/r^2 makes light sampling noisy, stay well behaved;
//  * glass (Material::dielectric, glass_vertex.hpp): reflection or refraction chosen by the
//    exact unpolarised Fresnel reflectance (total internal reflection: reflect), weight 1;
//    a segment that ran inside glass is attenuated by exp(-sigma d_user) (Beer-Lambert). A
//    glass vertex is not a diffuse vertex: no next-event estimation there;
//  * shadow rays are blocked by glass like by any face. A straight shadow ray through glass
//    would be wrong anyway (the light bends): an area emitter seen through glass is found
//    by the bounce that refracts (with MIS weight 1, as after a mirror), a delta light
//    through glass by the light tracer (below);
//  * delta lights (Scene::lights) no bounce can find: at every diffuse vertex x each light
//    adds rho_d/pi x its irradiance E at x (delta_irradiance), deterministically but for
//    the sun's disc — directly (a shadow ray; E = I(w) cos_x / r^2 for a point or spot,
//    E cos_x for a directional light) and through up to image_source_order() ideal planar
//    mirror faces (flat ones: a smooth mirror turns each ray about its own shading normal,
//    as eye paths do at it by specular_turn, so its light is the light tracer's) by image sources
//    (the light reflected in the mirrors' planes, the unfolded path checked face by face; rho_s of
//    each mirror on the way). Without those a delta light seen in a mirror would light nothing.
//    Glass on any leg blocks the image path: that light went through the glass (or was reflected by
//    it) instead;
//  * everything else a delta light sends — paths light -> (mirror | glass)+ -> diffuse ->
//    ... -> eye whose specular chain holds glass, a smooth mirror or more than
//    image_source_order() mirrors
//    — the eye cannot sample (a delta light meets no ray). The light tracer
//    (light_tracer.hpp) follows particles from the lights and splats exactly those into
//    the image (render()); the split between the two is stated there. The one family
//    neither finds is a caustic seen only through a mirror or glass (light -> S+ -> D ->
//    S+ -> eye with a delta light and a pinhole: no connection can close it);
//  * one lobe per bounce, chosen with probability proportional to the mean of rho_d
//    (Lambertian, cosine-weighted sampling) and rho_s (ideal mirror), weight divided by
//    that probability;
//  * Russian roulette from the fourth vertex on (survival = max throughput channel,
//    capped at 0.95) — so the estimate stays unbiased — at every vertex but glass (whose
//    weight is 1: the cap would make paths trapped by total internal reflection grow into
//    fireflies). A hard cap of kMaxPathVertices vertices exists only as a safety net (its
//    bias is below rho^1024, or the chance of 1024 vertices in glass).
// A scene may have no emitting face (lit by its lights alone) or no light.
// Random streams are seeded per pixel from (seed, pixel index), the light tracer's per
// batch of particles: images do not depend on the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/image_io.hpp"
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

// Russian roulette (Arvo & Kirk 1990; pbrt-v4 §14.1.5): the path survives with probability
// q = min(0.95, largest channel of beta) and then beta /= q; false when it ends.
bool russian_roulette(Rgb& beta, Pcg32& rng);

// A path-traced image (PathTracer::render).
struct PathTraceSettings {
    int width = 512;
    int height = 512;
    int spp = 64;       // eye paths per pixel (jittered over the pixel's area)
    uint64_t seed = 1;  // random streams: per pixel for eye paths, per batch for light paths
    // Light paths traced from the delta lights (the caustic pass, light_tracer.hpp), per
    // eye path: width x height x spp x this particles in all. Caustics on a few pixels are
    // then about as converged as the eye-traced light there; 0 leaves them out (a biased
    // image where glass or long mirror chains meet delta lights). The pass runs only when
    // the scene has delta lights and something they need it for (LightTracer::needed).
    double light_paths_per_sample = 1.0;
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
    // Eye paths only: without the light tracer's caustics (render() adds them).
    Rgb pixel(const PinholeCamera& camera, int x, int y, int width, int spp, uint64_t seed) const;

    // The whole image: pixel() for every pixel (parallel over rows), plus the light
    // tracer's splats (settings.light_paths_per_sample). The camera must have been built
    // for settings.width x settings.height. Independent of the thread count.
    Image render(const PinholeCamera& camera, const PathTraceSettings& settings) const;

    // The longest chain of mirror faces through which delta_irradiance finds a delta light
    // (image sources): kMaxMirrorOrder, or 1 when the second-order pairs were left out
    // (kMaxMirrorPairs, kMaxMirrorFacesForPairs). The light tracer takes the longer ones.
    int image_source_order() const { return m_image_order; }

    // The irradiance at x (normalised coordinates, on a surface with unit front normal n)
    // from the scene's delta lights, directly and through up to kMaxMirrorOrder mirror
    // faces, W per square scene unit (the rho_d/pi of a Lambertian surface turns it into
    // radiance). Light arriving at the back of the surface counts nothing. Deterministic
    // but for a directional light with an angular diameter: one direction of its disc per
    // call, drawn from rng.
    Rgb delta_irradiance(const Vec3& x, const Vec3& n, Pcg32& rng) const;

    // One light sample of the emitting polygons' irradiance at x (normal n), W per square
    // scene unit: Le cos_x cos_y / r^2 over the area pdf, shadowed (next-event estimation
    // without MIS; the final gather's direct light).
    Rgb light_sample(const Vec3& x, const Vec3& n, Pcg32& rng) const {
        return direct(x, n, 0.0, rng);
    }

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
    int m_image_order = 1;
    // Faces whose material has rho_s > 0 (not glass), and the ordered pairs (first seen from the
    // receiver, second) for second-order image sources, flattened.
    std::vector<int> m_mirrors;
    std::vector<int> m_mirror_pairs;
    double m_scale2 = 1.0;  // (normalised / user length)^2: I / r_user^2 = I scale^2 / r_n^2
};

}  // namespace vlf
