// scene.hpp — the scene model: materials, convex planar faces, the charts that hold their
// texels (docs/charts.md), cameras,
// and the normalisation into the unit ball (DESIGN §3; VLF §3 "the scene is enclosed by a
// regular cuboid bound from (-1,-1,-1) to (1,1,1)").
//
// All face geometry is stored in *normalised* coordinates (the unit ball), so every rotated
// copy of the scene projects inside the PSF square [-1,1]^2. Cameras stay in user units;
// Normalisation converts between the two.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/light.hpp"
#include "vlf/scene/texture.hpp"

namespace vlf {

struct Material {
    std::string name;
    Rgb diffuse{0.0};   // rho_d per channel
    Rgb specular{0.0};  // rho_s per channel (ideal mirror)
    Rgb emission{0.0};  // Le, radiance of a Lambertian emitter, W m^-2 sr^-1
    // A diffuse colour texture (index into Scene::textures) or -1. With one, `diffuse` is
    // the material's mean albedo and the albedo at a point is diffuse x texture(uv) / its
    // mean (Scene::albedo_at): the texture's pattern at the material's level.
    int diffuse_texture = -1;
    // A dielectric's transmission (glTF KHR_materials_transmission), kept from imported
    // files (0 = opaque); a scene file's glass is `dielectric` instead.
    double transmission = 0.0;
    // Smooth glass (docs/scenes.md "Glass"): exact unpolarised Fresnel reflectance, Snell
    // refraction and total internal reflection at its faces (core/fresnel.hpp), Beer-Lambert
    // absorption inside. `ior` is the index inside relative to the outside (air, 1);
    // `absorption` the attenuation coefficient per channel, per user unit of length. A
    // dielectric has no diffuse, specular or emission; its objects are closed, and every
    // face has an inner twin (Face::inner).
    bool dielectric = false;
    double ior = 1.5;
    Rgb absorption{0.0};
    bool is_emitter() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
    // Specular faces keep directional radiance maps: mirrors and glass.
    bool is_specular() const {
        return dielectric || specular.x > 0 || specular.y > 0 || specular.z > 0;
    }
    bool is_absorbing() const {
        return dielectric && (absorption.x > 0 || absorption.y > 0 || absorption.z > 0);
    }
    bool is_diffuse() const { return diffuse.x > 0 || diffuse.y > 0 || diffuse.z > 0; }
};

// A rectangular texel grid on a face's plane (normalised units). Texel (i, j) covers
//   origin + [i, i+1]*size*axis_u + [j, j+1]*size*axis_v,   0 <= i < width, 0 <= j < height.
// axis_u, axis_v are unit, orthogonal, and axis_u x axis_v = face normal. The grid covers
// the face's bounding rectangle in that frame.
struct TexelFrame {
    Vec3 origin{0.0};
    Vec3 axis_u{1, 0, 0};
    Vec3 axis_v{0, 1, 0};
    double size = 1.0;  // texel edge length, normalised units
    int width = 1;
    int height = 1;
    int count() const { return width * height; }
    // Plane point -> continuous texel coordinates (texel (i,j) spans [i,i+1]x[j,j+1]).
    Vec2 to_texel(const Vec3& p) const {
        Vec3 d = p - origin;
        return {glm::dot(d, axis_u) / size, glm::dot(d, axis_v) / size};
    }
    Vec3 to_plane(const Vec2& t) const { return origin + (t.x * axis_u + t.y * axis_v) * size; }
};

struct Face {
    int id = 0;        // index into Scene::faces
    int object = 0;    // index into Scene::objects
    int material = 0;  // index into Scene::materials
    int twin = -1;     // the reverse face of a two-sided face (same polygon, other side)
    // A dielectric's face whose front looks into the glass (the twin of an outer face):
    // light arriving on its front travels inside, and the medium behind it is outside.
    bool inner = false;
    int chart = -1;              // index into Scene::charts: the surface whose texels it uses
    std::vector<Vec3> vertices;  // normalised coords, counter-clockwise seen from the front
    Vec3 normal{0, 0, 1};        // unit, front side
    double plane_offset = 0.0;   // dot(normal, x) == plane_offset on the face
    double area = 0.0;           // normalised units^2
    // Bit e set: edge e (vertices e -> e+1) is shared with another face of the same chart,
    // so a beam footprint is not clipped there (texel_clip.hpp). Edges from 64 on are
    // always treated as the chart's rim.
    uint64_t inner_edges = 0;
    // Bit e set: edge e lies on a contact line where the face was cut at load
    // (imprint.hpp); charts never grow across it. Used only while charts are built (not in
    // the bake).
    uint64_t cut_edges = 0;
    // Texture coordinates per vertex (a textured material's triangles), else empty.
    std::vector<Vec2> uv;
    // Smooth shading (docs/scenes.md "smooth"): a unit shading normal per vertex, each on
    // the front side (dot with `normal` > 0), interpolated across the face by
    // Scene::shading_normal; empty for a flat face. A twin's are its face's negated, in its
    // (reversed) vertex order.
    std::vector<Vec3> vertex_normals;
};

// A chart (docs/charts.md): connected faces of one material whose normals lie within a
// bounded angle of each other (coplanar faces of a polygon cut into triangles, a patch of a
// curved mesh), sharing one texel grid at the scene's texel density on the plane of
// `normal`. Texels belong to the surface, not to how it is cut into triangles: a face maps
// into the grid by projection along `normal`.
struct Chart {
    int id = 0;
    int material = 0;
    Vec3 normal{0, 0, 1};  // unit; the grid's plane normal (axis_u x axis_v)
    double area = 0.0;     // sum of its faces' areas, normalised units^2
    std::vector<int> faces;
    TexelFrame texels;
    // Per texel (row-major, j*width+i): the area of the chart's surface in the texel,
    // normalised units^2 (a tilted face's projected area over the cosine of its tilt), less
    // what lies sealed behind other faces (sealed_areas.hpp).
    std::vector<double> texel_area;
    bool planar = true;  // every face has the chart's normal (their texel areas are exact)
    // Derived from the faces (charts.hpp finish_chart): the sum of area x normal, and the
    // smallest cosine between a face's normal and `normal`.
    Vec3 area_normal{0.0};
    double min_cos = 1.0;
    // A textured material's mean albedo per texel (texel_albedo.hpp), else empty: the
    // material's `diffuse` holds everywhere.
    std::vector<Rgb> texel_albedo;
    // Per texel, the part of its surface that is not sealed behind another face
    // (sealed_areas.hpp), in [0, 1]; empty when nothing of the chart is sealed. Light a
    // beam lands on the sealed part is lost into the gap (receive_step.cpp). Derived at
    // load; not in the bake (rendering does not need it).
    std::vector<double> texel_open;
};

struct SceneObject {
    std::string name;  // from "name" or "<type>#<index>"
    std::string type;  // polygon, box, sphere, cylinder, mesh
    int first_face = 0;
    int face_count = 0;
};

struct Camera {  // user units
    std::string name;
    Vec3 eye{0.0};
    Vec3 look_at{0, 0, 1};
    Vec3 up{0, 1, 0};
    double fov_y_deg = 45.0;
};

// p_normalised = (p_user - center) * scale
struct Normalisation {
    Vec3 center{0.0};
    double scale = 1.0;
    Vec3 to_normalised(const Vec3& p) const { return (p - center) * scale; }
    Vec3 to_user(const Vec3& p) const { return p / scale + center; }
};

struct Scene {
    std::string source;  // file the scene was loaded from (for messages only)
    std::string units;   // informational unit name from the file ("" when absent)
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<SceneObject> objects;
    std::vector<Face> faces;
    std::vector<Chart> charts;
    std::vector<Camera> cameras;
    std::vector<Light> lights;  // point, spot and directional lights (light.hpp), user units
    Normalisation normalisation;
    Vec3 user_bounds_min{0.0}, user_bounds_max{0.0};
    double texel_size_user = 0.0;  // the texel size used, user units
    // Surfaces closer than this (normalised units: the texel size) behind the back of
    // another are sealed by it (sealed_areas.hpp, exchange.hpp kSealed).
    double seal_gap = 0.0;
    // What loading changed or left out, one line each (imported materials' unrepresented
    // properties, dropped degenerate faces, ...); the executables print them on stderr.
    std::vector<std::string> load_notes;

    const Material& material_of(const Face& f) const { return materials[f.material]; }
    const Material& material_of(const Chart& c) const { return materials[c.material]; }
    const Chart& chart_of(const Face& f) const { return charts[f.chart]; }
    // The diffuse albedo at point x (normalised units) of face f: the material's, modulated
    // by its texture where it has one (Material::diffuse_texture).
    // `footprint`: the texture's mean over about that many texture pixels (mip levels).
    Rgb albedo_at(const Face& f, const Vec3& x, double footprint = 0.0) const;
    // The unit shading normal of face f at x (normalised units, a point of the face): its
    // vertex normals interpolated (barycentric on a triangle, mean value coordinates on a
    // convex polygon), or the geometric normal when the face is flat. An inner dielectric
    // face's is its outer twin's negated. Always on the front side of f.
    Vec3 shading_normal(const Face& f, const Vec3& x) const;
    int emitter_count() const;        // faces whose material emits
    int specular_face_count() const;  // faces whose material has rho_s > 0
};

// A hash of a point's coordinates, bit for bit (-0 and +0 alike): for finding the vertices
// that faces share.
uint64_t position_hash(const Vec3& p);

// Interpolation weights of x over the vertices of a convex planar polygon with unit normal n
// (they sum to 1, and reproduce x): barycentric for a triangle, Floater's mean value
// coordinates otherwise (smooth inside, linear along the edges, the triangle's barycentrics
// for three vertices). x at a vertex or on an edge takes that vertex or edge's linear mix.
void polygon_weights(const std::vector<Vec3>& v, const Vec3& n, const Vec3& x,
                     std::vector<double>& w);

}  // namespace vlf
