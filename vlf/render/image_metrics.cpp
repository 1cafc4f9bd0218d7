#include "vlf/render/image_metrics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

void check_sizes(const Image& a, const Image& ref, const char* what) {
    if (a.width != ref.width || a.height != ref.height || a.pixels.size() != ref.pixels.size())
        throw Error(fmt::format("{}: image sizes differ ({}x{} vs {}x{})", what, a.width, a.height,
                                ref.width, ref.height));
}

void check_mask(const Image& ref, const PixelMask& m, const char* what) {
    if (m.width != ref.width || m.height != ref.height || m.on.size() != ref.pixels.size())
        throw Error(fmt::format("{}: mask is {}x{}, the images {}x{}", what, m.width, m.height,
                                ref.width, ref.height));
}

// sqrt(num / den) with the conventions of relative_rmse for empty sums.
double ratio_root(double num, double den) {
    return den > 0.0 ? std::sqrt(num / den) : (num > 0.0 ? kInfinity : 0.0);
}

double rmse_over(const Image& a, const Image& ref, const PixelMask* where) {
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < a.pixels.size(); ++k) {
        if (where && !where->on[k]) continue;
        const Rgb d = a.pixels[k] - ref.pixels[k];
        num += glm::dot(d, d);
        den += glm::dot(ref.pixels[k], ref.pixels[k]);
    }
    return ratio_root(num, den);
}

}  // namespace

PixelMask away_from(const PixelMask& mask, int radius) {
    if (radius < 0) throw Error("away_from: radius must be >= 0");
    PixelMask out;
    out.width = mask.width;
    out.height = mask.height;
    out.on.assign(mask.on.size(), 1);
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x) {
            if (!mask.at(x, y)) continue;
            for (int j = std::max(0, y - radius); j <= std::min(mask.height - 1, y + radius); ++j)
                for (int i = std::max(0, x - radius); i <= std::min(mask.width - 1, x + radius);
                     ++i)
                    out.on[size_t(j) * out.width + i] = 0;
        }
    return out;
}

double relative_rmse(const Image& a, const Image& ref) {
    check_sizes(a, ref, "relative_rmse");
    return rmse_over(a, ref, nullptr);
}

double relative_rmse(const Image& a, const Image& ref, const PixelMask& where) {
    check_sizes(a, ref, "relative_rmse");
    check_mask(ref, where, "relative_rmse");
    return rmse_over(a, ref, &where);
}

Rgb mean_ratio(const Image& a, const Image& ref, const PixelMask& where) {
    check_sizes(a, ref, "mean_ratio");
    check_mask(ref, where, "mean_ratio");
    Rgb sa(0.0), sr(0.0);
    for (size_t k = 0; k < a.pixels.size(); ++k)
        if (where.on[k]) {
            sa += a.pixels[k];
            sr += ref.pixels[k];
        }
    Rgb r;
    for (int c = 0; c < 3; ++c)
        r[c] = sr[c] != 0.0 ? sa[c] / sr[c] : (sa[c] == 0.0 ? 1.0 : kInfinity);
    return r;
}

ImageError image_error(const Image& a, const Image& ref, const PixelMask& emitters) {
    check_sizes(a, ref, "image_error");
    check_mask(ref, emitters, "image_error");
    const PixelMask away = away_from(emitters);
    ImageError e;
    e.rmse = rmse_over(a, ref, nullptr);
    e.rmse_away = rmse_over(a, ref, &away);
    e.ratio_away = mean_ratio(a, ref, away);
    e.away_pixels = size_t(std::count(away.on.begin(), away.on.end(), 1));
    e.pixels = a.pixels.size();
    return e;
}

}  // namespace vlf
