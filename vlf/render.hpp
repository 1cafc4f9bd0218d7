// render.hpp — walkthrough rendering of a bake by lookup (VLF §6; DESIGN §7).
//
// Primary visibility by ray casting (Embree). Modes:
//   Rays      §6.1: radiance from L_T of the three PSF directions enclosing the ray,
//             interpolated over the 8-neighbourhood of the ray's pixel in each PSF and
//             across directions by spherical barycentric weights; P^T where a face has no
//             stored rays (diffuse faces unless --store-all-rays);
//   Texture   §6.2: diffuse from P^T (bilinear), specular faces as in Rays;
//   Raytrace  §6.3: diffuse from P^T, specular by recursive mirror reflection until a
//             diffuse surface;
//   Pathtrace an unbiased Monte-Carlo reference of the same scene (same materials and
//             Lambertian emitters), the ground truth of the accuracy tests.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vlf/bake.hpp"
#include "vlf/math.hpp"
#include "vlf/scene.hpp"

namespace vlf {

enum class RenderMode { Rays, Texture, Raytrace, Pathtrace };
std::string to_string(RenderMode m);
RenderMode render_mode_from_string(const std::string& s);  // throws ParameterError

struct RenderSettings {
    int width = 512;
    int height = 512;
    RenderMode mode = RenderMode::Texture;
    int spp = 64;        // pathtrace samples per pixel (other modes: 1 ray per pixel centre)
    int max_depth = 16;  // mirror bounces (raytrace) / path length (pathtrace)
    uint64_t seed = 1;   // pathtrace random streams, seeded per pixel
};

// Linear radiance image, row-major, row 0 at the top.
struct Image {
    int width = 0, height = 0;
    std::vector<Rgb> pixels;
    Rgb& at(int x, int y) { return pixels[size_t(y) * width + x]; }
    const Rgb& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

class Renderer {
  public:
    explicit Renderer(const Bake& bake);  // the bake must outlive the renderer
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Camera in the user's scene units (as in the scene file). Parallel over rows.
    Image render(const Camera& camera, const RenderSettings& settings) const;

    const Bake& bake() const { return m_bake; }

  private:
    struct Impl;
    const Bake& m_bake;
    std::unique_ptr<Impl> m_impl;
};

// Writes .exr (linear, half RGB) or .png (exposure in stops, then a filmic-free Reinhard
// tone map and sRGB encoding) atomically (temporary name, rename). Throws Error naming the
// path for an unknown extension or an I/O failure.
void write_image(const std::string& path, const Image& image, double exposure = 0.0);
Image read_exr(const std::string& path);  // throws Error

// Relative RMSE of `a` against the reference `ref`: sqrt(sum |a-ref|^2 / sum |ref|^2).
double relative_rmse(const Image& a, const Image& ref);

}  // namespace vlf
