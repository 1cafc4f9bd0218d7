#include "vlf/field/texture_maps.hpp"

namespace vlf {

TextureMaps::TextureMaps(const Scene& scene) {
    offset.resize(scene.charts.size() + 1, 0);
    for (size_t c = 0; c < scene.charts.size(); ++c)
        offset[c + 1] = offset[c] + static_cast<size_t>(scene.charts[c].texels.count());
    current.assign(offset.back(), Rgb(0.0));
    next.assign(offset.back(), Rgb(0.0));
    total.assign(offset.back(), Rgb(0.0));
}

Rgb TextureMaps::sum(const std::vector<Rgb>& map, size_t begin, size_t count) {
    Rgb s(0.0);
    for (size_t i = begin; i < begin + count; ++i) s += map[i];
    return s;
}

Rgb TextureMaps::radiance(const Chart& c, size_t texel) const {
    const double a = c.texel_area[texel];
    if (a <= 0.0) return Rgb(0.0);
    return total[offset[c.id] + texel] / (kPi * a);
}

double TextureMaps::radiance(const Chart& c, size_t texel, int channel) const {
    return radiance(c, texel)[channel];
}

}  // namespace vlf
