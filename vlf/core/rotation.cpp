#include "vlf/core/rotation.hpp"

#include <cmath>

namespace vlf {

void orthonormal_basis(const Vec3& n, Vec3& e1, Vec3& e2) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    e1 = Vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    e2 = Vec3(b, sign + n.y * n.y * a, -n.y);
}

Mat3 rotation_to_z(const Vec3& omega) {
    Vec3 e1, e2;
    orthonormal_basis(omega, e1, e2);
    // GLM matrices are column-major: build columns (e1, e2, omega) and transpose so they
    // become rows, i.e. (R v).x = e1.v, (R v).y = e2.v, (R v).z = omega.v.
    return glm::transpose(Mat3(e1, e2, omega));
}

Mat3 axis_angle(const Vec3& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
    const Vec3 a = axis;
    // Columns of the Rodrigues matrix.
    return Mat3(Vec3(t * a.x * a.x + c, t * a.x * a.y + s * a.z, t * a.x * a.z - s * a.y),
                Vec3(t * a.x * a.y - s * a.z, t * a.y * a.y + c, t * a.y * a.z + s * a.x),
                Vec3(t * a.x * a.z + s * a.y, t * a.y * a.z - s * a.x, t * a.z * a.z + c));
}

}  // namespace vlf
