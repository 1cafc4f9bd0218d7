// Direction set: counts, lattice geometry, solid angles and their spread bounds, the two maps,
// and the constant-time lookups against brute force (DESIGN §4, docs/directions.md).
#include "vlf/field/direction_set.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "vlf/core/error.hpp"

namespace vlf {

// Declared a friend in DirectionSet: the two lattice maps, for the map tests.
struct DirectionSetTestAccess {
    static Vec3 to_sphere(DirectionScheme s, const Vec2& uv) {
        return DirectionSet::map_to_sphere(s, uv);
    }
    static Vec2 to_diamond(DirectionScheme s, const Vec3& t) {
        return DirectionSet::map_to_diamond(s, t);
    }
};

namespace {

constexpr std::array<int, 6> kCounts = {9, 33, 129, 513, 2049, 8193};
constexpr std::array<DirectionScheme, 2> kSchemes = {DirectionScheme::Octahedral,
                                                     DirectionScheme::EqualArea};

// Sets are built once per (l, scheme) for the whole test binary.
const DirectionSet& cached(int l, DirectionScheme s) {
    static std::map<std::pair<int, int>, std::unique_ptr<DirectionSet>> sets;
    auto& p = sets[{l, static_cast<int>(s)}];
    if (!p) p = std::make_unique<DirectionSet>(l, s);
    return *p;
}

Vec3 travel(const DirectionSet& ds, int index, int sense) {
    return double(sense) * ds.direction(index);
}

double vos_area(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double det = glm::dot(a, glm::cross(b, c));
    return 2.0 * std::atan2(det, 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a));
}

Vec3 from_angles(double z, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

// Uniform directions on the whole sphere, plus a batch hugging the equator (including exact
// zeros and tiny negatives) and one near both poles; and the lattice directions themselves,
// the midpoints of lattice edges and the octahedron vertices, where ties and edges live.
std::vector<Vec3> test_directions(const DirectionSet& ds, int uniform, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<Vec3> out;
    for (int q = 0; q < uniform; ++q)
        out.push_back(from_angles(2.0 * u01(rng) - 1.0, 2.0 * kPi * u01(rng)));
    const std::array<double, 7> tiny = {0.0, 1e-17, -1e-17, 1e-13, -1e-13, 1e-9, -1e-9};
    for (int q = 0; q < uniform / 5; ++q) {
        const double z = q % 2 ? (2.0 * u01(rng) - 1.0) * 1e-3 : tiny[(q / 2) % tiny.size()];
        out.push_back(glm::normalize(from_angles(z, 2.0 * kPi * u01(rng))));
    }
    for (int q = 0; q < uniform / 5; ++q) {
        const double theta = 0.05 * u01(rng);
        const Vec3 d = from_angles(std::cos(theta), 2.0 * kPi * u01(rng));
        out.push_back(q % 2 ? d : -d);
    }
    for (int i = 0; i < ds.size(); ++i) {
        out.push_back(ds.direction(i));
        out.push_back(-ds.direction(i));
    }
    for (const auto& t : ds.triangles())
        for (int q = 0; q < 3; ++q) {
            const Vec3 m = glm::normalize(travel(ds, t.index[q], t.sense[q]) +
                                          travel(ds, t.index[(q + 1) % 3], t.sense[(q + 1) % 3]));
            out.push_back(m);
            out.push_back(-m);
        }
    for (const Vec3& axis : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}) {
        out.push_back(axis);
        out.push_back(-axis);
    }
    return out;
}

int brute_nearest(const DirectionSet& ds, const Vec3& d) {
    int best = -1;
    double best_dot = -1.0;
    for (int i = 0; i < ds.size(); ++i) {
        const double c = std::abs(glm::dot(d, ds.direction(i)));
        if (c > best_dot) {
            best_dot = c;
            best = i;
        }
    }
    return best;
}

// ---------------------------------------------------------------------------------------------

TEST(DirectionSetCount, ValidCountsForBothSchemes) {
    EXPECT_EQ(DirectionSet::valid_counts_text(), "9, 33, 129, 513, 2049, 8193");
    for (DirectionScheme s : kSchemes)
        for (int k = 1; k <= 6; ++k) {
            const int l = kCounts[k - 1];
            EXPECT_TRUE(DirectionSet::is_valid_count(l));
            const DirectionSet& ds = cached(l, s);
            EXPECT_EQ(ds.size(), l);
            EXPECT_EQ(ds.subdivisions(), 1 << k);
            EXPECT_EQ(ds.scheme(), s);
            EXPECT_EQ(ds.triangles().size(), size_t(4) << (2 * k));  // 4 faces x 4^k
            EXPECT_DOUBLE_EQ(ds.mean_solid_angle(), 2.0 * kPi / l);
        }
}

TEST(DirectionSetCount, InvalidCountsThrowWithTheValidList) {
    for (int l : {0, 1, 3, 8, 10, 17, 32, 34, 128, 512, 514, 8192, 32768, 32769, -9}) {
        EXPECT_FALSE(DirectionSet::is_valid_count(l)) << l;
        for (DirectionScheme s : kSchemes) {
            try {
                DirectionSet ds(l, s);
                ADD_FAILURE() << "no exception for l = " << l;
            } catch (const ParameterError& e) {
                EXPECT_NE(std::string(e.what()).find("9, 33, 129, 513, 2049, 8193"),
                          std::string::npos)
                    << e.what();
            }
        }
    }
}

TEST(DirectionSetCount, SchemeNamesRoundTrip) {
    for (DirectionScheme s : kSchemes) EXPECT_EQ(direction_scheme_from_string(to_string(s)), s);
    EXPECT_EQ(to_string(DirectionScheme::EqualArea), "equal-area");
    EXPECT_THROW(direction_scheme_from_string("equal_area"), ParameterError);
    EXPECT_THROW(direction_scheme_from_string(""), ParameterError);
}

TEST(DirectionSetGeometry, UnitUpperAndDistinctLines) {
    for (DirectionScheme s : kSchemes)
        for (int l : kCounts) {
            const DirectionSet& ds = cached(l, s);
            double max_dot = -1.0;  // over distinct lines, either sense
            for (int i = 0; i < l; ++i) {
                EXPECT_NEAR(glm::length(ds.direction(i)), 1.0, 1e-14);
                EXPECT_GE(ds.direction(i).z, 0.0);
                for (int j = i + 1; j < l; ++j)
                    max_dot =
                        std::max(max_dot, std::abs(glm::dot(ds.direction(i), ds.direction(j))));
            }
            EXPECT_LT(max_dot, 1.0 - 1e-6) << to_string(s) << " l=" << l;
            // Equator lines are stored once, with the canonical representative.
            for (int i = 0; i < l; ++i)
                if (ds.direction(i).z == 0.0) {
                    const Vec3& d = ds.direction(i);
                    EXPECT_TRUE(d.x > 0.0 || (d.x == 0.0 && d.y > 0.0)) << i;
                }
        }
}

// The lattice in row-major order (j, then i) through the scheme's map.
TEST(DirectionSetGeometry, DirectionsAreTheMappedLatticeInRowMajorOrder) {
    for (DirectionScheme s : kSchemes)
        for (int l : {33, 513}) {
            const DirectionSet& ds = cached(l, s);
            const int n = ds.subdivisions();
            int idx = 0;
            for (int j = -n; j <= n; ++j)
                for (int i = -n; i <= n; ++i) {
                    const int r = std::abs(i) + std::abs(j);
                    if (r > n || (r == n && !(i > 0 || (i == 0 && j > 0)))) continue;
                    const Vec3 p = DirectionSetTestAccess::to_sphere(s, Vec2(i, j) / double(n));
                    EXPECT_LT(glm::length(p - ds.direction(idx)), 1e-15) << i << "," << j;
                    ++idx;
                }
            EXPECT_EQ(idx, l);
        }
}

// Together with the antipodal copies, the triangles close the sphere: every edge (as pairs of
// travel vertices) is shared by exactly two triangles, and all are counter-clockwise.
TEST(DirectionSetGeometry, TrianglesTileTheSphere) {
    for (DirectionScheme s : kSchemes)
        for (int l : kCounts) {
            const DirectionSet& ds = cached(l, s);
            std::map<std::pair<int, int>, int> edges;  // key: signed vertex ids
            auto vid = [&](int index, int sense) { return sense > 0 ? index : index + l; };
            for (const auto& t : ds.triangles()) {
                EXPECT_GT(glm::dot(travel(ds, t.index[0], t.sense[0]),
                                   glm::cross(travel(ds, t.index[1], t.sense[1]),
                                              travel(ds, t.index[2], t.sense[2]))),
                          0.0);
                for (int flip : {1, -1})
                    for (int q = 0; q < 3; ++q) {
                        int a = vid(t.index[q], flip * t.sense[q]);
                        int b = vid(t.index[(q + 1) % 3], flip * t.sense[(q + 1) % 3]);
                        ++edges[{std::min(a, b), std::max(a, b)}];
                    }
            }
            for (const auto& [e, count] : edges) EXPECT_EQ(count, 2);
            // Euler: V - E + F = 2 with V = 2l travel vertices, F = 2 * 4n^2.
            EXPECT_EQ(2 * l - int(edges.size()) + 2 * int(ds.triangles().size()), 2);
        }
}

TEST(DirectionSetSolidAngle, SumsToTwoPiAndPositive) {
    for (DirectionScheme s : kSchemes)
        for (int l : kCounts) {
            const DirectionSet& ds = cached(l, s);
            double sum = 0.0;
            for (int i = 0; i < l; ++i) {
                EXPECT_GT(ds.solid_angle(i), 0.0);
                sum += ds.solid_angle(i);
            }
            EXPECT_NEAR(sum, 2.0 * kPi, 1e-9) << to_string(s) << " l=" << l;
        }
}

int index_of(const DirectionSet& ds, const Vec3& d) {
    for (int i = 0; i < ds.size(); ++i)
        if (glm::length(ds.direction(i) - d) < 1e-12) return i;
    return -1;
}

// docs/directions.md, "Spread bounds". Octahedral: every lattice triangle covers the same face
// area A_T = sqrt(3)/(2n^2), and dOmega = dA/(sqrt(3)|p|^3) lies in [1/sqrt(3), 3] per unit
// area, so every vertex gets at most 6 A_T; the minimum is the pole (and the equator corners),
// 4/3 of the closed-form pole triangle; the vertex nearest to a face centre gets at least
// 6 A_T / (1 + 3 R^2)^(3/2), R = s (1 + 1/sqrt 3), s = sqrt(2)/n.
TEST(DirectionSetSolidAngle, OctahedralSpreadWithinDerivedBounds) {
    for (int l : kCounts) {
        const DirectionSet& ds = cached(l, DirectionScheme::Octahedral);
        const double n = ds.subdivisions();
        const double a = 1.0 / n, b = 1.0 - 1.0 / n, q = std::hypot(a, b);
        const double pole_tri = 2.0 * std::atan(a * a / ((q + b) * (q + b)));
        const double pole = 4.0 / 3.0 * pole_tri;
        double mn = 1e300, mx = 0.0;
        for (int i = 0; i < l; ++i) {
            mn = std::min(mn, ds.solid_angle(i));
            mx = std::max(mx, ds.solid_angle(i));
        }
        EXPECT_NEAR(mn / pole, 1.0, 1e-12);
        for (const Vec3& v : {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0)}) {
            const int i = index_of(ds, v);
            ASSERT_GE(i, 0);
            EXPECT_NEAR(ds.solid_angle(i) / pole, 1.0, 1e-12);
        }
        const double area_t = std::sqrt(3.0) / (2.0 * n * n);
        const double s = std::sqrt(2.0) / n, r = s * (1.0 + 1.0 / std::sqrt(3.0));
        const double upper = 6.0 * area_t / pole;
        // n >= 4: the vertex nearest to the face centre is inside the face (in-plane bound);
        // n = 2: only the bound through |p| <= 1/sqrt(3) + R holds. Either way max >= mean.
        const double density = ds.subdivisions() >= 4
                                   ? 3.0 / std::pow(1.0 + 3.0 * r * r, 1.5)
                                   : 3.0 / std::pow(1.0 + std::sqrt(3.0) * r, 3.0);
        const double lower = std::max(2.0 * area_t * density, ds.mean_solid_angle()) / pole;
        const double spread = ds.solid_angle_spread();
        EXPECT_DOUBLE_EQ(spread, mx / mn);
        EXPECT_LE(spread, upper) << "l=" << l;
        EXPECT_GE(spread, lower) << "l=" << l;
        std::printf("[ spread   ] octahedral l=%4d: %.4f in [%.4f, %.4f]\n", l, spread, lower,
                    upper);
    }
}

// Equal-area: every map triangle has solid angle pi/(2n^2); the pole triangles lose the
// segment between their curved edge (a quarter of the latitude circle z = 1 - 1/n^2) and the
// great arc: closed form 2 atan(1/(2n^2 - 1)). The largest great-arc triangle is the
// pole cell's outer triangle (1,1),(0,1),(1,0), which gains that segment. So
// mean <= max <= 2 * largest triangle, min = 4/3 pole triangle.
TEST(DirectionSetSolidAngle, EqualAreaSpreadWithinDerivedBounds) {
    for (int l : kCounts) {
        const DirectionSet& ds = cached(l, DirectionScheme::EqualArea);
        const double n = ds.subdivisions();
        const double pole = 4.0 / 3.0 * 2.0 * std::atan(1.0 / (2.0 * n * n - 1.0));
        auto ring = [n](double k, double phi) {  // EA lattice point on ring k at azimuth phi
            const double r = k / n;
            return from_angles(1.0 - r * r, phi);
        };
        const double outer = vos_area(ring(2, kPi / 4), ring(1, kPi / 2), ring(1, 0));
        double mn = 1e300, max_tri = 0.0;
        for (int i = 0; i < l; ++i) mn = std::min(mn, ds.solid_angle(i));
        for (const auto& t : ds.triangles())
            max_tri = std::max(max_tri, vos_area(travel(ds, t.index[0], t.sense[0]),
                                                 travel(ds, t.index[1], t.sense[1]),
                                                 travel(ds, t.index[2], t.sense[2])));
        EXPECT_NEAR(mn / pole, 1.0, 1e-12);
        EXPECT_NEAR(ds.solid_angle(index_of(ds, Vec3(0, 0, 1))) / pole, 1.0, 1e-12);
        EXPECT_NEAR(max_tri / outer, 1.0, 1e-12);
        const double upper = 2.0 * outer / pole;
        const double lower = ds.mean_solid_angle() / pole;
        const double spread = ds.solid_angle_spread();
        EXPECT_LE(spread, upper) << "l=" << l;
        EXPECT_GE(spread, lower) << "l=" << l;
        std::printf("[ spread   ] equal-area l=%4d: %.4f in [%.4f, %.4f]\n", l, spread, lower,
                    upper);
    }
}

TEST(DirectionSetMaps, EqualAreaMapPreservesArea) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double h = 1e-6;
    int tested = 0;
    double max_oct = 0.0, min_oct = 1e300;
    while (tested < 20000) {
        const Vec2 p(u(rng), u(rng));
        // Stay off the quadrant axes and the diamond edge, where the map has kinks.
        if (std::abs(p.x) + std::abs(p.y) > 1.0 - 2 * h || std::abs(p.x) < 2 * h ||
            std::abs(p.y) < 2 * h)
            continue;
        ++tested;
        for (DirectionScheme s : kSchemes) {
            auto f = [s](Vec2 q) { return DirectionSetTestAccess::to_sphere(s, q); };
            const Vec3 du = (f(p + Vec2(h, 0)) - f(p - Vec2(h, 0))) / (2 * h);
            const Vec3 dv = (f(p + Vec2(0, h)) - f(p - Vec2(0, h))) / (2 * h);
            const double jac = glm::length(glm::cross(du, dv));
            if (s == DirectionScheme::EqualArea) {
                ASSERT_NEAR(jac, kPi, 1e-6 * kPi) << p.x << "," << p.y;
            } else {
                max_oct = std::max(max_oct, jac);
                min_oct = std::min(min_oct, jac);
            }
            // Both maps invert.
            const Vec2 back = DirectionSetTestAccess::to_diamond(s, f(p));
            ASSERT_LT(glm::length(back - p), 1e-12);
        }
    }
    // The octahedral map is not area preserving: dOmega/(du dv) = 1/|p|^3 goes from 1 at the
    // octahedron vertices to 3 sqrt(3) at the face centres.
    EXPECT_LT(min_oct, 1.05);
    EXPECT_GT(max_oct, 3.0 * std::sqrt(3.0) * 0.99);
    EXPECT_LE(max_oct, 3.0 * std::sqrt(3.0) * (1.0 + 1e-6));
}

TEST(DirectionSetNearest, MatchesBruteForce) {
    for (DirectionScheme s : kSchemes)
        for (int l : {9, 33, 513, 2049}) {
            const DirectionSet& ds = cached(l, s);
            const int uniform = l >= 513 ? 100000 : 20000;
            int checked = 0;
            for (const Vec3& d : test_directions(ds, uniform, 1234 + l)) {
                const int fast = ds.nearest(d), slow = brute_nearest(ds, d);
                if (fast != slow) {  // a tie is the only excuse
                    ASSERT_GE(fast, 0);
                    ASSERT_EQ(std::abs(glm::dot(d, ds.direction(fast))),
                              std::abs(glm::dot(d, ds.direction(slow))))
                        << to_string(s) << " l=" << l << " d=" << d.x << "," << d.y << "," << d.z;
                }
                ++checked;
            }
            EXPECT_GE(checked, uniform * 7 / 5);
        }
}

// Brute force: the containment score of every triangle of the sphere (the hemisphere's and their
// antipodal copies) = min over edges of the signed sine distance of t to the edge's great circle.
struct BruteTriangle {
    std::array<int, 3> index, sense;
    std::array<Vec3, 3> v, normal;  // travel vertices; inward unit edge normals
    Vec3 centre;
    double cos_radius;
};

std::vector<BruteTriangle> all_triangles(const DirectionSet& ds) {
    std::vector<BruteTriangle> out;
    for (const auto& t : ds.triangles())
        for (int flip : {1, -1}) {
            BruteTriangle b;
            b.index = t.index;
            for (int q = 0; q < 3; ++q) {
                b.sense[q] = flip * t.sense[q];
                b.v[q] = travel(ds, b.index[q], b.sense[q]);
            }
            const double orient = glm::dot(b.v[0], glm::cross(b.v[1], b.v[2])) > 0 ? 1.0 : -1.0;
            for (int q = 0; q < 3; ++q)
                b.normal[q] =
                    orient * glm::normalize(glm::cross(b.v[(q + 1) % 3], b.v[(q + 2) % 3]));
            b.centre = glm::normalize(b.v[0] + b.v[1] + b.v[2]);
            double c = 1.0;
            for (const Vec3& v : b.v) c = std::min(c, glm::dot(v, b.centre));
            b.cos_radius = c - 1e-9;
            out.push_back(b);
        }
    return out;
}

double containment(const BruteTriangle& b, const Vec3& t) {
    return std::min({glm::dot(t, b.normal[0]), glm::dot(t, b.normal[1]), glm::dot(t, b.normal[2])});
}

// A fixed pseudo-random value per travel vertex, so that "equal interpolated result" means
// the same vertices carry the weight.
double vertex_value(int index, int sense) {
    return std::sin(12.9898 * index + 78.233 * sense + 0.5) * 43758.5453 -
           std::floor(std::sin(12.9898 * index + 78.233 * sense + 0.5) * 43758.5453);
}

TEST(DirectionSetEnclosing, MatchesBruteForce) {
    for (DirectionScheme s : kSchemes)
        for (int l : {9, 33, 513, 2049}) {
            const DirectionSet& ds = cached(l, s);
            auto tris = all_triangles(ds);
            // Exact pruning of the scan: a triangle whose cap (centre, radius) holds t has
            // |theta_t - theta_centre| <= radius, so only a band of centre heights qualifies.
            std::sort(tris.begin(), tris.end(), [](const BruteTriangle& a, const BruteTriangle& b) {
                return a.centre.z < b.centre.z;
            });
            std::vector<double> centre_z;
            double max_radius = 0.0;
            for (const auto& b : tris) {
                centre_z.push_back(b.centre.z);
                max_radius = std::max(max_radius, std::acos(std::min(1.0, b.cos_radius)));
            }
            const int uniform = l >= 513 ? 100000 : 20000;
            int on_edge = 0, checked = 0;
            for (const Vec3& t : test_directions(ds, uniform, 99 + l)) {
                const EnclosingTriangle e = ds.enclosing(t);
                // Weights: >= 0, sum 1, and sum w v reproduces t.
                double wsum = 0.0, fast_value = 0.0;
                Vec3 mix(0.0);
                for (int q = 0; q < 3; ++q) {
                    ASSERT_GE(e.weight[q], 0.0);
                    ASSERT_TRUE(e.sense[q] == 1 || e.sense[q] == -1);
                    wsum += e.weight[q];
                    mix += e.weight[q] * travel(ds, e.index[q], e.sense[q]);
                    fast_value += e.weight[q] * vertex_value(e.index[q], e.sense[q]);
                }
                ASSERT_NEAR(wsum, 1.0, 1e-14);
                ASSERT_LT(glm::length(glm::normalize(mix) - t), 1e-9) << to_string(s) << " l=" << l;

                int best = -1;
                double best_score = -1.0;
                const double theta = std::acos(std::clamp(t.z, -1.0, 1.0));
                const double zlo = std::cos(std::min(kPi, theta + max_radius)) - 1e-9;
                const double zhi = std::cos(std::max(0.0, theta - max_radius)) + 1e-9;
                const int first =
                    int(std::lower_bound(centre_z.begin(), centre_z.end(), zlo) - centre_z.begin());
                const int last =
                    int(std::upper_bound(centre_z.begin(), centre_z.end(), zhi) - centre_z.begin());
                for (int b = first; b < last; ++b) {
                    if (glm::dot(t, tris[b].centre) < tris[b].cos_radius) continue;
                    const double sc = containment(tris[b], t);
                    if (sc > best_score) {
                        best_score = sc;
                        best = b;
                    }
                }
                ASSERT_GE(best, 0);
                ASSERT_GE(best_score, -1e-15);
                std::set<std::pair<int, int>> got, want;
                for (int q = 0; q < 3; ++q) {
                    got.insert({e.index[q], e.sense[q]});
                    want.insert({tris[best].index[q], tris[best].sense[q]});
                }
                if (best_score > 1e-12) {
                    ASSERT_EQ(got, want)
                        << to_string(s) << " l=" << l << " t=" << t.x << "," << t.y << "," << t.z;
                } else {
                    // t on a shared edge (or vertex): an adjacent triangle that contains t
                    // and interpolates the same.
                    ++on_edge;
                    BruteTriangle mine;
                    for (int q = 0; q < 3; ++q) mine.v[q] = travel(ds, e.index[q], e.sense[q]);
                    const double orient =
                        glm::dot(mine.v[0], glm::cross(mine.v[1], mine.v[2])) > 0 ? 1.0 : -1.0;
                    for (int q = 0; q < 3; ++q)
                        mine.normal[q] = orient * glm::normalize(glm::cross(mine.v[(q + 1) % 3],
                                                                            mine.v[(q + 2) % 3]));
                    ASSERT_GE(containment(mine, t), -1e-12);
                    double brute_value = 0.0, bsum = 0.0;
                    std::array<double, 3> w{};
                    for (int q = 0; q < 3; ++q) {
                        w[q] =
                            std::max(0.0, glm::dot(t, tris[best].normal[q]) *
                                              glm::length(glm::cross(tris[best].v[(q + 1) % 3],
                                                                     tris[best].v[(q + 2) % 3])));
                        bsum += w[q];
                    }
                    for (int q = 0; q < 3; ++q)
                        brute_value +=
                            w[q] / bsum * vertex_value(tris[best].index[q], tris[best].sense[q]);
                    ASSERT_NEAR(fast_value, brute_value, 1e-9);
                }
                ++checked;
            }
            EXPECT_GE(checked, uniform * 7 / 5);
            EXPECT_GT(on_edge, 0);  // the lattice points and edge midpoints are exercised
        }
}

// A hint (the triangle a neighbouring direction fell in) changes nothing: each direction of
// a path that wanders in small steps (as a curved mirror's reflections of neighbouring rays
// do), and of one that jumps, finds the triangle and weights it finds without a hint, and the
// hint it leaves is that triangle. The jumps include the lattice points and the edges'
// midpoints, where the triangles around score alike up to rounding and the map decides.
TEST(DirectionSetEnclosing, AHintFindsTheSameTriangle) {
    for (DirectionScheme s : kSchemes)
        for (int l : {33, 2049}) {
            const DirectionSet& ds = cached(l, s);
            const std::vector<Vec3> jumps = test_directions(ds, 20000, 7 + l);
            int hint = -1, kept = 0;
            Vec3 t = jumps[0];
            for (size_t k = 0; k < 2 * jumps.size(); ++k) {
                // Even steps: a small turn towards the next test direction; odd: a jump.
                const Vec3& to = jumps[(k / 2 + 1) % jumps.size()];
                t = k % 2 == 0 ? glm::normalize(t + 0.02 * (to - t)) : to;
                const int before = hint;
                const EnclosingTriangle a = ds.enclosing(t, hint);
                const EnclosingTriangle b = ds.enclosing(t);
                ASSERT_EQ(a.index, b.index) << to_string(s) << " l=" << l << " k=" << k;
                ASSERT_EQ(a.sense, b.sense);
                ASSERT_EQ(a.weight, b.weight);
                int again = -1;
                ds.enclosing(t, again);
                EXPECT_EQ(hint, again);
                kept += before == hint;
            }
            EXPECT_GT(kept, int(jumps.size()) / 4);  // the small steps mostly keep the hint
        }
}

// A smooth function of the travel direction, interpolated from its values at the 2l travel
// vertices with enclosing(); RMS error over uniform directions (docs/directions.md).
double smooth_f(const Vec3& t) {
    const Vec3 a = glm::normalize(Vec3(0.3, -0.5, 0.8));
    return std::exp(2.0 * glm::dot(t, a)) + 0.5 * t.x * t.y + 0.25 * t.z * t.z * t.z;
}

double interpolation_rms(const DirectionSet& ds, int samples) {
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    double se = 0.0, sf = 0.0;
    for (int q = 0; q < samples; ++q) {
        const Vec3 t = from_angles(2.0 * u01(rng) - 1.0, 2.0 * kPi * u01(rng));
        const EnclosingTriangle e = ds.enclosing(t);
        double v = 0.0;
        for (int k = 0; k < 3; ++k) v += e.weight[k] * smooth_f(travel(ds, e.index[k], e.sense[k]));
        se += (v - smooth_f(t)) * (v - smooth_f(t));
        sf += smooth_f(t) * smooth_f(t);
    }
    return std::sqrt(se / sf);
}

TEST(DirectionSetInterpolation, ErrorDecreasesWithCount) {
    for (DirectionScheme s : kSchemes) {
        double previous = 1e300;
        for (int l : kCounts) {
            const double rms = interpolation_rms(cached(l, s), 200000);
            std::printf("[ interp   ] %-10s l=%4d relative RMS error %.4e\n", to_string(s).c_str(),
                        l, rms);
            EXPECT_LT(rms, previous) << to_string(s) << " l=" << l;
            previous = rms;
        }
    }
}

}  // namespace
}  // namespace vlf
