// math.hpp — the graphics-math vocabulary of the library (GLM, double precision).
#pragma once

#include <glm/glm.hpp>
#include <limits>

namespace vlf {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Mat3 = glm::dmat3;
using Rgb = glm::dvec3;  // linear RGB, one value per channel

// The mean of the three channels.
inline double luminance(const Rgb& c) {
    return (c.x + c.y + c.z) / 3.0;
}

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace vlf
