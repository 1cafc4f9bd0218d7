// image_io.hpp — walkthrough images on disk (DESIGN §7 "Output"): OpenEXR (linear HDR,
// half RGB) and PNG (tone-mapped, sRGB): the image types, writing, reading, and the
// tone-mapping step, which the interactive window and tests reuse.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

// Linear radiance image, row-major, row 0 at the top.
struct Image {
    int width = 0, height = 0;
    std::vector<Rgb> pixels;
    Rgb& at(int x, int y) { return pixels[size_t(y) * width + x]; }
    const Rgb& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

// One flag per pixel, row-major, row 0 at the top (the layout of Image).
struct PixelMask {
    int width = 0, height = 0;
    std::vector<uint8_t> on;
    bool at(int x, int y) const { return on[size_t(y) * width + x] != 0; }
};

// Writes .exr (linear, half RGB) or .png (exposure in stops, then a filmic-free Reinhard
// tone map and sRGB encoding) atomically (temporary name, rename). Throws Error naming the
// path for an unknown extension or an I/O failure.
void write_image(const std::string& path, const Image& image, double exposure = 0.0);
Image read_exr(const std::string& path);  // throws Error

// Linear radiance -> 8-bit sRGB: scale by 2^exposure (stops), Reinhard x / (1 + x) per
// channel, sRGB transfer curve, round. Returns width*height*3 bytes, row 0 at the top.
std::vector<uint8_t> tone_map_srgb8(const Image& image, double exposure);

}  // namespace vlf
