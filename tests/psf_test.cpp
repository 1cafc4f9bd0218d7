// PSF rasterisation: coverage against projected area, fill-rule partitions, bad parameters.
#include "vlf/field/psf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

// Covered rays of each face in one PSF.
std::vector<int64_t> covered_per_face(const Psf& psf, size_t faces) {
    std::vector<int64_t> c(faces, 0);
    for (const Tile& t : psf.tiles)
        for (const Fragment& f : t.fragments) c[f.face] += f.covered;
    return c;
}

double projected_perimeter(const Face& f, const Mat3& r) {
    double p = 0.0;
    for (size_t i = 0; i < f.vertices.size(); ++i) {
        const Vec3 a = r * f.vertices[i], b = r * f.vertices[(i + 1) % f.vertices.size()];
        p += std::hypot(a.x - b.x, a.y - b.y);
    }
    return p;
}

TEST(PsfRotation, MapsDirectionToZ) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    for (int i = 0; i < 1000; ++i) {
        Vec3 d = glm::normalize(Vec3(g(rng), g(rng), g(rng)));
        const Mat3 r = rotation_to_z(d);
        const Vec3 z = r * d;
        EXPECT_NEAR(z.x, 0.0, 1e-12);
        EXPECT_NEAR(z.y, 0.0, 1e-12);
        EXPECT_NEAR(z.z, 1.0, 1e-12);
        EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);  // a rotation, not a reflection
    }
}

// Covered rays x ray cross-section = projected area, within the perimeter's worth of rays.
TEST(PsfCoverage, CoveredAreaMatchesProjectedArea) {
    const Scene scene = load_scene(test::source_path("scenes/cornell.json"));
    const DirectionSet dirs(129);
    const int N = 64;
    int checked = 0;
    for (int d = 0; d < dirs.size(); ++d) {
        const Psf psf = rasterise_psf(scene, dirs.direction(d), d, N, 8);
        const auto covered = covered_per_face(psf, scene.faces.size());
        for (const Face& f : scene.faces) {
            const double nz = std::abs(glm::dot(f.normal, dirs.direction(d)));
            const double projected = f.area * nz;
            const double raster = covered[f.id] * psf.ray_area();
            const double tolerance = projected_perimeter(f, psf.rotation) * (2.0 / N);
            EXPECT_LE(std::abs(raster - projected), tolerance)
                << "face " << f.id << " direction " << d;
            ++checked;
        }
    }
    EXPECT_GT(checked, 1000);
}

// The same property with a tight statistical check: over many directions the signed
// error averages out (a biased fill rule — e.g. closed intervals — fails this).
TEST(PsfCoverage, FillRuleIsUnbiased) {
    const Scene scene =
        test::make_scene({{{-0.5, -0.4, 0.1}, {0.45, -0.5, 0.0}, {0.3, 0.55, -0.1}}});
    const DirectionSet dirs(2049);
    double signed_sum = 0.0, projected_sum = 0.0;
    for (int d = 0; d < dirs.size(); ++d) {
        const Psf psf = rasterise_psf(scene, dirs.direction(d), d, 32, 8);
        const double nz = std::abs(glm::dot(scene.faces[0].normal, dirs.direction(d)));
        signed_sum += covered_per_face(psf, 1)[0] * psf.ray_area() - scene.faces[0].area * nz;
        projected_sum += scene.faces[0].area * nz;
    }
    EXPECT_LT(std::abs(signed_sum) / projected_sum, 0.01);
}

// Two triangles sharing an edge, and a fan around a shared vertex: every ray of the
// union is covered exactly once (no gaps, no double coverage) in every direction.
TEST(PsfFillRule, SharedEdgesPartitionTheRays) {
    std::vector<std::vector<Vec3>> fan;
    const Vec3 c(0.01, -0.02, 0.0);
    const int k = 7;
    for (int i = 0; i < k; ++i) {
        const double a0 = 2 * kPi * i / k, a1 = 2 * kPi * (i + 1) / k;
        fan.push_back({c, Vec3(0.8 * std::cos(a0), 0.8 * std::sin(a0), 0.1 * std::sin(3 * a0)),
                       Vec3(0.8 * std::cos(a1), 0.8 * std::sin(a1), 0.1 * std::sin(3 * a1))});
    }
    // Close the fan's rim by wrapping vertex k onto vertex 0 exactly.
    fan.back()[2] = fan.front()[1];
    const Scene scene = test::make_scene(fan);
    const DirectionSet dirs(129);
    for (int d = 0; d < dirs.size(); ++d) {
        const Psf psf = rasterise_psf(scene, dirs.direction(d), d, 64, 8);
        // Per ray, count front-facing and back-facing coverage separately: the fan is a
        // single-sheeted surface except where it folds, so each ray is covered by at most
        // one face of each facing... and the hull of the fan must be covered exactly once
        // by the projection when the fan does not fold in projection.
        std::map<long, int> count;
        for (const Tile& t : psf.tiles)
            for (const Fragment& f : t.fragments)
                t.edge_table(f).for_each_ray([&](int u, int v, int) {
                    count[(long)(t.t * 8 + v) * 64 + (t.s * 8 + u)] += f.facing;
                });
        // Each face's facing is the same sign where the fan does not fold; the fan is
        // nearly flat, so for directions not grazing it no ray may be counted twice.
        const double nz = std::abs(dirs.direction(d).z);
        if (nz < 0.3) continue;
        for (const auto& [ray, c] : count) EXPECT_LE(std::abs(c), 1) << "direction " << d;
        // Total coverage equals the sum of fragments (no overlaps, checked above), and the
        // union has no holes: compare with the coverage of the fan's convex rim polygon.
        std::vector<Vec3> rim;
        for (const auto& tri : fan) rim.push_back(tri[1]);
        const Scene hull = test::make_scene({rim});
        const Psf hp = rasterise_psf(hull, dirs.direction(d), d, 64, 8);
        int64_t hull_rays = covered_per_face(hp, 1)[0];
        EXPECT_EQ(static_cast<int64_t>(count.size()), hull_rays) << "direction " << d;
    }
}

// Facets smaller than a ray (a tessellated ball's, most of which cover no ray centre in a
// direction, and which face_rows turns away before their row spans): a tilted flat
// square cut into 2 x 48 x 48 triangles covers, in every direction, exactly the rays the
// square itself covers, each once. A facet that dropped a ray it covers leaves a hole here.
TEST(PsfFillRule, FacetsSmallerThanARayPartitionTheRays) {
    const int n = 48;
    const Vec3 o(-0.43, -0.37, 0.05), ex(0.81, 0.07, 0.21), ey(-0.11, 0.77, 0.17);
    auto at = [&](int i, int j) { return o + ex * (double(i) / n) + ey * (double(j) / n); };
    std::vector<std::vector<Vec3>> facets;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            facets.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            facets.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    const Scene fine = test::make_scene(facets);
    const Scene whole = test::make_scene({{at(0, 0), at(n, 0), at(n, n), at(0, n)}});
    const DirectionSet dirs(129);
    const int N = 32;  // a ray is 1/16 of a unit: each facet is a fraction of one
    int64_t rays = 0;
    for (int d = 0; d < dirs.size(); ++d) {
        const Psf a = rasterise_psf(fine, dirs.direction(d), d, N, 8);
        const Psf b = rasterise_psf(whole, dirs.direction(d), d, N, 8);
        std::map<long, int> fine_count, whole_count;
        for (const auto& [psf, count] : {std::pair{&a, &fine_count}, std::pair{&b, &whole_count}})
            for (const Tile& t : psf->tiles)
                for (const Fragment& f : t.fragments)
                    t.edge_table(f).for_each_ray([&, count = count](int u, int v, int) {
                        ++(*count)[long(t.t * 8 + v) * N + (t.s * 8 + u)];
                    });
        ASSERT_EQ(fine_count.size(), whole_count.size()) << "direction " << d;
        for (const auto& [ray, c] : fine_count) {
            ASSERT_EQ(c, 1) << "ray " << ray << " direction " << d;
            ASSERT_EQ(whole_count.count(ray), 1u) << "ray " << ray << " direction " << d;
        }
        rays += int64_t(fine_count.size());
    }
    EXPECT_GT(rays, 5000);  // (10,930 rays in all)
}

// count_covered (the coverage count of the transport's set-up) is rasterise_face's count:
// random triangles and quads, small and large, at the edge of the grid and beyond it, and
// faces seen edge-on, in every direction of a set.
TEST(PsfCoverage, CountMatchesTheRaster) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.2, 1.2), size(0.001, 0.6);
    std::vector<std::vector<Vec3>> polys;
    for (int k = 0; k < 60; ++k) {
        const Vec3 c(u(rng), u(rng), u(rng));
        const double r = size(rng);
        const int n = 3 + k % 2;
        std::vector<Vec3> p;
        for (int i = 0; i < n; ++i) {
            const double a = 2 * kPi * i / n + 0.3 * k;
            p.push_back(c + r * Vec3(std::cos(a), std::sin(a), 0.2 * std::sin(2 * a + k)));
        }
        polys.push_back(p);
    }
    polys.push_back({{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0.5, 0, 0.5}, {-0.5, 0, 0.5}});  // y = 0
    const Scene scene = test::make_scene(polys);
    const DirectionSet dirs(129);
    FaceRaster fr;
    int64_t total = 0;
    for (int d = 0; d < dirs.size(); ++d) {
        const Mat3 rot = rotation_to_z(dirs.direction(d));
        for (const Face& f : scene.faces)
            for (const auto& [N, m] : {std::pair{64, 8}, std::pair{60, 20}}) {
                rasterise_face(f, rot, N, m, fr);
                ASSERT_EQ(count_covered(f, rot, N), fr.covered)
                    << "face " << f.id << " direction " << d << " N " << N;
                total += fr.covered;
            }
    }
    EXPECT_GT(total, 100000);
}

TEST(PsfTiles, FragmentsLieInsideTheirTiles) {
    const Scene scene = load_scene(test::source_path("scenes/cornell.json"));
    const DirectionSet dirs(33);
    for (int d = 0; d < dirs.size(); ++d) {
        const Psf psf = rasterise_psf(scene, dirs.direction(d), d, 48, 16);
        const int n = psf.tiles_per_side();
        ASSERT_EQ(static_cast<int>(psf.tile_of.size()), n * n);
        for (size_t ti = 0; ti < psf.tiles.size(); ++ti) {
            const Tile& t = psf.tiles[ti];
            EXPECT_EQ(psf.tile_of[t.t * n + t.s], static_cast<int>(ti));
            uint32_t offset = 0;
            for (const Fragment& f : t.fragments) {
                EXPECT_EQ(f.ray_offset, offset);
                const EdgeTable et = t.edge_table(f);
                EXPECT_EQ(et.covered(), static_cast<int>(f.covered));
                EXPECT_GT(f.covered, 0u);
                EXPECT_LE(et.row_begin + et.rows, 16);
                for (int r = 0; r < et.rows; ++r) EXPECT_LE(et.spans[r].end, 16);
                offset += f.covered;
            }
            EXPECT_EQ(offset, t.covered);
        }
    }
}

TEST(PsfParameters, BadResolutionAndTileFailBeforeWork) {
    EXPECT_THROW(validate_raster(64, 7), ParameterError);
    EXPECT_THROW(validate_raster(0, 1), ParameterError);
    EXPECT_THROW(validate_raster(8192, 8), ParameterError);
    EXPECT_THROW(validate_raster(64, 0), ParameterError);
    EXPECT_THROW(validate_raster(64, 128), ParameterError);
    EXPECT_NO_THROW(validate_raster(64, 8));
    try {
        validate_raster(100, 16);
        FAIL();
    } catch (const ParameterError& e) {
        EXPECT_NE(std::string(e.what()).find("not a multiple"), std::string::npos);
    }
    const Scene scene = test::make_scene({{{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}}});
    EXPECT_THROW(rasterise_psf(scene, Vec3(0, 0, 1), 0, 64, 6), ParameterError);
    EXPECT_THROW(DirectionSet(100), ParameterError);
}

}  // namespace
}  // namespace vlf

namespace vlf {
namespace {

// tests/scenes/glass-room.json (a glass ball of 320 facets, most covering no ray centre in a
// given direction, a glass box, a mirror, the room) in 129 directions on a 32 x 32 grid of
// 8 x 8 tiles, with every face's coverage measured.
struct GlassRoomPsfs {
    const Scene s = load_scene(test::source_path("tests/scenes/glass-room.json"));
    const DirectionSet dirs{129};
    const std::vector<Mat3> rot = [&] {
        std::vector<Mat3> r(size_t(dirs.size()));
        for (int d = 0; d < dirs.size(); ++d) r[size_t(d)] = rotation_to_z(dirs.direction(d));
        return r;
    }();
    const int N = 32, m = 8;
    const Coverage cov = measure_coverage(s, rot, N, std::vector<uint8_t>(s.faces.size(), 1));
};

TEST(PsfCoverage, FacesTheCountFoundEmptyAreSkippedForTheSamePsf) {
    // The transport's true-direction PSFs skip a stored face whose measured coverage in the
    // direction is 0 (rasterise_psf's `coverage`): the tiles, fragments and spans must be
    // those of the full rasterisation.
    const GlassRoomPsfs g;
    uint64_t skipped = 0;
    for (int d = 0; d < g.dirs.size(); ++d) {
        for (const Face& f : g.s.faces) skipped += g.cov(d, f.id) == 0;
        const Psf a = rasterise_psf(g.s, g.rot[size_t(d)], d, g.N, g.m);
        const Psf b = rasterise_psf(g.s, g.rot[size_t(d)], d, g.N, g.m, &g.cov);
        ASSERT_EQ(a.tile_of, b.tile_of) << d;
        ASSERT_EQ(a.tiles.size(), b.tiles.size()) << d;
        for (size_t t = 0; t < a.tiles.size(); ++t) {
            const Tile &x = a.tiles[t], &y = b.tiles[t];
            ASSERT_EQ(x.covered, y.covered);
            ASSERT_EQ(x.fragments.size(), y.fragments.size()) << d << " tile " << t;
            for (size_t k = 0; k < x.fragments.size(); ++k) {
                const Fragment &p = x.fragments[k], &q = y.fragments[k];
                EXPECT_TRUE(p.face == q.face && p.row_begin == q.row_begin && p.rows == q.rows &&
                            p.span_offset == q.span_offset && p.ray_offset == q.ray_offset &&
                            p.covered == q.covered && p.facing == q.facing);
            }
            ASSERT_EQ(x.spans.size(), y.spans.size());
            for (size_t k = 0; k < x.spans.size(); ++k)
                EXPECT_TRUE(x.spans[k].begin == y.spans[k].begin &&
                            x.spans[k].end == y.spans[k].end);
        }
    }
    EXPECT_GT(skipped, uint64_t(g.dirs.size()) * 200);  // the case is exercised
}

TEST(PsfTwins, ATwinHasItsFacesRasterFacingTheOtherWay) {
    // TwinRasters hands a glass face's raster to its inner twin, and measure_coverage copies
    // its count: both must equal rasterising the twin itself (rasterise_face, count_covered)
    // in every direction, with the twin's own facing. Every third outer face is left out of
    // the pass (a face whose coverage is 0 is not rasterised), so its twin rasterises alone.
    const GlassRoomPsfs g;
    TwinRasters twins;
    FaceRaster got, want;
    uint64_t shared = 0, twin_faces = 0;
    for (int d = 0; d < g.dirs.size(); ++d) {
        twins.clear();
        for (const Face& f : g.s.faces) {
            if (f.twin > f.id && f.id % 3 == 0) continue;  // left out: its twin goes alone
            twins.rasterise(f, g.rot[size_t(d)], g.N, g.m, got);
            rasterise_face(f, g.rot[size_t(d)], g.N, g.m, want);
            ASSERT_EQ(got.facing, want.facing) << d << " face " << f.id;
            ASSERT_EQ(got.covered, want.covered) << d << " face " << f.id;
            ASSERT_EQ(g.cov(d, f.id), want.covered) << d << " face " << f.id;
            ASSERT_EQ(got.fragments.size(), want.fragments.size());
            for (size_t k = 0; k < got.fragments.size(); ++k) {
                const FaceFragment &p = got.fragments[k], &q = want.fragments[k];
                EXPECT_TRUE(p.s == q.s && p.t == q.t && p.row_begin == q.row_begin &&
                            p.rows == q.rows && p.span_offset == q.span_offset &&
                            p.covered == q.covered);
            }
            ASSERT_EQ(got.spans.size(), want.spans.size());
            for (size_t k = 0; k < got.spans.size(); ++k)
                EXPECT_TRUE(got.spans[k].begin == want.spans[k].begin &&
                            got.spans[k].end == want.spans[k].end);
            if (f.twin >= 0 && f.twin < f.id) {
                ++twin_faces;
                shared += want.covered > 0 && f.twin % 3 != 0;
            }
        }
    }
    EXPECT_GT(twin_faces, 0u);
    EXPECT_GT(shared, uint64_t(g.dirs.size()) * 20);  // rasters handed over: the case is run
}

}  // namespace
}  // namespace vlf
