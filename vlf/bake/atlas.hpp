// atlas.hpp — where each chart's texel grid sits in the lightmap atlas (DESIGN §6,
// docs/bake-format.md "lightmaps.exr"): shelf packing, tallest charts first (ties by width,
// then chart id), a 1-texel gutter of zeros between rectangles, so the layout is a pure
// function of the texel grids.
#pragma once

#include <vector>

#include "vlf/scene/scene.hpp"

namespace vlf {

// A chart's rectangle in the atlas, in texels: texel (i, j) is atlas pixel (x + i, y + j).
struct AtlasRect {
    int chart = 0, x = 0, y = 0, width = 0, height = 0;
};

struct Atlas {
    int width = 1, height = 1;
    std::vector<AtlasRect> rects;  // per chart, in chart order
};

Atlas pack_atlas(const Scene& scene);

}  // namespace vlf
