// image_io.hpp — walkthrough images on disk (DESIGN §7 "Output"): OpenEXR (linear HDR,
// half RGB) and PNG (tone-mapped, sRGB). write_image and read_exr are declared in
// render.hpp (the walkthrough API) and implemented in image_io.cpp; this header adds the
// tone-mapping step so tests and tools can reuse it.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/render/render.hpp"

namespace vlf {

// Linear radiance -> 8-bit sRGB: scale by 2^exposure (stops), Reinhard x / (1 + x) per
// channel, sRGB transfer curve, round. Returns width*height*3 bytes, row 0 at the top.
std::vector<uint8_t> tone_map_srgb8(const Image& image, double exposure);

}  // namespace vlf
