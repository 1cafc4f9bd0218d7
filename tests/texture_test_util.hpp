// texture_test_util.hpp — fixtures of the texture-map post-processing tests (rim pools,
// Gaussian filter): faces with rim texels of every size and fields of exitance on them.
#pragma once

#include <gtest/gtest.h>

#include "test_util.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace vlf::test {

// tests/scenes/odd-faces.json: a rectangle of 7.3 x 4.6 texels and a triangle, so rim
// texels of every size.
inline Scene odd_faces() {
    return load_scene(source_path("tests/scenes/odd-faces.json"));
}

// P = B * area: a field of exitance B(face, texel) in the next maps.
template <class F>
void fill(const Scene& scene, TextureMaps& maps, F&& exitance) {
    for (const Chart& f : scene.charts)
        for (size_t k = 0; k < maps.count(f.id); ++k)
            maps.next[maps.begin(f.id) + k] = Rgb(exitance(f, k)) * f.texel_area[k];
}

inline double face_power(const TextureMaps& maps, const Chart& f) {
    return TextureMaps::sum(maps.next, maps.begin(f.id), maps.count(f.id)).x;
}

// Every texel with area inside its face shows exitance `value` (to rounding).
inline void expect_uniform(const Scene& scene, const TextureMaps& maps, double value) {
    for (const Chart& f : scene.charts)
        for (size_t k = 0; k < maps.count(f.id); ++k) {
            if (f.texel_area[k] <= 0.0) continue;
            EXPECT_NEAR(maps.next[maps.begin(f.id) + k].x / f.texel_area[k], value, 1e-12 * value)
                << "chart " << f.id << " texel " << k << " (inside "
                << f.texel_area[k] / (f.texels.size * f.texels.size) << ")";
        }
}

}  // namespace vlf::test
