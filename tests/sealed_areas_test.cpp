// Sealed areas (vlf/scene/sealed_areas.hpp): the part of a face right behind another face is
// taken out of its texel areas exactly; a face farther away, beside, or facing the other
// way takes nothing.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "vlf/scene/scene_loader.hpp"

namespace vlf {
namespace {

// A 2 x 2 wall facing +z at z = 0 and a 0.5 x 0.7 panel in front of it at z = gap,
// facing +z too (its back towards the wall), or facing -z when `facing_wall`.
Scene wall_and_panel(double gap, bool facing_wall) {
    const std::string panel =
        facing_wall ? "[[0.3, 0.2, {0}], [0.3, 0.9, {0}], [0.8, 0.9, {0}], [0.8, 0.2, {0}]]"
                    : "[[0.3, 0.2, {0}], [0.8, 0.2, {0}], [0.8, 0.9, {0}], [0.3, 0.9, {0}]]";
    return load_scene_from_string(
        fmt::format(
            R"({{"materials": {{"w": {{"diffuse": [0.5, 0.5, 0.5], "emission": [1, 1, 1]}}}},
          "objects": [
            {{"type": "polygon", "material": "w",
              "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}},
            {{"type": "polygon", "material": "w", "vertices": {}}}],
          "settings": {{"texel_size": 0.13}}}})",
            fmt::format(fmt::runtime(panel), gap)),
        "sealed.json", ".");
}

double user_area(const Scene& s, const Face& f) {
    double a = 0.0;
    for (double t : s.chart_of(f).texel_area) a += t;
    return a / (s.normalisation.scale * s.normalisation.scale);
}

TEST(SealedAreas, PanelInContactIsCutOutOfTheWallExactly) {
    const Scene s = wall_and_panel(0.001, false);
    ASSERT_GT(s.seal_gap, 0.001 * s.normalisation.scale);
    EXPECT_NEAR(user_area(s, s.faces[0]), 4.0 - 0.35, 1e-9);
    EXPECT_NEAR(user_area(s, s.faces[1]), 0.35, 1e-9);  // the panel keeps its own area
    // A texel wholly behind the panel has none left; one wholly beside it keeps its cell.
    const Face& w = s.faces[0];
    const Chart& wc = s.chart_of(w);
    const double cell = wc.texels.size * wc.texels.size;
    int emptied = 0, whole = 0;
    for (double a : wc.texel_area) {
        emptied += a == 0.0;
        whole += std::abs(a - cell) < 1e-12 * cell;
    }
    EXPECT_GT(emptied, 4);
    EXPECT_GT(whole, 100);
}

TEST(SealedAreas, FarOrFacingPanelsTakeNothing) {
    for (const auto& [gap, facing] : {std::pair{0.5, false}, std::pair{0.001, true}}) {
        const Scene s = wall_and_panel(gap, facing);
        EXPECT_NEAR(user_area(s, s.faces[0]), 4.0, 1e-9) << "gap " << gap << " facing " << facing;
    }
}

}  // namespace
}  // namespace vlf
