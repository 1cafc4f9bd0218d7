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

struct Texture {
    std::string name;  // as the model file names it
    int width = 0, height = 0;
    std::vector<uint8_t> srgb;  // width x height x 3, row 0 at the top (as image files store it)

    // Linear RGB at (u, v), bilinear between texel centres, wrapping.
    Rgb at(const Vec2& uv) const;
    // The mean linear colour of all texels, and the same kept by finish() (call it once
    // the texels are in place).
    Rgb mean() const;
    Rgb average{1.0};
    void finish() { average = mean(); }
};

// sRGB-encoded 8-bit value to linear [0, 1].
double srgb_to_linear(uint8_t value);

}  // namespace vlf
