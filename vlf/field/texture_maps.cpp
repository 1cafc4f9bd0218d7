#include "vlf/field/texture_maps.hpp"

namespace vlf {

TextureMaps::TextureMaps(const Scene& scene) {
    offset.resize(scene.faces.size() + 1, 0);
    for (size_t f = 0; f < scene.faces.size(); ++f)
        offset[f + 1] = offset[f] + static_cast<size_t>(scene.faces[f].texels.count());
    current.assign(offset.back(), Rgb(0.0));
    next.assign(offset.back(), Rgb(0.0));
    total.assign(offset.back(), Rgb(0.0));
}

Rgb TextureMaps::sum(const std::vector<Rgb>& map, size_t begin, size_t count) {
    Rgb s(0.0);
    for (size_t i = begin; i < begin + count; ++i) s += map[i];
    return s;
}

Rgb TextureMaps::radiance(const Face& f, size_t texel) const {
    const double a = f.texel_area[texel];
    if (a <= 0.0) return Rgb(0.0);
    return total[offset[f.id] + texel] / (kPi * a);
}

double TextureMaps::radiance(const Face& f, size_t texel, int channel) const {
    return radiance(f, texel)[channel];
}

}  // namespace vlf
