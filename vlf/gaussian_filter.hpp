// gaussian_filter.hpp — energy-preserving Gaussian filtering of the next texture maps
// after perturbed transfers (VLF §5: "Gaussian filtering is required on the next diffuse
// texture maps to remove the high frequencies that were introduced ... performed just
// before the current and next diffuse maps are swapped").
//
// Each texel spreads its power over the texels of its own face within 3 sigma, weighted by
// the Gaussian and by how much of the receiving texel lies inside the polygon, and the
// weights of each source texel are normalised to 1: no power is created, lost or moved off
// the face.
#pragma once

#include "vlf/scene.hpp"
#include "vlf/texture_maps.hpp"

namespace vlf {

void gaussian_filter_next(const Scene& scene, TextureMaps& maps, double sigma_texels);

}  // namespace vlf
