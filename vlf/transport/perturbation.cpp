#include "vlf/transport/perturbation.hpp"

#include <cmath>
#include <random>

#include "vlf/core/rotation.hpp"

namespace vlf {

double mean_cone_half_angle(const DirectionSet& dirs) {
    // 2*pi*(1 - cos alpha) = mean solid angle.
    return std::acos(1.0 - dirs.mean_solid_angle() / (2.0 * kPi));
}

Mat3 perturbation_rotation(const DirectionSet& dirs, uint64_t seed, int index, int count) {
    std::seed_seq seq{uint32_t(seed), uint32_t(seed >> 32), uint32_t(index)};
    std::mt19937_64 rng(seq);
    auto uniform = [&] { return double(rng() >> 11) * 0x1.0p-53; };
    const double alpha = mean_cone_half_angle(dirs);
    const double theta = alpha * std::sqrt((index - 1 + uniform()) / count);
    const double phi = 2.0 * kPi * uniform();
    const Vec3 axis(-std::sin(phi), std::cos(phi), 0.0);  // tilts +z towards azimuth phi
    return axis_angle(axis, theta);
}

}  // namespace vlf
