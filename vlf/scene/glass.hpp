// glass.hpp — what a segment of a ray inside glass keeps (scene.hpp Material::dielectric):
// Beer-Lambert exp(-sigma d), d in user units, shared by propagation and rendering.
#pragma once

#include "vlf/scene/scene.hpp"

namespace vlf {

// The transmittance exp(-sigma d_user) per channel of a ray segment of normalised length
// `length` that ended on face f: the segment ran inside glass when f is a dielectric's inner
// face (its front looks into the glass, and rays meet fronts only). 1 otherwise.
inline Rgb glass_transmittance(const Scene& scene, const Face& f, double length) {
    if (!f.inner) return Rgb(1.0);
    const Material& m = scene.material_of(f);
    if (!m.is_absorbing()) return Rgb(1.0);
    return glm::exp(-m.absorption * (length / scene.normalisation.scale));
}

}  // namespace vlf
