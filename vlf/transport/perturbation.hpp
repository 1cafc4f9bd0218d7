// perturbation.hpp — perturbed PSFs (VLF §5): "a number of stratified samples are
// randomly selected within [the average] solid angle for each propagation iteration. At
// each perturbation, the entire scene is rotated such that the canonical PSF is oriented
// along the new sampled direction." Diffuse receivers then see directions between the
// PSFs, which fills the "holes" that cylindrical beams leave at a distance.
#pragma once

#include <cstdint>

#include "vlf/core/math.hpp"
#include "vlf/field/direction_set.hpp"

namespace vlf {

// Half-angle of the cone whose solid angle is the set's mean solid angle 2*pi/l.
double mean_cone_half_angle(const DirectionSet& dirs);

// The rotation of perturbation `index` (1..count): it tilts +z by an angle
// alpha * sqrt((index - 1 + u) / count) (stratified by area in the cone) towards a random
// azimuth. Deterministic in (seed, index). The paper draws new samples every cycle; VLF
// draws one stratified set per run and reuses it in every cycle, so each perturbed
// direction's geometry (PSF, footprints, exchange partners) is built once and cached like
// the true directions' (docs/propagation.md §5): P perturbations cost P more passes of
// transfer, not P more rasterisations per cycle.
Mat3 perturbation_rotation(const DirectionSet& dirs, uint64_t seed, int index, int count);

}  // namespace vlf
