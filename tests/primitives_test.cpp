// primitives_test.cpp — shape generators and polygon checks (vlf/scene/primitives.hpp,
// vlf/scene/texel_frame.hpp clipping).
#include "vlf/scene/primitives.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "test_util.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/scene/texel_frame.hpp"

namespace vlf {
namespace {

using test::vertex_key;

// Every directed edge a->b has exactly one partner b->a: the faces form closed,
// consistently oriented surfaces (and shared vertices are bit-identical).
bool closed_and_consistent(const std::vector<Polygon>& faces) {
    std::map<std::pair<test::VertexKey, test::VertexKey>, int> edges;
    for (const Polygon& p : faces)
        for (size_t i = 0; i < p.size(); ++i)
            ++edges[{vertex_key(p[i]), vertex_key(p[(i + 1) % p.size()])}];
    for (const auto& [e, n] : edges) {
        if (n != 1) return false;
        auto it = edges.find({e.second, e.first});
        if (it == edges.end() || it->second != 1) return false;
    }
    return true;
}

double total_area(const std::vector<Polygon>& faces) {
    double a = 0;
    for (const Polygon& p : faces) a += polygon_area(p);
    return a;
}

// Signed volume by the divergence theorem: positive when the normals point out.
double signed_volume(const std::vector<Polygon>& faces) {
    double v = 0;
    for (const Polygon& p : faces) v += glm::dot(newell_vector(p), polygon_centroid(p)) / 6.0;
    return v;
}

// Mean value coordinates (polygon_weights, the shading normals of smooth quads and polygons):
// they sum to 1 and reproduce the point (linear precision) inside a convex polygon, are 1/m
// at a regular polygon's centre, and take a vertex or an edge's endpoints exactly there;
// checked for a pentagon and for a 24-gon (more corners than its stack scratch holds).
TEST(PolygonWeights, PartitionOfUnityAndLinearPrecision) {
    for (const int m : {5, 24}) {
        std::vector<Vec3> v;
        for (int i = 0; i < m; ++i) {
            const double a = 2.0 * kPi * i / m;
            v.push_back(Vec3(std::cos(a), std::sin(a), 0.25));
        }
        const Vec3 n(0.0, 0.0, 1.0);
        std::vector<double> w;
        polygon_weights(v, n, Vec3(0.0, 0.0, 0.25), w);
        ASSERT_EQ(w.size(), size_t(m));
        for (double wi : w) EXPECT_NEAR(wi, 1.0 / m, 1e-12) << m << " corners";
        for (const Vec3 x :
             {Vec3(0.3, -0.2, 0.25), Vec3(-0.55, 0.41, 0.25), Vec3(0.8, 0.1, 0.25)}) {
            polygon_weights(v, n, x, w);
            double sum = 0.0;
            Vec3 at(0.0);
            for (int i = 0; i < m; ++i) {
                EXPECT_GT(w[size_t(i)], 0.0);
                sum += w[size_t(i)];
                at += w[size_t(i)] * v[size_t(i)];
            }
            EXPECT_NEAR(sum, 1.0, 1e-12);
            EXPECT_NEAR(glm::length(at - x), 0.0, 1e-12) << m << " corners";
        }
        polygon_weights(v, n, v[3], w);
        for (int i = 0; i < m; ++i) EXPECT_EQ(w[size_t(i)], i == 3 ? 1.0 : 0.0);
        polygon_weights(v, n, 0.25 * v[1] + 0.75 * v[2], w);
        EXPECT_NEAR(w[1], 0.25, 1e-12);
        EXPECT_NEAR(w[2], 0.75, 1e-12);
    }
}

TEST(PrimitiveBox, SixOutwardQuadsWithTheRightArea) {
    const Vec3 lo(-1, 2, 3), hi(2, 4, 7);
    const auto faces = make_box(lo, hi);
    ASSERT_EQ(faces.size(), 6u);
    const Vec3 c = 0.5 * (lo + hi);
    for (const Polygon& p : faces) {
        EXPECT_EQ(p.size(), 4u);
        EXPECT_FALSE(polygon_problem(p, 1e-12, 1e-12).has_value());
        EXPECT_GT(glm::dot(newell_vector(p), polygon_centroid(p) - c), 0) << "inward face";
    }
    const Vec3 d = hi - lo;
    EXPECT_NEAR(total_area(faces), 2 * (d.x * d.y + d.y * d.z + d.z * d.x), 1e-12);
    EXPECT_NEAR(signed_volume(faces), d.x * d.y * d.z, 1e-12);
    EXPECT_TRUE(closed_and_consistent(faces));
}

TEST(PrimitiveIcosphere, FaceCountAreaAndOrientation) {
    const Vec3 c(1, -2, 0.5);
    const double r = 2.5;
    double previous_error = 1.0;
    for (int k = 0; k <= 4; ++k) {
        const auto faces = make_icosphere(c, r, k);
        ASSERT_EQ(faces.size(), 20u * (1u << (2 * k))) << "k=" << k;
        for (const Polygon& p : faces) {
            ASSERT_EQ(p.size(), 3u);
            EXPECT_GT(glm::dot(newell_vector(p), polygon_centroid(p) - c), 0);
            for (const Vec3& v : p) EXPECT_NEAR(glm::length(v - c), r, 1e-12);
        }
        EXPECT_TRUE(closed_and_consistent(faces)) << "k=" << k;
        const double error = std::abs(total_area(faces) / (4 * kPi * r * r) - 1);
        EXPECT_LT(error, previous_error) << "area must converge, k=" << k;
        previous_error = error;
    }
    EXPECT_LT(previous_error, 0.01);  // k = 4: within 1% of 4 pi r^2
}

TEST(PrimitiveCylinder, SolidWithCaps) {
    CylinderShape s;
    s.base_center = Vec3(1, 2, 3);
    s.radius = 2;
    s.height = 5;
    s.segments = 48;
    const auto faces = make_cylinder(s);
    const int n = s.segments;
    ASSERT_EQ(faces.size(), 3u * n);
    const double side = 2 * n * s.radius * std::sin(kPi / n) * s.height;
    const double disc = 0.5 * n * s.radius * s.radius * std::sin(2 * kPi / n);
    EXPECT_NEAR(total_area(faces), side + 2 * disc, 1e-9);
    // Faceting error of the side against 2 pi r h: 1 - sin(x)/x with x = pi/n.
    EXPECT_NEAR(side / (2 * kPi * s.radius * s.height), 1.0, 1e-3);
    for (int k = 0; k < n; ++k) {  // outer wall faces away from the axis
        const Vec3 c = polygon_centroid(faces[k]);
        const Vec3 radial(c.x - s.base_center.x, 0, c.z - s.base_center.z);
        EXPECT_GT(glm::dot(glm::normalize(newell_vector(faces[k])), glm::normalize(radial)), 0.99);
    }
    for (int k = 0; k < n; ++k) {
        EXPECT_NEAR(glm::normalize(newell_vector(faces[n + k])).y, -1.0, 1e-12);     // bottom
        EXPECT_NEAR(glm::normalize(newell_vector(faces[2 * n + k])).y, 1.0, 1e-12);  // top
    }
    for (const Polygon& p : faces) EXPECT_FALSE(polygon_problem(p, 1e-9, 1e-9).has_value());
    EXPECT_TRUE(closed_and_consistent(faces));
    EXPECT_GT(signed_volume(faces), 0);
}

TEST(PrimitiveCylinder, OpenTube) {
    CylinderShape s;
    s.radius = 1;
    s.height = 2;
    s.segments = 16;
    s.caps = false;
    auto faces = make_cylinder(s);
    EXPECT_EQ(faces.size(), 16u);
    s.inner_radius = 0.5;
    faces = make_cylinder(s);
    EXPECT_EQ(faces.size(), 32u);
    EXPECT_NEAR(total_area(faces), 2 * 16 * (1.0 + 0.5) * std::sin(kPi / 16) * 2, 1e-12);
}

TEST(PrimitiveCylinder, RingWithAnnularCaps) {
    CylinderShape s;
    s.radius = 1.5;
    s.inner_radius = 1.0;
    s.height = 0.5;
    s.segments = 64;
    const auto faces = make_cylinder(s);
    const int n = s.segments;
    ASSERT_EQ(faces.size(), 4u * n);
    for (int k = 0; k < n; ++k) {
        const Vec3 co = polygon_centroid(faces[k]), ci = polygon_centroid(faces[n + k]);
        EXPECT_GT(glm::dot(newell_vector(faces[k]), Vec3(co.x, 0, co.z)), 0)
            << "outer wall faces out";
        EXPECT_LT(glm::dot(newell_vector(faces[n + k]), Vec3(ci.x, 0, ci.z)), 0)
            << "inner wall faces the axis";
        EXPECT_EQ(faces[2 * n + k].size(), 4u);
        EXPECT_NEAR(glm::normalize(newell_vector(faces[2 * n + k])).y, -1.0, 1e-12);
        EXPECT_NEAR(glm::normalize(newell_vector(faces[3 * n + k])).y, 1.0, 1e-12);
    }
    const double annulus = 0.5 * n * (1.5 * 1.5 - 1.0) * std::sin(2 * kPi / n);
    const double walls = 2 * n * (1.5 + 1.0) * std::sin(kPi / n) * 0.5;
    EXPECT_NEAR(total_area(faces), walls + 2 * annulus, 1e-12);
    EXPECT_NEAR(annulus / (kPi * (1.5 * 1.5 - 1.0)), 1.0, 2e-3);
    for (const Polygon& p : faces) EXPECT_FALSE(polygon_problem(p, 1e-9, 1e-9).has_value());
    EXPECT_TRUE(closed_and_consistent(faces));
    EXPECT_GT(signed_volume(faces), 0);
}

TEST(PrimitivePolygon, ProblemsAreRecognised) {
    const Polygon square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    EXPECT_FALSE(polygon_problem(square, 1e-9, 1e-9).has_value());
    const Polygon bent = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}};
    ASSERT_TRUE(polygon_problem(bent, 1e-6, 1e-9).has_value());
    EXPECT_NE(polygon_problem(bent, 1e-6, 1e-9)->find("not planar"), std::string::npos);
    const Polygon ell = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    ASSERT_TRUE(polygon_problem(ell, 1e-9, 1e-9).has_value());
    EXPECT_NE(polygon_problem(ell, 1e-9, 1e-9)->find("not convex"), std::string::npos);
    Polygon star;  // a pentagram turns left at every vertex but winds twice
    for (int k = 0; k < 5; ++k)
        star.push_back({std::cos(4 * kPi * k / 5), std::sin(4 * kPi * k / 5), 0});
    ASSERT_TRUE(polygon_problem(star, 1e-9, 1e-9).has_value());
    EXPECT_NE(polygon_problem(star, 1e-9, 1e-9)->find("not convex"), std::string::npos);
    const Polygon line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    ASSERT_TRUE(polygon_problem(line, 1e-9, 1e-9).has_value());
    EXPECT_NE(polygon_problem(line, 1e-9, 1e-9)->find("degenerate"), std::string::npos);
    const Polygon repeated = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    ASSERT_TRUE(polygon_problem(repeated, 1e-9, 1e-9).has_value());
    EXPECT_NE(polygon_problem(repeated, 1e-9, 1e-9)->find("degenerate"), std::string::npos);
}

TEST(PrimitivePolygon, TriangulationKeepsAreaAndOrientation) {
    const Polygon ell = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    const auto tris = triangulate_polygon(ell, 1e-9, 1e-9);
    ASSERT_TRUE(tris.has_value());
    EXPECT_EQ(tris->size(), 4u);
    EXPECT_NEAR(total_area(*tris), 3.0, 1e-12);
    for (const Polygon& t : *tris) {
        EXPECT_GT(newell_vector(t).z, 0);
        EXPECT_FALSE(polygon_problem(t, 1e-9, 1e-9).has_value());
    }
    const Polygon bent = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0}};
    const auto fan = triangulate_polygon(bent, 1e-6, 1e-9);
    ASSERT_TRUE(fan.has_value());
    ASSERT_EQ(fan->size(), 2u);
    EXPECT_EQ((*fan)[0][0], bent[0]);
    EXPECT_EQ((*fan)[1][0], bent[0]);
    // A straight vertex gives a zero-area ear that is dropped.
    const Polygon with_collinear = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
    const auto t2 = triangulate_polygon(with_collinear, 1e-9, 1e-9);
    ASSERT_TRUE(t2.has_value());
    EXPECT_NEAR(total_area(*t2), 4.0, 1e-12);
    for (const Polygon& t : *t2) EXPECT_GT(polygon_area(t), 1e-6);
}

TEST(PrimitiveClipping, ClippedAreaOfASquareAndATriangle) {
    const std::vector<Vec2> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
    EXPECT_NEAR(clipped_area(square, {1, 1}, {3, 3}), 1.0, 1e-15);
    EXPECT_NEAR(clipped_area(square, {-1, -1}, {3, 3}), 4.0, 1e-15);
    EXPECT_NEAR(clipped_area(square, {2.5, 0}, {3, 3}), 0.0, 1e-15);
    const std::vector<Vec2> tri = {{0, 0}, {1, 0}, {0, 1}};
    EXPECT_NEAR(clipped_area(tri, {0, 0}, {0.5, 0.5}), 0.25, 1e-15);
    EXPECT_NEAR(clipped_area(tri, {0.5, 0}, {1, 1}), 0.125, 1e-15);
}

}  // namespace
}  // namespace vlf
