// texel_albedo.hpp — a textured material's albedo per texel of its charts (issue 12): the
// mean of Scene::albedo_at over the chart's surface in each texel, which propagation uses
// as rho_d of that texel (receive_step.cpp). Derived from the faces' texture coordinates
// and the textures, so a bake recomputes it on load instead of storing it.
#pragma once

#include "vlf/scene/scene.hpp"

namespace vlf {

// Fills Chart::texel_albedo for every chart whose material has a diffuse texture (and
// clears it elsewhere). Each triangle is sampled at the centres of an n x n subdivision,
// n = ceil(max(4 x its longest edge / the texel size, 2 x the texture pixels it spans)),
// at most 1024: 16 or more samples per texel, 4 or more per texture pixel.
void compute_texel_albedo(Scene& scene);

}  // namespace vlf
