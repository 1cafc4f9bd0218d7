// render.hpp — walkthrough rendering of a bake by lookup (VLF §6; DESIGN §7).
//
// Primary visibility by ray casting (Embree). Modes:
//   Rays      §6.1: radiance from L_T of the three PSF directions enclosing the ray,
//             interpolated over the 8-neighbourhood of the ray's pixel in each PSF and
//             across directions by spherical barycentric weights; P^T where a face has no
//             stored rays (diffuse faces unless --store-all-rays);
//   Texture   §6.2: diffuse from P^T (bilinear), specular faces as in Rays;
//   Raytrace  §6.3: diffuse from P^T, specular by recursive ray tracing until a diffuse
//             surface: mirrors reflect, glass splits into the Fresnel-weighted reflected
//             and refracted rays (total internal reflection, Beer-Lambert absorption
//             inside), both about the smooth shading normal (Scene::shading_normal);
//             Rays and Texture show glass, as mirrors, from its outer faces' stored L_T;
//   Pathtrace an unbiased Monte-Carlo reference of the same scene (same materials and
//             Lambertian emitters), the ground truth of the accuracy tests.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vlf/bake/bake.hpp"
#include "vlf/core/math.hpp"
#include "vlf/render/image_io.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

enum class RenderMode { Rays, Texture, Raytrace, Pathtrace };
std::string to_string(RenderMode m);
RenderMode render_mode_from_string(const std::string& s);  // throws ParameterError

struct PrimaryRay {
    Vec3 origin{0.0};
    Vec3 dir{0.0, 0.0, 1.0};
};

struct RenderSettings {
    int width = 512;
    int height = 512;
    RenderMode mode = RenderMode::Texture;
    int spp = 64;  // pathtrace samples per pixel (jittered over the pixel's area)
    // Lookup modes: k x k primary rays per pixel on a regular grid, at (x + (i+0.5)/k,
    // y + (j+0.5)/k), averaged (a box filter over the pixel's area, the footprint of the
    // path tracer's pixels). 1 = one ray through the pixel centre. Not used by pathtrace.
    int pixel_samples = 1;
    int max_depth = 16;  // specular events (raytrace: mirror bounces, glass interfaces) /
                         // path length (pathtrace)
    uint64_t seed = 1;   // pathtrace random streams, seeded per pixel
    // Pathtrace: light paths from the delta lights per eye path, for the caustics the eye
    // cannot sample (PathTraceSettings::light_paths_per_sample).
    double light_paths_per_sample = 1.0;
};

class PathTracer;

class Renderer {
  public:
    explicit Renderer(const Bake& bake);  // the bake must outlive the renderer
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Camera in the user's scene units (as in the scene file). Parallel over rows.
    Image render(const Camera& camera, const RenderSettings& settings) const;

    // Pixels that see an emitting face (Material::is_emitter) from its front: set when
    // any of the pixel's k x k primary rays (the grid of RenderSettings::pixel_samples)
    // hits one first. Geometric — it reads no radiance — so it marks the pixels whose
    // value is the lamp's exact emission, in every mode and in the reference alike. Lamps
    // seen in a mirror are not marked. Camera in user units; throws ParameterError for
    // k < 1 or a bad size.
    PixelMask emitter_mask(const Camera& camera, int width, int height, int k) const;

    // The fraction of an n x n grid of the camera's rays whose first hit is the back of a
    // one-sided face: near 1 when the camera is inside a wall or outside a closed room
    // (every such pixel renders black).
    double back_face_fraction(const Camera& camera, int n) const;

    // Radiance along arbitrary primary rays (normalised coordinates, unit directions), one
    // value per ray, in settings.mode (width, height and pixel_samples are not used). For
    // Pathtrace, the mean of settings.spp paths, ray i on stream (settings.seed, i). For
    // probes that are not pinhole images: a face seen straight on from just above it.
    std::vector<Rgb> shade(const std::vector<PrimaryRay>& rays,
                           const RenderSettings& settings) const;

    const Bake& bake() const { return m_bake; }

    // For the final gather (final_gather.hpp): the radiance arriving at `origin` from
    // direction `dir` as raytrace mode sees it, less the emission of a lamp met first (the
    // light samples count that); a lamp seen through a mirror or glass counts in full.
    // `back`, when given, is set when the ray meets the back of a one-sided face first.
    Rgb gather_radiance(const Vec3& origin, const Vec3& dir, int max_depth,
                        bool* back = nullptr) const;
    // The path tracer over the same scene and caster (its light samples and delta lights).
    const PathTracer& path_tracer() const;

  private:
    struct Impl;
    const Bake& m_bake;
    std::unique_ptr<Impl> m_impl;
};

// Image error against a reference (relative_rmse, mean_ratio, image_error): image_metrics.hpp.

}  // namespace vlf
