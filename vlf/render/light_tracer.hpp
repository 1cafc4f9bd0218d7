// light_tracer.hpp — the path-traced reference's caustic pass (DESIGN §7 `pathtrace`):
// particles traced from the delta lights (light.hpp: point, spot, directional) through
// mirrors and glass, connected to the camera at diffuse vertices and splatted into the
// image. Light tracing is Veach's thesis §10.2 (the s = path, t = 1 strategy of
// bidirectional path tracing; pbrt-v3 §16.3.1 writes the camera connection the same way).
//
// Why: a delta light meets no ray, so the eye path tracer (pathtrace.hpp) reaches it only
// by next-event estimation — a straight shadow ray, or an unfolded image-source path
// through at most PathTracer::image_source_order() planar mirrors. Light that went through
// glass (refracted or Fresnel-reflected), or through a longer mirror chain, arrives at a
// diffuse point along a path no eye path can close: a caustic.
//
// The split (every path light -> ... -> eye counted exactly once). Call a light path's
// *prefix* its vertices from the light up to the first one where a diffuse lobe acts
// (rho_d > 0; on a face that is both diffuse and mirror, the diffuse part), and its
// *specular chain* the mirror and glass vertices before it.
//  * The eye tracer's next-event estimation counts the prefixes whose chain is no glass
//    and at most image_source_order() flat mirrors, every leg clear (glass blocks a leg).
//  * The light tracer counts every other prefix: a chain with glass or a smooth mirror in
//    it (a mirror with shading normals turns each particle about its own normal, by
//    specular_turn, with the shading-normal correction), or with more mirrors. Such a particle is
//    *tagged* at its first diffuse vertex; it splats there and at every later diffuse vertex (it
//    goes on by the lobes of each surface, Lambertian by cosine sampling, with Russian roulette),
//    because the eye tracer finds no path with that prefix however it continues: its NEE at the
//    prefix's diffuse vertex sees nothing of it.
//  * An untagged particle stops at its first diffuse vertex (the eye tracer has all that
//    follows); at a face that is also a mirror it goes on by the mirror alone (weight
//    rho_s), since its chain may still become one the eye tracer misses.
// A splat is the connection to the pinhole (a shadow ray; glass blocks it): the particle's
// power x rho_d/pi x the camera's importance for the pixel it projects to. What no
// connection can close — a caustic seen only through a mirror or glass (light -> S+ ->
// D -> S+ -> eye) — stays missing from the reference; so are caustics in
// Renderer::shade's probes, which are no pinhole images.
//
// Particles: light chosen with probability proportional to its power (a directional
// light's: E times the area of the disc it crosses the scene's unit ball through);
// directions uniform on the sphere (point), over the outer cone (spot) or the sun's disc;
// a directional light's particles start uniformly on a disc of radius kBeamRadius
// (normalised) perpendicular to their direction, outside the unit ball. Batches of
// kBatchParticles particles, each on its own stream (seed, batch): the image is the same
// for any number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/image_io.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

class Pcg32;

class LightTracer {
  public:
    // Particles per random stream, and the radius (normalised units) of the disc a
    // directional light's particles start on: the scene lies in the unit ball.
    static constexpr long long kBatchParticles = 1024;
    static constexpr double kBeamRadius = 1.0;

    // image_source_order: the longest mirror chain the eye tracer's image sources cover
    // (PathTracer::image_source_order()). Scene and caster must outlive the tracer.
    LightTracer(const Scene& scene, const RayCaster& caster, int image_source_order);

    // Whether any path is the light tracer's: the scene has a delta light that emits, and
    // glass, or mirror faces enough for a chain longer than image_source_order (two).
    bool needed() const { return m_needed; }

    // Traces `particles` light paths in all and adds their splats to `image` (radiance,
    // W m^-2 sr^-1 per user unit, the pixel's box-filtered mean like PathTracer::pixel;
    // width x height pixels, the camera built for that size). Deterministic for a seed.
    void splat(const PinholeCamera& camera, int width, int height, long long particles,
               uint64_t seed, Image& image) const;

    // Per light of Scene::lights: the probability of choosing it (0 for one that does
    // not emit).
    const std::vector<double>& light_probabilities() const { return m_probability; }

  private:
    struct Splat {
        uint32_t pixel = 0;
        Rgb value{0.0};
    };
    struct View;  // the camera's frame and pixel footprint (light_tracer.cpp)
    // One particle of `particles` in all (its power is the light's over that count); its
    // splats appended to `out`.
    void trace(const View& view, long long particles, Pcg32& rng, std::vector<Splat>& out) const;
    // The connection of the diffuse vertex x (normal n, front lit) to the camera.
    void connect(const View& view, const Vec3& x, const Vec3& n, const Rgb& power_rho,
                 std::vector<Splat>& out) const;
    // The power-proportional choice of a light: its index.
    int choose_light(double u) const;

    const Scene& m_scene;
    const RayCaster& m_caster;
    int m_image_order = 1;
    bool m_needed = false;
    std::vector<double> m_probability, m_cdf;
    // Per light: its power in W (mean over channels) as used for the choice.
    std::vector<double> m_power;
};

}  // namespace vlf
