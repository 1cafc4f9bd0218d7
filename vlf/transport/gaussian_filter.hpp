// gaussian_filter.hpp — energy-preserving Gaussian filtering of the next texture maps
// after perturbed transfers (VLF §5: "Gaussian filtering is required on the next diffuse
// texture maps to remove the high frequencies that were introduced ... performed just
// before the current and next diffuse maps are swapped").
//
// Written as an exchange of power between texels of one face: texels i and j trade
// w_ij (B_j - B_i), B = power / area inside the face, with symmetric weights
// w_ij = A_i A_j G(|i - j|) / (a * sum G) (a the full texel area, the sum over the whole
// kernel). Every trade is antisymmetric, so no power is created, lost or moved off the
// face; a uniform B stays uniform (rims and partial texels included); inside a face it is
// the normalised Gaussian of B; texels near the rim, with fewer neighbours, keep more of
// their own value instead of being darkened (docs/propagation.md §6).
#pragma once

#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

void gaussian_filter_next(const Scene& scene, TextureMaps& maps, double sigma_texels);

}  // namespace vlf
