// specular.hpp — transfers *to* specular receivers (VLF §4.2 "Diffuse to Specular", §4.3
// "Specular to Specular"; DESIGN §5 "Specular receiver").
//
// Light arriving at a mirror P along PSF omega is reflected about P's normal; the mirrored
// direction generally is no PSF direction, so its power is split over the three enclosing
// directions by barycentric weight (§4.2). Within each target direction omega', every ray
// of P's unshot radiance map L_U(omega', P) *gathers* by backward mapping: its point on P
// is projected back into the source PSF and picks up the incoming radiance there, so no
// target cell is left as a hole. The gathered pattern is then scaled so the power
// deposited equals w_i * rho_s * (power received), channel by channel: exact energy.
//
// A source is recorded while its direction is processed (phase 1 of a cycle, in parallel
// over directions); the gathers run afterwards (phase 2, in parallel over target
// directions). Each target (omega', P) is written by one task, in source order, so the
// result is independent of thread count.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct SpecularSource {
    int face = 0;  // the face whose unshot maps it is gathered into (a dielectric: either side)
    Mat3 rotation{1.0};  // of the source PSF (true or perturbed direction)
    int resolution = 0;  // of the source PSF's ray grid (N, or N * supersample)
    int i0 = 0, j0 = 0;  // window origin in source pixels
    int width = 0, height = 0;
    std::vector<RgbF> radiance;    // incoming radiance per window pixel
    std::vector<uint8_t> covered;  // 1 where the face covers the pixel
    int targets = 0;
    std::array<int, 3> target_direction{};
    // The power deposited into each target direction (of rho_s * received, or Fresnel's
    // share at glass), normalised units.
    std::array<Rgb, 3> target_power{};
};

// The enclosing PSF directions of `outgoing` (a travel direction leaving face `f`'s front:
// the mirrored direction, or the refracted one leaving a dielectric's twin) on which `f`
// shows its front and has rays (`coverage(d, f)`). An enclosing direction in which `f`
// itself has no ray (a facet smaller than a ray pixel, as on a finely tessellated ball)
// goes to the nearest face of f's chart that has rays there and shows its front: the light
// moves by a facet instead of being lost. Each target names its face; returns how many
// (weights renormalised).
struct SpecularTarget {
    int face = 0;
    int direction = 0;
    double weight = 0.0;
};
int chart_specular_targets(const Scene& scene, const DirectionSet& dirs, const Face& f,
                           const Vec3& outgoing, const Coverage& coverage,
                           std::array<SpecularTarget, 3>& out);

// Phase 2: gathers every source into maps.unshot_next, adding to what it holds (a cycle
// zeroes it once, then every pass of the cycle, perturbed or not, adds its deposits).
// `rotations[d]` is the rotation of PSF d; `ray_area` = (2/N)^2.
// Only the directions `maps` holds are gathered into (maps.first..last: an MPI rank's own;
// each target is still written in source order, so every rank writes what one process
// would). Returns, per held direction, the power that single-precision storage rounded away
// (deposited minus stored, either sign), for the ledger to sum in direction order.
std::vector<Rgb> gather_specular(const Scene& scene, const DirectionSet& dirs,
                                 const std::vector<Mat3>& rotations, int resolution, int tile,
                                 const std::vector<SpecularSource>& sources, RadianceMaps& maps);

}  // namespace vlf
