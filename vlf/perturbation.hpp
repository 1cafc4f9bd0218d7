// perturbation.hpp — perturbed PSFs (VLF §5): "a number of stratified samples are
// randomly selected within [the average] solid angle for each propagation iteration. At
// each perturbation, the entire scene is rotated such that the canonical PSF is oriented
// along the new sampled direction." Diffuse receivers then see directions between the
// PSFs, which fills the "holes" that cylindrical beams leave at a distance.
#pragma once

#include <cstdint>

#include "vlf/direction_set.hpp"
#include "vlf/math.hpp"

namespace vlf {

// Half-angle of the cone whose solid angle is the set's mean solid angle 2*pi/l.
double mean_cone_half_angle(const DirectionSet& dirs);

// The rotation of perturbation `index` (1..count) of `cycle`: it tilts +z by an angle
// alpha * sqrt((index - 1 + u) / count) (stratified by area in the cone) towards a random
// azimuth. Deterministic in (seed, cycle, index).
Mat3 perturbation_rotation(const DirectionSet& dirs, uint64_t seed, int cycle, int index,
                           int count);

}  // namespace vlf
