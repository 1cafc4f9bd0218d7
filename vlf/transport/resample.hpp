// resample.hpp — backward ray-traced re-sampling of the specular total radiance maps after
// the last propagation cycle (VLF §5, last part: "re-sample the directional radiance maps
// on specular surfaces using backwards ray-tracing, following S*D paths only"; the same
// tracing as §6.3). Every ray of a specular face's L_T is replaced by the radiance found
// along its real reflection path, so the maps are geometrically sharp and free of the
// propagation's holes; DESIGN §5 lists it as a switch (PropagateParams::resample).
#pragma once

#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/outward_casters.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

// Specular bounces followed at most (the 8th surface reached still adds its own diffuse
// part, nothing beyond it).
inline constexpr int kResampleMaxBounces = 8;
// A branch of the specular path tree (glass splits it in two) is traced only while its
// weight (the product of the reflectances and transmittances on the way) is at least this;
// a lighter branch adds nothing (at most this fraction of the radiance).
inline constexpr double kResampleMinWeight = 1e-4;
// Ray origins are moved this far (normalised units) along the traced direction.
inline constexpr double kResampleEpsilon = 1e-6;

// The closest hit along `dir` of a ray that leaves face `from` at `origin` (a point of the
// face), starting kResampleEpsilon along, never on `from` or its twin: a planar face,
// either side, is not met again by a ray leaving it, and a hit there is rounding at t ~ 0
// (in the float hierarchy a grazing ray leaving a glass ball met the ball's own polygon).
// False when the ray escapes.
bool trace_leaving(const RayCaster& caster, int from, const Vec3& origin, const Vec3& dir,
                   RayHit& hit);

// Radiance (W m^-2 sr^-1) leaving face `face` at `point` (normalised coordinates, on the
// face) along the unit travel direction `travel` (must leave the face's front side):
// the face's own diffuse part (bilinear P^T radiance) when it is diffuse or emits, plus
// rho_s times the radiance arriving along the mirror path (at glass, Fresnel's R of the
// reflected and 1 - R of the refracted path, resample.cpp), traced recursively through
// specular faces until a non-specular face (its bilinear P^T radiance, emission included),
// an escape or a back face (both 0). `texel_radiance` is texel_radiance(scene, maps) and
// `texel_offset` is TextureMaps::offset. At most `max_bounces` mirror steps are traced.
// Thread-safe.
Rgb specular_path_radiance(const Scene& scene, const RayCaster& caster,
                           const std::vector<Rgb>& texel_radiance,
                           const std::vector<size_t>& texel_offset, int face, const Vec3& point,
                           const Vec3& travel, int max_bounces = kResampleMaxBounces);

// Replaces transport.specular_maps().total — L_T of every specular face, every direction,
// every covered ray — by specular_path_radiance at the ray's point on the face, along the
// ray's travel direction facing * omega_d. Parallel over directions; every ray is written
// by one task, so the result does not depend on the number of threads (the third argument
// is unused: vlf::ThreadLimit governs the threads).
void resample_specular(Transport& transport, const RayCaster& caster, int threads_unused = 0);

// The same resampling a direction at a time, for a caller that consumes the maps direction
// by direction: the bake writer resamples each direction as it makes its rays
// (propagate/main.cpp), so the tracing overlaps the writer's serial compression. The maps
// come out bit-identical to resample_specular's.
class SpecularResampler {
  public:
    // Keeps references to both; reads the transport's texture maps (P^T) once.
    SpecularResampler(Transport& transport, const RayCaster& caster);
    // Resamples direction d's specular L_T. Thread-safe for distinct directions.
    void direction(int d) const;
    // Resamples face f's rays in direction d, `raster` its rasterise_face in d (a caller
    // that rasterises the face anyway passes its own); false, and nothing written, for a
    // face that is not resampled (not specular, no rays in d, or an inner glass face).
    bool face(int d, int f, const FaceRaster& raster) const;
    // Whether face f's rays are resampled (in the directions it has rays in).
    bool resamples(int f) const;

  private:
    Transport& m_transport;
    const RayCaster& m_caster;
    std::vector<Rgb> m_radiance;  // texel_radiance of the texture maps
    OutwardCasters m_outward;     // casts leaving a convex mirror or glass skip its faces
};

}  // namespace vlf
