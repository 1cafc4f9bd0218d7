// texture.hpp — diffuse colour textures (issue 12): an 8-bit sRGB image read from a model
// file, looked up by texture coordinates with bilinear filtering and repeat wrapping, in
// linear RGB. Coordinates follow OBJ and OpenGL: u to the right, v up, (0, 0) the image's
// bottom-left corner (assimp gives glTF's coordinates the same way round).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

// The largest texture a scene or a bake holds, and the longest name kept.
inline constexpr int64_t kMaxTextureTexels = int64_t(1) << 28;
inline constexpr size_t kMaxTextureName = 4096;

struct Texture {
    std::string name;  // as the model file names it
    int width = 0, height = 0;
    std::vector<uint8_t> srgb;  // width x height x 3, row 0 at the top (as image files store it)

    // Linear RGB at (u, v), bilinear between texel centres, wrapping.
    Rgb at(const Vec2& uv) const;
    // The mean linear colour of all texels; set by finish().
    Rgb average{1.0};
    // Call once the texels are in place: sets `average` and builds the mip levels.
    void finish();

    // The mean colour over a footprint about `pixels` texture pixels wide around (u, v):
    // trilinear between box-filtered mip levels (pixels <= 1 is at()).
    Rgb filtered(const Vec2& uv, double pixels) const;

    // Linear RGB mip levels (level 0 = the texels), each half the last, box-filtered.
    struct Level {
        int width = 0, height = 0;
        std::vector<float> rgb;
    };
    std::vector<Level> levels;
};

}  // namespace vlf
