// texture.cpp — bilinear, wrapping lookups of sRGB textures in linear RGB (texture.hpp).
#include "vlf/scene/texture.hpp"

#include <algorithm>
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
    // Wrapped into one period first, so huge coordinates stay in range of a long.
    const double u = uv.x - std::floor(uv.x), v = uv.y - std::floor(uv.y);
    const double x = u * width - 0.5, y = (1.0 - v) * height - 0.5;
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

void Texture::finish() {
    average = mean();
    levels.clear();
    const auto& lut = srgb_table();
    Level base;
    base.width = width;
    base.height = height;
    base.rgb.resize(srgb.size());
    for (size_t i = 0; i < srgb.size(); ++i) base.rgb[i] = float(lut[srgb[i]]);
    levels.push_back(std::move(base));
    while (levels.back().width > 1 || levels.back().height > 1) {
        const Level& a = levels.back();
        Level b;
        b.width = std::max(1, (a.width + 1) / 2);
        b.height = std::max(1, (a.height + 1) / 2);
        b.rgb.assign(size_t(b.width) * size_t(b.height) * 3, 0.0f);
        for (int y = 0; y < b.height; ++y)
            for (int x = 0; x < b.width; ++x)
                for (int c = 0; c < 3; ++c) {
                    double sum = 0.0;
                    int n = 0;
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx) {
                            const int sx = 2 * x + dx, sy = 2 * y + dy;
                            if (sx >= a.width || sy >= a.height) continue;
                            sum +=
                                a.rgb[(size_t(sy) * size_t(a.width) + size_t(sx)) * 3 + size_t(c)];
                            ++n;
                        }
                    b.rgb[(size_t(y) * size_t(b.width) + size_t(x)) * 3 + size_t(c)] =
                        float(sum / n);
                }
        levels.push_back(std::move(b));
    }
}

namespace {

Rgb bilinear(const Texture::Level& l, const Vec2& uv) {
    const double u = uv.x - std::floor(uv.x), v = uv.y - std::floor(uv.y);
    const double x = u * l.width - 0.5, y = (1.0 - v) * l.height - 0.5;
    if (!std::isfinite(x) || !std::isfinite(y)) return Rgb(0.0);
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    Rgb sum(0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const double w = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty);
            const size_t at = (size_t(wrap(long(fy) + dy, l.height)) * size_t(l.width) +
                               size_t(wrap(long(fx) + dx, l.width))) *
                              3;
            sum += w * Rgb(l.rgb[at], l.rgb[at + 1], l.rgb[at + 2]);
        }
    return sum;
}

}  // namespace

Rgb Texture::filtered(const Vec2& uv, double pixels) const {
    if (levels.empty() || !(pixels > 1.0)) return at(uv);
    const double level = std::min(std::log2(pixels), double(levels.size() - 1));
    const size_t lo = size_t(level);
    const size_t hi = std::min(lo + 1, levels.size() - 1);
    const double t = level - double(lo);
    return (1.0 - t) * bilinear(levels[lo], uv) + t * bilinear(levels[hi], uv);
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
