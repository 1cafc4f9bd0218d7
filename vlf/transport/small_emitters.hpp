// small_emitters.hpp — lamps smaller than a ray: their light enters the field by a first
// shot of rays cast from them, not through the PSFs (issue 11, docs/propagation.md §11).
//
// The paper's lamps are large polygons: each owns many rays in every direction, and
// VLF §4.4 eq. (3) sends its power along them. A lamp smaller than a ray pixel (a 1 mm LED
// in a room) owns a ray in few directions or none: its power would stay unshot, or leave
// in a handful of beams. Such an emitter's power is instead shot in cycle 1 along
// K cosine-distributed rays from points on it (a Hammersley set: deterministic, stratified),
// each carrying U / K to the first surface it meets: rho_d of it into that surface's texel
// (P^N), rho_s of it on along the mirror reflection, the rest absorbed; rays that leave the
// scene escape and rays on a back face are absorbed there — every watt is in the ledger.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/ledger.hpp"

namespace vlf {

// Charts that emit and whose area is below `pixels` ray pixels of the exchange grid
// (2 / N per side, normalised units).
std::vector<int> small_emitter_charts(const Scene& scene, int resolution, double pixels = 1.0);

// The radical inverse of k in `base` (a Halton coordinate), in [0, 1).
double radical_inverse(uint64_t k, uint64_t base);

// A point on chart c's faces, uniform by area, from three numbers in [0, 1) (the face,
// then a point in it); `face`, if given, is set to the face it lies on.
Vec3 point_on(const Scene& scene, const Chart& c, double u, double v, double w,
              int* face = nullptr);

// The texel of chart c at p (normalised units) that has area, the nearest such in its
// 3 x 3 neighbourhood, else -1.
long nearest_texel(const Chart& c, const Vec3& p);

// What a share of a first shot (this one, or the lamp caustics', lamp_caustics.hpp)
// deposits: P^N per texel, and where the rest went.
struct ShotResult {
    explicit ShotResult(std::vector<Rgb>& n) : next(n) {}
    std::vector<Rgb>& next;  // per texel (TextureMaps order)
    Rgb absorbed{0.0}, absorbed_back{0.0}, escaped{0.0};
    NumericalLoss lost;
    std::vector<uint32_t>* landed = nullptr;  // if given: rays deposited, per texel
};

// Rays [k0, k1) of the K rays of chart `chart`, carrying `power` (its unshot power) in all.
void shoot_rays(const Scene& scene, const RayCaster& caster, const TextureMaps& tex, int chart,
                const Rgb& power, uint64_t k0, uint64_t k1, uint64_t K, ShotResult& out);

}  // namespace vlf
