// primitives.hpp — convex planar polygons: the shape generators of the scene file (box,
// icosphere, cylinder) and the polygon geometry the loader checks every face with
// (Newell normal, planarity, convexity, triangulation). DESIGN §3: "a scene is a set of
// planar convex polygons".
//
// A Polygon is a list of vertices, counter-clockwise seen from its front (right-hand rule:
// the front normal is the direction of Newell's vector). All functions work in whatever
// units the caller uses; tolerances that need a length scale take it as an argument.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

using Polygon = std::vector<Vec3>;

// ---- shape generators (outward-facing, untransformed) -------------------------------

// Axis-aligned box [min, max]: 6 quads, normals pointing out. Requires max > min per axis.
std::vector<Polygon> make_box(const Vec3& min, const Vec3& max);

// Icosphere: the icosahedron subdivided `subdivisions` times (midpoints pushed onto the
// sphere), 20*4^subdivisions triangles, normals pointing out. Shared edges use
// bit-identical vertices.
std::vector<Polygon> make_icosphere(const Vec3& center, double radius, int subdivisions);

struct CylinderShape {
    Vec3 base_center{0.0};    // centre of the bottom cap; the axis runs along +y
    double radius = 1.0;      // outer radius, > 0
    double inner_radius = 0;  // 0 <= inner < radius; > 0 makes a tube with an inner wall
    double height = 1.0;      // > 0
    int segments = 32;        // >= 3
    bool caps = true;
};

// Faceted cylinder. Outer wall: `segments` quads facing out. When inner_radius > 0: an inner
// wall of `segments` quads facing the axis, and annular caps made of quads; otherwise caps
// are fans of triangles around the cap centre. Caps face -y (bottom) and +y (top).
// Face order: outer wall, inner wall, bottom cap, top cap.
std::vector<Polygon> make_cylinder(const CylinderShape& shape);

// ---- smooth shading normals (docs/scenes.md "smooth") ---------------------------------

// Per face, per vertex: the unit normals of the surface the faces approximate, or an empty
// list for a face that stays flat. `faces` as the generators above made them (untransformed).
using VertexNormals = std::vector<std::vector<Vec3>>;

// The sphere's: (vertex - center) / |vertex - center| at every vertex of every face.
VertexNormals sphere_normals(const std::vector<Polygon>& faces, const Vec3& center);

// The cylinder's curved walls (the outer wall's normals point away from the axis, the inner
// wall's towards it, both perpendicular to it); the caps stay flat. `faces` is
// make_cylinder(shape).
VertexNormals cylinder_normals(const std::vector<Polygon>& faces, const CylinderShape& shape);

// ---- polygon geometry ----------------------------------------------------------------

// Newell's vector: twice the area, in the front-normal direction (exact for planar polygons;
// for a non-planar one it is the area vector of its projection onto the best-fit plane).
Vec3 newell_vector(const Polygon& p);
Vec3 polygon_centroid(const Polygon& p);  // vertex average
double polygon_area(const Polygon& p);    // |newell_vector| / 2

// Largest distance of a vertex from the plane through the centroid with Newell's normal.
// Returns +inf for a polygon whose Newell vector is zero.
double max_plane_deviation(const Polygon& p);

// Why a polygon is not a valid scene face, or nullopt when it is one: at least 3
// vertices, area > (eps_length)^2, no edge shorter than eps_length, every vertex within
// planar_tolerance of its plane, convex (never turns clockwise, winds exactly once).
// Messages read like "polygon is not planar (max deviation 3.2 from its plane)".
std::optional<std::string> polygon_problem(const Polygon& p, double planar_tolerance,
                                           double eps_length);

// Triangulates a polygon into triangles with its orientation. Planar polygons (within
// planar_tolerance), convex or not but simple, are ear-clipped; non-planar ones are fanned
// from vertex 0. Triangles with area <= eps_length^2 are dropped. Returns nullopt when ear
// clipping finds no ear (self-intersecting outline).
std::optional<std::vector<Polygon>> triangulate_polygon(const Polygon& p, double planar_tolerance,
                                                        double eps_length);

}  // namespace vlf
