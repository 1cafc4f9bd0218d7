// Continuous clipping (VLF §4.2, vlf/transport/texel_clip.hpp): the overlaps of a beam's footprint
// with a texel grid are exact areas, they partition the footprint, and the rim cells
// reach outwards. Checked against an independent clip of the quad by each cell.
#include "vlf/transport/texel_clip.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <vector>

namespace vlf {
namespace {

using Polygon = std::vector<Vec2>;

// Keeps the part of `p` with sign * (coord - c) >= 0 (the textbook one-plane clip).
Polygon keep(const Polygon& p, int axis, double c, double sign) {
    Polygon out;
    for (size_t k = 0; k < p.size(); ++k) {
        const Vec2 a = p[k], b = p[(k + 1) % p.size()];
        const double da = sign * (a[axis] - c), db = sign * (b[axis] - c);
        if (da >= 0) out.push_back(a);
        if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    return out;
}

double area(const Polygon& p) {
    double s = 0;
    for (size_t k = 0; k < p.size(); ++k) {
        const Vec2 a = p[k], b = p[(k + 1) % p.size()];
        s += a.x * b.y - a.y * b.x;
    }
    return 0.5 * std::abs(s);
}

// Area of the quad inside cell (i, j) of a W x H grid whose rim cells are unbounded
// outwards.
double reference_overlap(const Vec2 q[4], int i, int j, int W, int H) {
    Polygon p(q, q + 4);
    if (i > 0) p = keep(p, 0, i, 1);
    if (i < W - 1) p = keep(p, 0, i + 1, -1);
    if (j > 0) p = keep(p, 1, j, 1);
    if (j < H - 1) p = keep(p, 1, j + 1, -1);
    return p.size() >= 3 ? area(p) : 0.0;
}

void check_quad(const Vec2 q[4], int W, int H) {
    std::vector<TexelOverlap> ov;
    const int n = clip_quad_to_grid(q, W, H, ov);
    ASSERT_EQ(n, static_cast<int>(ov.size()));
    std::map<uint32_t, double> got;
    double sum = 0;
    for (const TexelOverlap& o : ov) {
        ASSERT_LT(o.texel, uint32_t(W * H));
        ASSERT_EQ(got.count(o.texel), 0u) << "texel " << o.texel << " listed twice";
        ASSERT_GT(o.area, 0.0f);
        got[o.texel] = o.area;
        sum += o.area;
    }
    const double whole = area(Polygon(q, q + 4));
    EXPECT_NEAR(sum, whole, 1e-6 * whole + 1e-12) << "the overlaps must partition the quad";
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const double want = reference_overlap(q, i, j, W, H);
            const auto it = got.find(uint32_t(j * W + i));
            const double have = it == got.end() ? 0.0 : it->second;
            EXPECT_NEAR(have, want, 1e-6 * whole + 1e-9) << "cell " << i << "," << j;
        }
}

TEST(TexelClip, RandomParallelogramsMatchAnIndependentClip) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> pos(-1.0, 9.0), len(-2.5, 2.5);
    for (int trial = 0; trial < 400; ++trial) {
        const Vec2 c(pos(rng), pos(rng)), ax(len(rng), len(rng)), ay(len(rng), len(rng));
        const Vec2 q[4] = {c - ax - ay, c + ax - ay, c + ax + ay, c - ax + ay};
        SCOPED_TRACE(trial);
        check_quad(q, 8, 6);
    }
}

TEST(TexelClip, QuadInsideOneCellKeepsItsArea) {
    const Vec2 q[4] = {{2.1, 3.1}, {2.6, 3.2}, {2.7, 3.8}, {2.2, 3.7}};
    std::vector<TexelOverlap> ov;
    ASSERT_EQ(clip_quad_to_grid(q, 5, 5, ov), 1);
    EXPECT_EQ(ov[0].texel, 3u * 5 + 2);
    EXPECT_NEAR(ov[0].area, area(Polygon(q, q + 4)), 1e-7);
}

TEST(TexelClip, RimCellsTakeWhatSpillsOver) {
    // Half of a unit square hangs off the left edge of a 4 x 4 grid: all of it lands on
    // column 0, split between rows 1 and 2.
    const Vec2 q[4] = {{-0.5, 1.5}, {0.5, 1.5}, {0.5, 2.5}, {-0.5, 2.5}};
    std::vector<TexelOverlap> ov;
    clip_quad_to_grid(q, 4, 4, ov);
    ASSERT_EQ(ov.size(), 2u);
    for (const TexelOverlap& o : ov) {
        EXPECT_EQ(o.texel % 4, 0u);
        EXPECT_NEAR(o.area, 0.5, 1e-7);
    }
    // Entirely outside, beyond a corner: the corner cell takes it whole.
    const Vec2 far[4] = {{10, 10}, {11, 10}, {11, 11}, {10, 11}};
    ov.clear();
    ASSERT_EQ(clip_quad_to_grid(far, 4, 4, ov), 1);
    EXPECT_EQ(ov[0].texel, 15u);
    EXPECT_NEAR(ov[0].area, 1.0, 1e-7);
}

TEST(TexelClip, VerticesOnGridLinesAreNotDoubleCounted) {
    // A square whose corners sit exactly on grid lines covers four cells exactly.
    const Vec2 q[4] = {{1, 1}, {3, 1}, {3, 3}, {1, 3}};
    check_quad(q, 5, 5);
    std::vector<TexelOverlap> ov;
    clip_quad_to_grid(q, 5, 5, ov);
    EXPECT_EQ(ov.size(), 4u);
    // A diamond through grid vertices.
    const Vec2 d[4] = {{2, 1}, {3, 2}, {2, 3}, {1, 2}};
    check_quad(d, 5, 5);
}

}  // namespace
}  // namespace vlf

namespace vlf {
namespace {

// The footprint weights of a face's covered rays (clip_footprint_to_grid) are unbiased:
// averaged over the position of the ray grid (random phase) and over footprint shapes,
// every texel receives weight in proportion to its area inside the face, rim texels
// included. Without the mirrored spill a rim texel gets ~70 % of its share at the edge.
TEST(TexelClip, FootprintWeightsAreUnbiasedAtTheRim) {
    // A triangle in texel coordinates over a 9 x 7 grid: oblique edges, rim texels of
    // every size, two acute corners.
    const std::vector<Vec2> poly = {{0.3, 0.2}, {8.6, 1.1}, {2.2, 6.7}};
    const int W = 9, H = 7;
    std::vector<double> inside(W * H, 0.0), got(W * H, 0.0);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            // Area of the cell inside the triangle, by the midpoint rule.
            double a = 0.0;
            const int n = 400;  // midpoint rule on the cell
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const Vec2 p(i + (x + 0.5) / n, j + (y + 0.5) / n);
                    bool in = true;
                    for (int e = 0; e < 3; ++e) {
                        const Vec2 s = poly[e], d = poly[(e + 1) % 3] - s;
                        in = in && d.x * (p.y - s.y) - d.y * (p.x - s.x) >= 0;
                    }
                    a += in ? 1.0 / (double(n) * n) : 0.0;
                }
            inside[j * W + i] = a;
        }
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int trials = 3000;
    double total_area_weight = 0.0;
    for (int t = 0; t < trials; ++t) {
        // A footprint: pixel edges dx, dy in texel units (rotated, sheared, stretched as an
        // oblique beam's is), lattice of centres with a random phase.
        const double ang = 6.283185307179586 * u(rng), shear = u(rng) - 0.5,
                     stretch = 1.0 / (0.3 + 0.7 * u(rng));
        const Vec2 dx = Vec2(std::cos(ang), std::sin(ang)) * (0.8 * stretch);
        const Vec2 dy = Vec2(-std::sin(ang), std::cos(ang)) * 0.8 + dx * shear;
        const double cell_area = std::abs(dx.x * dy.y - dx.y * dy.x);
        const Vec2 phase = dx * u(rng) + dy * u(rng);
        std::vector<TexelOverlap> ov;
        for (int a = -40; a <= 40; ++a)
            for (int b = -40; b <= 40; ++b) {
                const Vec2 c = phase + dx * double(a) + dy * double(b);
                bool in = true;
                for (int e = 0; e < 3; ++e) {
                    const Vec2 s = poly[e], d = poly[(e + 1) % 3] - s;
                    in = in && d.x * (c.y - s.y) - d.y * (c.x - s.x) >= 0;
                }
                if (!in) continue;  // the ray's centre misses the face: not covered
                const Vec2 q[4] = {c - dx * 0.5 - dy * 0.5, c + dx * 0.5 - dy * 0.5,
                                   c + dx * 0.5 + dy * 0.5, c - dx * 0.5 + dy * 0.5};
                ov.clear();
                clip_footprint_to_grid(q, polygon_rim(poly), W, H, ov);
                double sum = 0.0;
                for (const TexelOverlap& o : ov) sum += o.area;
                ASSERT_GT(sum, 0.0);
                // A beam of power cell_area (unit irradiance) spread by its weights.
                for (const TexelOverlap& o : ov) got[o.texel] += cell_area * o.area / sum;
            }
        total_area_weight += 1.0;
    }
    int rim = 0;
    for (int k = 0; k < W * H; ++k) {
        if (inside[k] < 0.3) continue;  // slivers: too few samples for a 3 % check
        const double ratio = got[k] / total_area_weight / inside[k];
        EXPECT_NEAR(ratio, 1.0, 0.03)
            << "texel " << k % W << "," << k / W << " inside " << inside[k];
        rim += inside[k] < 0.999;
    }
    EXPECT_GT(rim, 8);
}

}  // namespace
}  // namespace vlf
