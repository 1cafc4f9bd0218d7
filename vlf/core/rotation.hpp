// rotation.hpp — the rotation M_i of a PSF: it takes the PSF direction to the canonical
// direction (0,0,1) (VLF §3: "the scene can be rotated such that omega_i is mapped to
// direction (0,0,1) and then the rasterisation carried out in the canonical space").
#pragma once

#include "vlf/core/math.hpp"

namespace vlf {

// Orthonormal basis (e1, e2, n) with e1 x e2 = n, continuous except at n.z = -1
// (Duff et al. 2017, "Building an orthonormal basis, revisited").
void orthonormal_basis(const Vec3& n, Vec3& e1, Vec3& e2);

// R with R * omega = (0,0,1); rows of R are (e1, e2, omega). omega must be unit.
Mat3 rotation_to_z(const Vec3& omega);

// Rotation by `angle` radians about the unit `axis` (Rodrigues).
Mat3 axis_angle(const Vec3& axis, double angle);

}  // namespace vlf
