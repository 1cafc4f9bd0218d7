// texture.cpp — bilinear, wrapping lookups of sRGB textures in linear RGB (texture.hpp).
#include "vlf/scene/texture.hpp"

#include <array>
#include <cmath>

namespace vlf {

namespace {

const std::array<double, 256>& srgb_table() {
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[size_t(i)] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return table;
}

int wrap(long i, int n) {
    const long r = i % n;
    return int(r < 0 ? r + n : r);
}

}  // namespace

double srgb_to_linear(uint8_t value) {
    return srgb_table()[value];
}

Rgb Texture::at(const Vec2& uv) const {
    if (width <= 0 || height <= 0) return Rgb(1.0);
    const auto& lut = srgb_table();
    // Continuous texel coordinates with texel (i, j) centred at (i + 0.5, j + 0.5); row 0
    // is the top of the image, v = 1.
    const double x = uv.x * width - 0.5, y = (1.0 - uv.y) * height - 0.5;
    if (!std::isfinite(x) || !std::isfinite(y)) return Rgb(0.0);
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    const long ix = long(fx), iy = long(fy);
    Rgb sum(0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const double w = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty);
            const size_t at =
                (size_t(wrap(iy + dy, height)) * size_t(width) + size_t(wrap(ix + dx, width))) * 3;
            sum += w * Rgb(lut[srgb[at]], lut[srgb[at + 1]], lut[srgb[at + 2]]);
        }
    return sum;
}

Rgb Texture::mean() const {
    const auto& lut = srgb_table();
    Rgb sum(0.0);
    const size_t n = size_t(width) * size_t(height);
    for (size_t i = 0; i < n; ++i)
        sum += Rgb(lut[srgb[3 * i]], lut[srgb[3 * i + 1]], lut[srgb[3 * i + 2]]);
    return n ? sum / double(n) : Rgb(1.0);
}

}  // namespace vlf
