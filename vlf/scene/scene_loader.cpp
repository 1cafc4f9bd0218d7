// scene_loader.cpp — JSON scene files to a Scene (DESIGN §3), in four stages:
//
//   parse     text -> JSON tree (core/json_reader.hpp): syntax errors name line and column,
//             numbers that overflow a double (1e999) name their JSON place, duplicate keys
//             are errors;
//   validate  JSON tree -> SceneDescription through the JSON reader: every key known, every
//             type and range checked, materials resolved; nothing is read from disk yet;
//   load      mesh files -> ImportedMesh (OpenMesh readers);
//   build     shapes -> transformed polygons (user units) -> checked convex planar faces
//             -> normalisation into the unit ball -> texel frames.
//
// Every problem is a SceneError "<file>: <json.path>: <message>".
//
// Keys (anything else is an error; "?" = optional, with its default). docs/scene.schema.json
// says the same as a JSON Schema; keep the two in step (tests/scene_schema_test.py).
//   top level  materials {name: material}, objects [object, ...] (non-empty),
//              cameras? [camera, ...], lights? [light, ...], settings? {texel_size? (> 0, user
//              units), units? (string)}, $schema? (string: the schema, for editors; ignored)
//   material   diffuse? [r,g,b] = 0, specular? [r,g,b] = 0 (each in [0,1],
//              diffuse + specular <= 1 per channel), emission? [r,g,b] = 0 (>= 0, W m^-2 sr^-1)
//   object     type (polygon|box|sphere|cylinder|mesh|import), material (optional for
//              import), name? = "<type>#<index>",
//              two_sided? = false, flip? = false, scale? = 1 (number or [sx,sy,sz], > 0),
//              smooth? (vertex normals: default true for sphere, the cylinder's walls and
//              mesh or import files with normals; true is an error for polygon and box),
//              rotate_x_deg? / rotate_y_deg? / rotate_z_deg? = 0, translate? = [0,0,0]
//              applied as: scale, rotate x, y, z (about the pivot), translate. Pivot: box
//              centre, sphere centre, cylinder axis midpoint; the origin for polygon and mesh.
//   - polygon  vertices [[x,y,z] x >= 3] (counter-clockwise seen from the front),
//              triangulate? = false
//   - box      min, max (max > min per axis)
//   - sphere   center? = [0,0,0], radius (> 0), subdivisions? = 2 (integer 0..6)
//   - cylinder radius (> 0), height (> 0), inner_radius? = 0 (0 <= inner < radius),
//              center? = [0,0,0] (base centre; axis +y), segments? = 32 (3..4096),
//              caps? = true
//   - mesh     file (.obj .ply .off .stl, relative to the scene file's directory),
//              triangulate? = false
//   - import   file (any format assimp reads: .obj with its .mtl, .gltf, .glb, .ply, .fbx,
//              .dae, ...), materials? {file material name: scene material name} (overrides
//              some), material? (overrides all: the file's materials are then unused).
//              Each of the file's materials becomes a scene material "<name>/<file's
//              material>" (scene_import.hpp) and an object of that name; faces are
//              triangulated (degenerate triangles dropped with a count in the load notes);
//              two_sided when the object or the file's material says so. The file's cameras
//              join the scene's as "<name>/<camera>".
//   light      type (point|spot|directional), name? = "light#<index>" (light.hpp):
//   - point    position, power [W,W,W] or intensity [W/sr,...] (each >= 0, <= 1e20)
//   - spot     position, direction (the axis), outer_deg (0 < outer <= 180), inner_deg? = 0
//              (<= outer; smoothstep falloff between), power or intensity (on the axis)
//   - directional  direction (the way the light travels), irradiance [W/unit^2,...] on a
//              plane facing it, angular_diameter_deg? = 0 (0..30; the sun's is 0.53)
//   camera     name? = "camera#<index>", eye, look_at (!= eye), up? = [0,1,0] (not parallel
//              to the view direction), fov_y_deg (0 < fov < 180); user units
// "triangulate": true turns every face of the object into triangles (ear clipping for planar
// faces, convex or not; a fan from vertex 0 for non-planar ones; zero-area triangles dropped).
//
// Tolerances (documented contract): a face is planar when every vertex lies within
// kRelativeTolerance × D of its Newell plane, and degenerate when an edge is shorter than
// kRelativeTolerance × D or its area is below (kRelativeTolerance × D)², where D is the
// diagonal of the scene's bounding box in user units. Mesh face indices in messages are
// 0-based, in file order.
#include "vlf/scene/scene_loader.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"
#include "vlf/core/json_reader.hpp"
#include "vlf/scene/charts.hpp"
#include "vlf/scene/closed_surface.hpp"
#include "vlf/scene/imprint.hpp"
#include "vlf/scene/mesh_import.hpp"
#include "vlf/scene/primitives.hpp"
#include "vlf/scene/scene_import.hpp"
#include "vlf/scene/sealed_areas.hpp"
#include "vlf/scene/texel_albedo.hpp"

namespace vlf {

namespace {

using Json = nlohmann::ordered_json;  // keeps file order: materials are indexed as written
using Reader = OrderedJsonReader;

constexpr double kRelativeTolerance = 1e-6;
constexpr double kMaxEmission = 1e20;
// Scene coordinates (after transforms) beyond this are refused: with the relative tolerance
// above, a scene that large cannot hold millimetre detail anywhere.
constexpr double kMaxCoordinate = 1e15;
constexpr double kNormalisedRadius = 0.999;  // geometry strictly inside the unit ball

[[noreturn]] void fail(const std::string& file, const std::string& place, const std::string& what) {
    throw SceneError(fmt::format("{}: {}: {}", file, place, what));
}

// ============================ stages 1 and 2: parse, validate ============================

struct ObjectDesc {
    std::string place;  // "objects[3]"
    std::string name;
    std::string type;
    int material = 0;
    bool two_sided = false, flip = false, triangulate = false;
    std::optional<bool> smooth;  // "smooth" as given (the default depends on the type)
    Vec3 scale{1.0}, rotate_deg{0.0}, translate{0.0};
    std::vector<Vec3> vertices;  // polygon
    Vec3 box_min{0.0}, box_max{0.0};
    Vec3 center{0.0};  // sphere
    double radius = 0;
    int subdivisions = 2;
    CylinderShape cylinder;
    std::string file, file_path;  // mesh: as written, resolved against the scene directory
    bool material_given = true;   // import: "material" overrides the file's materials
    std::vector<std::pair<std::string, int>> material_overrides;  // import: "materials"
    std::string overrides_place;                                  // import: "objects[i].materials"
    int source_object = 0;  // after the imports are expanded: the JSON object it came from
    // An imported file's glass (scene_import.hpp): the file's material it replaced, taken
    // instead where the faces are not closed once degenerate or repeated ones are dropped.
    std::optional<Material> glass_fallback;
    std::string glass_source;  // "<file>: material '<name>'", for the note
};

struct SceneDescription {
    std::vector<Material> materials;
    std::vector<ObjectDesc> objects;
    std::vector<Camera> cameras;
    std::vector<Light> lights;
    std::optional<double> texel_size;
    std::string units;
    std::vector<std::string> notes;  // Scene::load_notes
    std::vector<Texture> textures;   // imported files' diffuse textures (Scene::textures)
};

const std::vector<std::string> kObjectTypes = {"polygon",  "box",  "sphere",
                                               "cylinder", "mesh", "import"};

// The keys an object of `type` may have.
std::vector<std::string> object_keys(const std::string& type) {
    std::vector<std::string> keys = {"type",         "material",  "name",         "two_sided",
                                     "flip",         "scale",     "rotate_x_deg", "rotate_y_deg",
                                     "rotate_z_deg", "translate", "smooth"};
    std::vector<std::string> specific;
    if (type == "polygon")
        specific = {"vertices", "triangulate"};
    else if (type == "box")
        specific = {"min", "max"};
    else if (type == "sphere")
        specific = {"center", "radius", "subdivisions"};
    else if (type == "cylinder")
        specific = {"radius", "inner_radius", "height", "center", "segments", "caps"};
    else if (type == "mesh")
        specific = {"file", "triangulate"};
    else if (type == "import")
        specific = {"file", "materials"};
    keys.insert(keys.end(), specific.begin(), specific.end());
    return keys;
}

// [r, g, b] with every channel in [0, upper]; `bound` says why the upper bound.
Rgb checked_rgb(const Reader& e, double upper, const char* bound) {
    const Rgb c = e.vec3();
    for (int i = 0; i < 3; ++i) {
        if (c[i] < 0) e.element(i).fail(fmt::format("must be >= 0 (got {})", c[i]));
        if (c[i] > upper) e.element(i).fail(fmt::format("{} (got {})", bound, c[i]));
    }
    return c;
}

// "dielectric": {"ior": n, "absorption"?: [r, g, b]} (per user unit of length): glass.
void validate_dielectric(const Reader& r, Material& m) {
    for (const char* other : {"diffuse", "specular", "emission"})
        if (r.optional(other))
            r.required(other).fail(
                "a dielectric material has no diffuse, specular or emission (its reflectance "
                "is Fresnel's)");
    const Reader d = r.required("dielectric");
    d.expect_object();
    d.only_keys({"ior", "absorption"});
    m.dielectric = true;
    m.ior = d.required("ior").positive();
    if (!(m.ior > 1.0 && m.ior <= 4.0))
        d.required("ior").fail(fmt::format("must be in (1, 4] (got {})", m.ior));
    if (const auto a = d.optional("absorption"))
        m.absorption = checked_rgb(*a, 1e6, "absorption must be <= 1e6 per unit of length");
}

Material validate_material(const Reader& r, const std::string& name) {
    r.only_keys({"diffuse", "specular", "emission", "dielectric"});
    Material m;
    m.name = name;
    if (r.optional("dielectric")) {
        validate_dielectric(r, m);
        return m;
    }
    auto rgb = [&](const char* key, double upper, const char* bound) {
        const auto e = r.optional(key);
        return e ? checked_rgb(*e, upper, bound) : Rgb(0.0);
    };
    m.diffuse = rgb("diffuse", 1.0, "reflectance must be <= 1");
    m.specular = rgb("specular", 1.0, "reflectance must be <= 1");
    // Far above any lamp (the sun's disc is ~2e7 W m^-2 sr^-1), far below where the
    // ledger's sums of power over faces and cycles would overflow.
    m.emission = rgb("emission", kMaxEmission,
                     "emission must be <= 1e20 W m^-2 sr^-1 (the power ledger would overflow)");
    for (int i = 0; i < 3; ++i)
        if (m.diffuse[i] + m.specular[i] > 1.0)
            r.fail(fmt::format(
                "diffuse + specular = {} > 1 in channel {} (reflectance must not exceed 1)",
                m.diffuse[i] + m.specular[i], i));
    return m;
}

void validate_transform(const Reader& r, ObjectDesc& o) {
    if (const auto s = r.optional("scale")) {
        if (s->json().is_number()) {
            o.scale = Vec3(s->positive());
        } else if (s->json().is_array()) {
            o.scale = s->vec3();
            for (int i = 0; i < 3; ++i)
                if (!(o.scale[i] > 0))
                    s->element(i).fail(fmt::format("must be > 0 (got {})", o.scale[i]));
        } else {
            s->fail(fmt::format("expected a number or an array of 3 numbers, got {}",
                                describe_json(s->json())));
        }
    }
    const char* rot[3] = {"rotate_x_deg", "rotate_y_deg", "rotate_z_deg"};
    for (int a = 0; a < 3; ++a)
        if (const auto v = r.optional(rot[a])) o.rotate_deg[a] = v->number();
    if (const auto t = r.optional("translate")) o.translate = t->vec3();
}

void validate_polygon(const Reader& r, ObjectDesc& o) {
    const Reader vs = r.required("vertices");
    if (!vs.json().is_array())
        vs.fail(fmt::format("expected an array of points, got {}", describe_json(vs.json())));
    const std::vector<Reader> points = vs.elements();
    if (points.size() < 3)
        vs.fail(fmt::format("a polygon needs at least 3 vertices (got {})", points.size()));
    for (const Reader& p : points) o.vertices.push_back(p.vec3());
}

void validate_box(const Reader& r, ObjectDesc& o) {
    o.box_min = r.required("min").vec3();
    const Reader max = r.required("max");
    o.box_max = max.vec3();
    for (int a = 0; a < 3; ++a)
        if (!(o.box_max[a] > o.box_min[a]))
            max.element(a).fail(fmt::format("must be greater than min[{}] ({} <= {})", a,
                                            o.box_max[a], o.box_min[a]));
}

void validate_sphere(const Reader& r, ObjectDesc& o) {
    if (const auto c = r.optional("center")) o.center = c->vec3();
    o.radius = r.required("radius").positive();
    if (const auto s = r.optional("subdivisions")) o.subdivisions = s->integer(0, 6);
}

void validate_cylinder(const Reader& r, ObjectDesc& o) {
    CylinderShape& c = o.cylinder;
    c.radius = r.required("radius").positive();
    c.height = r.required("height").positive();
    if (const auto inner = r.optional("inner_radius")) {
        c.inner_radius = inner->number();
        if (!(c.inner_radius >= 0 && c.inner_radius < c.radius))
            inner->fail(
                fmt::format("must be >= 0 and < radius {} (got {})", c.radius, c.inner_radius));
    }
    if (const auto b = r.optional("center")) c.base_center = b->vec3();
    if (const auto s = r.optional("segments")) c.segments = s->integer(3, 4096);
    if (const auto b = r.optional("caps")) c.caps = b->boolean();
}

void validate_file(const Reader& r, ObjectDesc& o, const std::string& base_dir) {
    const Reader file = r.required("file");
    o.file = file.string();
    if (o.file.empty()) file.fail("empty file name");
    std::filesystem::path p(o.file);
    o.file_path = (p.is_absolute() || base_dir.empty())
                      ? p.string()
                      : (std::filesystem::path(base_dir) / p).string();
    if (o.type == "mesh" && !is_supported_mesh_file(o.file))
        file.fail(
            fmt::format("'{}': unsupported mesh format (use .obj, .ply, .off or .stl, or \"type\": "
                        "\"import\" for whole scenes)",
                        o.file));
    if (o.type == "import" && !is_importable_scene_file(o.file))
        file.fail(
            fmt::format("'{}': no importer reads '{}' files", o.file, lower_extension(o.file)));
}

void validate_import(const Reader& r, ObjectDesc& o, const std::string& base_dir,
                     const std::vector<std::string>& material_names) {
    validate_file(r, o, base_dir);
    o.triangulate = true;
    if (const auto m = r.optional("materials")) {
        if (r.optional("material"))
            m->fail(
                "cannot be combined with \"material\" (which overrides all of the file's "
                "materials)");
        m->expect_object();
        o.overrides_place = m->path();
        for (const auto& [name, target] : m->members())
            o.material_overrides.emplace_back(
                name, static_cast<int>(target.one_of(material_names, "material")));
    }
}

ObjectDesc validate_object(const Reader& r, int index,
                           const std::vector<std::string>& material_names,
                           const std::string& base_dir) {
    ObjectDesc o;
    o.place = r.path();
    r.expect_object();
    o.type = kObjectTypes[r.required("type").one_of(kObjectTypes, "type")];
    r.only_keys(object_keys(o.type), " for a " + o.type);
    if (o.type == "import" && !r.optional("material"))
        o.material_given = false;
    else
        o.material = static_cast<int>(r.required("material").one_of(material_names, "material"));
    o.name = fmt::format("{}#{}", o.type, index);
    if (const auto n = r.optional("name")) o.name = n->string();
    if (const auto b = r.optional("two_sided")) o.two_sided = b->boolean();
    if (const auto b = r.optional("flip")) o.flip = b->boolean();
    if (const auto b = r.optional("triangulate")) o.triangulate = b->boolean();
    if (const auto b = r.optional("smooth")) {
        o.smooth = b->boolean();
        if (*o.smooth && (o.type == "polygon" || o.type == "box"))
            b->fail(fmt::format(
                "a {} has no vertex normals to smooth with (\"smooth\": true is for sphere, "
                "cylinder, mesh and import)",
                o.type));
    }
    validate_transform(r, o);
    if (o.type == "polygon")
        validate_polygon(r, o);
    else if (o.type == "box")
        validate_box(r, o);
    else if (o.type == "sphere")
        validate_sphere(r, o);
    else if (o.type == "cylinder")
        validate_cylinder(r, o);
    else if (o.type == "mesh")
        validate_file(r, o, base_dir);
    else
        validate_import(r, o, base_dir, material_names);
    return o;
}

Camera validate_camera(const Reader& r, int index) {
    r.expect_object();
    r.only_keys({"name", "eye", "look_at", "up", "fov_y_deg"});
    Camera c;
    c.name = fmt::format("camera#{}", index);
    if (const auto n = r.optional("name")) c.name = n->string();
    c.eye = r.required("eye").vec3();
    const Reader look_at = r.required("look_at");
    c.look_at = look_at.vec3();
    const auto up = r.optional("up");
    if (up) c.up = up->vec3();
    const Reader fov = r.required("fov_y_deg");
    c.fov_y_deg = fov.number();
    if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180))
        fov.fail(fmt::format("must be in (0, 180) degrees (got {})", c.fov_y_deg));
    const Vec3 d = c.look_at - c.eye;
    if (!(glm::length(d) > 0)) look_at.fail("equals eye (no view direction)");
    // The default up is checked too; its messages name the key it stands for.
    const Reader up_place = up ? *up : r;
    const std::string up_what = up ? "" : "the default up [0,1,0] ";
    if (!(glm::length(c.up) > 0)) up_place.fail(up_what + "is the zero vector");
    const double s = glm::length(glm::cross(glm::normalize(d), glm::normalize(c.up)));
    if (!(s > 1e-6)) up_place.fail(up_what + "is parallel to the view direction (look_at - eye)");
    return c;
}

// A unit direction from a non-zero [x, y, z].
Vec3 unit_direction(const Reader& r) {
    const Vec3 d = r.vec3();
    const double len = glm::length(d);
    if (!(len > 0) || !std::isfinite(len)) r.fail("must be a non-zero direction");
    return d / len;
}

// A light (light.hpp): point {position, power | intensity}, spot {position, direction,
// inner_deg?, outer_deg, power | intensity}, directional {direction, irradiance,
// angular_diameter_deg?}.
Light validate_light(const Reader& r, int index) {
    r.expect_object();
    Light l;
    const Reader type = r.required("type");
    const size_t t = type.one_of({"point", "spot", "directional"}, "light type");
    l.type = t == 0 ? LightType::Point : t == 1 ? LightType::Spot : LightType::Directional;
    l.name = fmt::format("light#{}", index);
    if (const auto n = r.optional("name")) l.name = n->string();
    const char* kBound = "must be <= 1e20 (the power ledger would overflow)";
    if (l.type == LightType::Directional) {
        r.only_keys({"type", "name", "direction", "irradiance", "angular_diameter_deg"},
                    " for a directional light");
        l.direction = unit_direction(r.required("direction"));
        l.irradiance = checked_rgb(r.required("irradiance"), kMaxEmission, kBound);
        if (const auto a = r.optional("angular_diameter_deg"))
            l.angular_diameter_deg = a->number(0, 30);
        return l;
    }
    std::vector<std::string> keys = {"type", "name", "position", "power", "intensity"};
    if (l.type == LightType::Spot)
        for (const char* k : {"direction", "inner_deg", "outer_deg"}) keys.push_back(k);
    r.only_keys(keys, fmt::format(" for a {} light", light_type_name(l.type)));
    const Reader pos = r.required("position");
    l.position = pos.vec3();
    for (int i = 0; i < 3; ++i)
        if (std::abs(l.position[i]) > kMaxCoordinate)
            pos.element(i).fail(fmt::format("coordinate {} is beyond +-1e15", l.position[i]));
    if (l.type == LightType::Spot) {
        l.direction = unit_direction(r.required("direction"));
        const Reader outer = r.required("outer_deg");
        const double outer_deg = outer.number();
        if (!(outer_deg > 0 && outer_deg <= 180))
            outer.fail(fmt::format("must be in (0, 180] degrees (got {})", outer_deg));
        double inner_deg = 0;
        if (const auto inner = r.optional("inner_deg")) {
            inner_deg = inner->number();
            if (!(inner_deg >= 0 && inner_deg <= outer_deg))
                inner->fail(fmt::format("must be in [0, outer_deg = {}] degrees (got {})",
                                        outer_deg, inner_deg));
        }
        l.cos_inner = std::cos(inner_deg * kPi / 180.0);
        l.cos_outer = std::cos(outer_deg * kPi / 180.0);
    }
    const auto power = r.optional("power"), intensity = r.optional("intensity");
    if (power && intensity) intensity->fail("give either power or intensity, not both");
    if (!power && !intensity) r.fail("a point or spot light needs power (W) or intensity (W/sr)");
    if (intensity) {
        l.intensity = checked_rgb(*intensity, kMaxEmission, kBound);
    } else {
        l.intensity = checked_rgb(*power, kMaxEmission, kBound) / l.solid_angle();
    }
    return l;
}

std::vector<Material> validate_materials(const Reader& r) {
    r.expect_object();
    std::vector<Material> materials;
    for (const auto& [name, m] : r.members()) {
        if (name.empty()) r.fail("empty material name");
        m.expect_object();
        materials.push_back(validate_material(m, name));
    }
    return materials;
}

// A list of things with unique names (cameras, lights), each validated by `one`; a repeated
// name is reported at the repeat's "name" (or the element, when the name is the default).
template <class T, class Validate>
std::vector<T> validate_named(const Reader& r, const char* what, Validate one) {
    std::vector<T> items;
    std::set<std::string> names;
    const std::vector<Reader> list = r.elements();
    for (size_t i = 0; i < list.size(); ++i) {
        items.push_back(one(list[i], static_cast<int>(i)));
        if (!names.insert(items.back().name).second) {
            const auto name = list[i].optional("name");
            (name ? *name : list[i])
                .fail(fmt::format("duplicate {} name '{}'", what, items.back().name));
        }
    }
    return items;
}

void validate_settings(const Reader& r, SceneDescription& d) {
    r.expect_object();
    r.only_keys({"texel_size", "units"});
    if (const auto t = r.optional("texel_size")) d.texel_size = t->positive();
    if (const auto u = r.optional("units")) d.units = u->string();
}

SceneDescription validate(const Json& root, const std::string& file, const std::string& base_dir) {
    const Reader r(root, file);
    SceneDescription d;
    r.expect_object();
    r.only_keys({"$schema", "materials", "objects", "cameras", "lights", "settings"});
    if (const auto schema = r.optional("$schema")) schema->string();  // for editors; ignored
    d.materials = validate_materials(r.required("materials"));
    std::vector<std::string> material_names;
    for (const Material& m : d.materials) material_names.push_back(m.name);

    const Reader objs = r.required("objects");
    const std::vector<Reader> objects = objs.elements();
    if (objects.empty()) objs.fail("the scene has no objects");
    for (size_t i = 0; i < objects.size(); ++i)
        d.objects.push_back(
            validate_object(objects[i], static_cast<int>(i), material_names, base_dir));

    if (const auto cams = r.optional("cameras"))
        d.cameras = validate_named<Camera>(*cams, "camera", validate_camera);
    if (const auto lights = r.optional("lights"))
        d.lights = validate_named<Light>(*lights, "light", validate_light);
    if (const auto s = r.optional("settings")) validate_settings(*s, d);

    // (An imported file's materials and lights are known only once it is read.)
    const bool any_emitter =
        std::any_of(d.objects.begin(), d.objects.end(),
                    [&](const ObjectDesc& o) {
                        // (an import may emit through its file's lights even when
                        // "material" overrides its materials)
                        return o.type == "import" || d.materials[o.material].is_emitter();
                    }) ||
        std::any_of(d.lights.begin(), d.lights.end(), [](const Light& l) { return l.emits(); });
    if (!any_emitter)
        objs.fail("no emitter: no object uses a material with emission > 0 and no light emits");
    return d;
}

// sin and cos of an angle in degrees, exact for multiples of 90 degrees so axis-aligned
// rotations keep shared vertices and planes exact.
void sincos_deg(double deg, double& s, double& c) {
    const double r = std::fmod(deg, 360.0);
    const double q = r < 0 ? r + 360.0 : r;
    if (q == 0)
        s = 0, c = 1;
    else if (q == 90)
        s = 1, c = 0;
    else if (q == 180)
        s = 0, c = -1;
    else if (q == 270)
        s = -1, c = 0;
    else
        s = std::sin(q * kPi / 180.0), c = std::cos(q * kPi / 180.0);
}

// Scale, then rotate about x, y, z, then translate; scale and rotation act about `pivot`.
struct Transform {
    Vec3 pivot{0.0}, scale{1.0}, translate{0.0};
    Mat3 rotation{1.0};
    bool linear_identity = true;

    Transform(const ObjectDesc& o, const Vec3& pivot_point)
        : pivot(pivot_point), scale(o.scale), translate(o.translate) {
        double s, c;
        sincos_deg(o.rotate_deg.x, s, c);
        const Mat3 rx(1, 0, 0, 0, c, s, 0, -s, c);  // GLM matrices are column-major
        sincos_deg(o.rotate_deg.y, s, c);
        const Mat3 ry(c, 0, -s, 0, 1, 0, s, 0, c);
        sincos_deg(o.rotate_deg.z, s, c);
        const Mat3 rz(c, s, 0, -s, c, 0, 0, 0, 1);
        rotation = rz * ry * rx;
        linear_identity = scale == Vec3(1.0) && rotation == Mat3(1.0);
    }
    Vec3 operator()(const Vec3& p) const {
        // The identity part is skipped so untransformed vertices stay bit-identical.
        if (linear_identity) return p + translate;
        return rotation * ((p - pivot) * scale) + pivot + translate;
    }
    // A surface normal moves by the inverse transpose of the linear part (a unit normal,
    // or a zero or non-finite one as it was).
    Vec3 normal(const Vec3& n) const {
        const Vec3 m = linear_identity ? n : rotation * (n / scale);
        const double len = glm::length(m);
        return len > 0 && std::isfinite(len) ? m / len : m;
    }
    Vec3 inverse(const Vec3& q) const {
        return glm::transpose(rotation) * (q - pivot - translate) / scale + pivot;
    }
};

// ================================ stage 3: load =========================================

// An imported glass's absorption is per file unit: the object's scale makes it per user unit
// (a non-uniform scale by the geometric mean of its factors, noted). Beyond the scene file's
// bound of 1e6 per unit (an attenuation colour of 0) it is 1e6: opaque glass (noted).
void glass_absorption_to_user_units(const ObjectDesc& o, ImportedGroup& g) {
    Rgb& a = g.material.absorption;
    if (a == Rgb(0.0)) return;
    const double s = std::cbrt(o.scale.x * o.scale.y * o.scale.z);
    if (o.scale.x != o.scale.y || o.scale.y != o.scale.z)
        g.unrepresented.push_back(
            fmt::format("absorption under a non-uniform scale (divided by the geometric mean "
                        "{:.6g} of its factors)",
                        s));
    constexpr double kMostAbsorption = 1e6;  // validate_dielectric's bound
    bool capped = false;
    for (int c = 0; c < 3; ++c) {
        a[c] /= s;
        if (!(a[c] <= kMostAbsorption)) a[c] = kMostAbsorption, capped = true;
    }
    if (capped)
        g.unrepresented.push_back(
            "an absorption above 1e6 per unit (an attenuation colour of 0): 1e6, opaque");
}

// An import object becomes one object per material of its file (scene_import.hpp): the
// file's materials join the scene's (or are overridden), its cameras and lights join the
// scene's as "<name>/<camera>", "<name>/<light>", moved by the object's transform.
void expand_import(SceneDescription& d, const ObjectDesc& o, ImportedScene&& imported,
                   std::vector<ObjectDesc>& objects, std::vector<ImportedMesh>& meshes) {
    std::set<std::string> used;
    for (const auto& [name, target] : o.material_overrides) {
        const bool known =
            std::any_of(imported.groups.begin(), imported.groups.end(),
                        [&](const ImportedGroup& g) { return g.material_name == name; });
        if (!known) {
            std::string names;
            for (const ImportedGroup& g : imported.groups)
                names += (names.empty() ? "'" : ", '") + g.material_name + "'";
            throw SceneError(
                fmt::format("{}: no material '{}' in '{}' (its materials with "
                            "faces: {})",
                            o.overrides_place, name, o.file, names));
        }
    }
    for (ImportedGroup& g : imported.groups) {
        ObjectDesc part = o;
        std::string label = g.material_name;
        for (int k = 2; !used.insert(label).second; ++k)
            label = fmt::format("{}#{}", g.material_name, k);
        part.name = o.name + "/" + label;
        part.two_sided = o.two_sided || g.two_sided;
        const auto over = std::find_if(o.material_overrides.begin(), o.material_overrides.end(),
                                       [&](const auto& m) { return m.first == g.material_name; });
        if (o.material_given) {
            part.material = o.material;
            g.mesh.uvs.clear();
        } else if (over != o.material_overrides.end()) {
            part.material = over->second;
            g.mesh.uvs.clear();
        } else {
            g.material.name = part.name;
            if (g.material.dielectric) glass_absorption_to_user_units(o, g);
            if (g.texture.width > 0 && g.material.is_diffuse()) {
                g.material.diffuse_texture = static_cast<int>(d.textures.size());
                d.textures.push_back(std::move(g.texture));
            } else {
                g.mesh.uvs.clear();
            }
            part.material = static_cast<int>(d.materials.size());
            d.materials.push_back(g.material);
            if (g.material.dielectric && g.not_glass) {
                part.glass_fallback = *g.not_glass;
                part.glass_fallback->name = part.name;
                part.glass_source = fmt::format("{}: material '{}'", o.file, g.material_name);
            }
            if (!g.unrepresented.empty()) {
                std::string what;
                for (const std::string& u : g.unrepresented) what += (what.empty() ? "" : "; ") + u;
                d.notes.push_back(
                    fmt::format("{}: material '{}': left out: {}", o.file, g.material_name, what));
            }
        }
        objects.push_back(std::move(part));
        meshes.push_back(std::move(g.mesh));
    }
    for (const std::string& l : imported.left_out)
        d.notes.push_back(fmt::format("{}: left out: {}", o.file, l));
    for (const std::string& n : imported.notes) d.notes.push_back(fmt::format("{}: {}", o.file, n));
    const Transform xf(o, Vec3(0.0));
    for (Camera c : imported.cameras) {
        const Vec3 up_tip = xf(c.eye + c.up);
        c.eye = xf(c.eye);
        c.look_at = xf(c.look_at);
        c.up = up_tip - c.eye;
        c.name = o.name + "/" + c.name;
        d.cameras.push_back(c);
    }
    std::set<std::string> light_names;
    for (const Light& l : d.lights) light_names.insert(l.name);
    for (Light l : imported.lights) {
        // A direction is the difference of two moved points (scale and rotation, no
        // translation); intensities are per steradian and stay as they are.
        const Vec3 moved = xf(l.position + l.direction) - xf(l.position);
        if (l.type != LightType::Directional) l.position = xf(l.position);
        if (l.type != LightType::Point) l.direction = glm::normalize(moved);
        const std::string name = o.name + "/" + l.name;
        l.name = name;
        for (int k = 2; !light_names.insert(l.name).second; ++k)
            l.name = fmt::format("{}#{}", name, k);
        d.lights.push_back(l);
    }
}

// "smooth": true needs a file with vertex normals (an import: in any of its parts); normals a
// file has but cannot give per vertex are noted.
void check_smooth(SceneDescription& d, const std::vector<ImportedMesh>& meshes,
                  const std::string& file) {
    std::vector<char> has_normals(
        d.objects.empty() ? 0 : size_t(d.objects.back().source_object) + 1, 0);
    for (size_t i = 0; i < d.objects.size(); ++i) {
        const ObjectDesc& o = d.objects[i];
        if (!meshes[i].normals.empty()) has_normals[size_t(o.source_object)] = 1;
        if (!meshes[i].normals_left_out.empty() && o.smooth != false)
            d.notes.push_back(fmt::format("{}: {} ({}): '{}': vertex normals left out (flat): {}",
                                          file, o.place, o.name, o.file,
                                          meshes[i].normals_left_out));
    }
    for (const ObjectDesc& o : d.objects)
        if ((o.type == "mesh" || o.type == "import") && o.smooth == true &&
            !has_normals[size_t(o.source_object)])
            fail(file, o.place + ".smooth",
                 fmt::format("'{}' has no vertex normals{} (\"smooth\": true needs them)", o.file,
                             o.type == "mesh" && lower_extension(o.file) == ".stl"
                                 ? " (STL files have facet normals only)"
                                 : ""));
}

// Reads the mesh files and expands the imports; returns one mesh per (expanded) object.
std::vector<ImportedMesh> load_resources(SceneDescription& d, const std::string& file) {
    std::vector<ObjectDesc> objects;
    std::vector<ImportedMesh> meshes;
    for (size_t i = 0; i < d.objects.size(); ++i) {
        ObjectDesc& o = d.objects[i];
        o.source_object = static_cast<int>(i);
        try {
            if (o.type == "import") {
                // The scene's own cameras and point and spot lights, in the file's frame:
                // a closed part of the file around one is a room seen from inside
                // (winding.hpp).
                const Transform xf(o, Vec3(0.0));
                std::vector<Vec3> viewpoints;
                for (const Camera& c : d.cameras) viewpoints.push_back(xf.inverse(c.eye));
                for (const Light& l : d.lights)
                    if (l.type != LightType::Directional)
                        viewpoints.push_back(xf.inverse(l.position));
                expand_import(d, o, import_scene_file(o.file_path, viewpoints), objects, meshes);
                continue;
            }
            meshes.push_back(o.type == "mesh" ? import_mesh(o.file_path) : ImportedMesh{});
            objects.push_back(std::move(o));
        } catch (const SceneError& e) {
            throw SceneError(fmt::format("{}: {}", file, e.what()));
        } catch (const Error& e) {
            // A model file given on its own is the scene: its messages need no JSON place.
            if (o.file_path == file) throw SceneError(e.what());
            fail(file, o.place + ".file", e.what());
        }
    }
    d.objects = std::move(objects);
    check_smooth(d, meshes, file);
    return meshes;
}

// ================================ stage 4: build ========================================

// The untransformed faces of an object, their vertex normals (empty unless smooth) and the
// pivot its transform acts about.
std::vector<Polygon> shape_faces(const ObjectDesc& o, const ImportedMesh& mesh, Vec3& pivot,
                                 VertexNormals& normals) {
    pivot = Vec3(0.0);
    normals.clear();
    const bool smooth = o.smooth.value_or(true);  // polygon and box have none to give
    if (o.type == "polygon") return {o.vertices};
    if (o.type == "box") {
        pivot = 0.5 * (o.box_min + o.box_max);
        return make_box(o.box_min, o.box_max);
    }
    if (o.type == "sphere") {
        pivot = o.center;
        std::vector<Polygon> out = make_icosphere(o.center, o.radius, o.subdivisions);
        if (smooth) normals = sphere_normals(out, o.center);
        return out;
    }
    if (o.type == "cylinder") {
        pivot = o.cylinder.base_center + Vec3(0, 0.5 * o.cylinder.height, 0);
        std::vector<Polygon> out = make_cylinder(o.cylinder);
        if (smooth) normals = cylinder_normals(out, o.cylinder);
        return out;
    }
    std::vector<Polygon> out;  // mesh
    out.reserve(mesh.faces.size());
    const bool with_normals = smooth && mesh.normals.size() == mesh.vertices.size();
    if (with_normals) normals.resize(mesh.faces.size());
    for (size_t k = 0; k < mesh.faces.size(); ++k) {
        Polygon p;
        p.reserve(mesh.faces[k].size());
        for (int vi : mesh.faces[k]) {
            p.push_back(mesh.vertices[static_cast<size_t>(vi)]);
            if (with_normals) normals[k].push_back(mesh.normals[static_cast<size_t>(vi)]);
        }
        out.push_back(std::move(p));
    }
    return out;
}

// Where a face problem is reported, e.g. "objects[2].vertices: polygon is not planar ..." or
// "objects[4] (mesh meshes/x.obj): face 17 is not planar ...".
[[noreturn]] void face_error(const std::string& file, const ObjectDesc& o, size_t face,
                             const std::string& problem) {
    // problem reads "polygon is ..." / "polygon has ..."
    const std::string rest = problem.rfind("polygon ", 0) == 0 ? problem.substr(8) : problem;
    // Non-planar and degenerate faces are what triangulation repairs.
    const bool repairable = !o.triangulate && (o.type == "polygon" || o.type == "mesh") &&
                            problem.find("crosses itself") == std::string::npos;
    const std::string hint = repairable ? " (\"triangulate\": true repairs it)" : "";
    if (o.type == "polygon") fail(file, o.place + ".vertices", problem + hint);
    const std::string what =
        o.file.empty() ? o.type
                       : fmt::format("{} {}", o.type == "mesh" ? "mesh" : "import", o.file);
    fail(file, fmt::format("{} ({})", o.place, what),
         fmt::format("face {} {}{}", face, rest, hint));
}

// Every object's shape in user units, transformed; `diameter` is the diagonal of their
// bounding box.
std::vector<std::vector<Polygon>> transformed_shapes(const SceneDescription& d,
                                                     const std::vector<ImportedMesh>& meshes,
                                                     double& diameter, const std::string& file,
                                                     std::vector<VertexNormals>& normals) {
    std::vector<std::vector<Polygon>> raw(d.objects.size());
    normals.assign(d.objects.size(), {});
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < d.objects.size(); ++i) {
        const ObjectDesc& o = d.objects[i];
        Vec3 pivot;
        raw[i] = shape_faces(o, meshes[i], pivot, normals[i]);
        const Transform xf(o, pivot);
        for (std::vector<Vec3>& face : normals[i])
            for (Vec3& n : face) n = xf.normal(n);
        for (size_t k = 0; k < raw[i].size(); ++k)
            for (size_t j = 0; j < raw[i][k].size(); ++j) {
                Vec3& x = raw[i][k][j];
                x = xf(x);
                // Far-out points would make every other face degenerate at the scene's
                // relative tolerance: name the point instead.
                if (!(std::max({std::abs(x.x), std::abs(x.y), std::abs(x.z)}) <= kMaxCoordinate)) {
                    const std::string at =
                        o.type == "polygon"
                            ? fmt::format("{}.vertices[{}]", o.place, j)
                            : fmt::format("{} ({}): face {} vertex {}", o.place, o.type, k, j);
                    fail(file, at,
                         fmt::format("lies at [{:.3g}, {:.3g}, {:.3g}], beyond +-{:.0e} scene "
                                     "units (after the object's transform)",
                                     x.x, x.y, x.z, kMaxCoordinate));
                }
                lo = glm::min(lo, x), hi = glm::max(hi, x);
            }
    }
    diameter = glm::length(hi - lo);
    return raw;
}

// An object's checked convex planar faces (triangulated when asked), oriented, doubled
// when two-sided.
// An object's faces as they enter the scene, with their texture coordinates (per face and
// vertex; empty when the object has none).
struct ObjectFaces {
    std::vector<Polygon> polygons;
    std::vector<std::vector<Vec2>> uvs;
    // Unit vertex normals per face (Face::vertex_normals; an empty list: flat), or empty
    // when the object is flat throughout.
    VertexNormals normals;
};

// The vertex normals of triangle `t`, cut from polygon `p` with normals `pn` (triangulation
// keeps the polygon's vertices): empty when `p` has none.
std::vector<Vec3> triangle_normals(const Polygon& p, const std::vector<Vec3>& pn,
                                   const Polygon& t) {
    std::vector<Vec3> n;
    if (pn.size() != p.size()) return n;
    for (const Vec3& x : t) {
        const auto at = std::find(p.begin(), p.end(), x);
        if (at == p.end()) return {};
        n.push_back(pn[size_t(at - p.begin())]);
    }
    return n;
}

// Keeps a face's vertex normals only when every one is finite, non-zero and on the front
// side of the face (made unit); returns false when they were dropped.
bool keep_front_normals(const Polygon& p, std::vector<Vec3>& normals) {
    if (normals.empty()) return true;
    const Vec3 front = newell_vector(p);
    for (Vec3& n : normals) {
        const double len = glm::length(n);
        if (!(len > 0) || !std::isfinite(len) || !(glm::dot(n, front) > 0)) {
            normals.clear();
            return false;
        }
        n /= len;
    }
    return true;
}

// The texture coordinates of triangle `t`, cut from polygon `k` of `mesh` (triangulation
// keeps the polygon's vertices): empty when a vertex has none.
std::vector<Vec2> triangle_uvs(const ImportedMesh& mesh, size_t k, const Polygon& p,
                               const Polygon& t) {
    std::vector<Vec2> uv;
    for (const Vec3& x : t) {
        const auto at = std::find(p.begin(), p.end(), x);
        if (at == p.end()) return {};
        const Vec2 u = mesh.uvs[size_t(mesh.faces[k][size_t(at - p.begin())])];
        if (!std::isfinite(u.x) || !std::isfinite(u.y)) return {};
        uv.push_back(u);
    }
    return uv;
}

// `twins`: every face gets a reversed twin (a two-sided object, or glass).
// `raw_normals`: the faces' vertex normals (VertexNormals; empty when flat).
ObjectFaces checked_faces(const ObjectDesc& o, const std::vector<Polygon>& raw,
                          const VertexNormals& raw_normals, const ImportedMesh& mesh, double tol,
                          const std::string& file, std::vector<std::string>& notes, bool twins) {
    ObjectFaces result;
    std::vector<Polygon>& out = result.polygons;
    const bool smooth = !raw_normals.empty();
    const bool textured = !mesh.uvs.empty();
    // Imports are repaired, never refused for a face: what changed is counted.
    const bool imported = o.type == "import";
    size_t crossing = 0, degenerate = 0, non_planar = 0, duplicate = 0;
    // An imported face that repeats another of the object (the same vertices in the same
    // cyclic order: the same side) is a modelling defect that would z-fight; it is dropped.
    std::set<std::vector<std::array<double, 3>>> seen;
    auto repeats = [&](const Polygon& t) {
        std::vector<std::array<double, 3>> key;
        for (const Vec3& x : t) key.push_back({x.x, x.y, x.z});
        std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
        return !seen.insert(std::move(key)).second;
    };
    for (size_t k = 0; k < raw.size(); ++k) {
        const Polygon& p = raw[k];
        if (o.triangulate) {
            auto tris = triangulate_polygon(p, tol, tol);
            if (!tris && !imported)
                face_error(file, o, k,
                           "polygon cannot be triangulated (its outline crosses itself)");
            if (!tris) {
                ++crossing;
                continue;
            }
            if (imported && p.size() > 3)
                if (const auto problem = polygon_problem(p, tol, tol);
                    problem && problem->find("not planar") != std::string::npos)
                    ++non_planar;
            degenerate += p.size() - 2 - tris->size();
            for (Polygon& t : *tris) {
                if (imported && repeats(t)) {
                    ++duplicate;
                    continue;
                }
                if (textured) result.uvs.push_back(triangle_uvs(mesh, k, p, t));
                if (smooth) result.normals.push_back(triangle_normals(p, raw_normals[k], t));
                out.push_back(std::move(t));
            }
        } else {
            if (auto problem = polygon_problem(p, tol, tol)) {
                // Sizes are relative to the whole scene: say so, or a far-away vertex of
                // another object is hard to find.
                if (problem->find("degenerate") != std::string::npos)
                    *problem += fmt::format(
                        " (lengths below {:.3g}, 1e-6 of the scene's bounding-box diagonal, are "
                        "zero)",
                        tol);
                face_error(file, o, k, *problem);
            }
            if (smooth) result.normals.push_back(raw_normals[k]);
            out.push_back(p);
        }
    }
    std::string changed;
    auto count = [&](size_t n, const char* what) {
        if (n) changed += fmt::format("{}{} {}", changed.empty() ? "" : ", ", n, what);
    };
    count(crossing, "self-crossing face(s) dropped");
    count(degenerate, "zero-area triangle(s) dropped");
    count(non_planar, "non-planar face(s) split into triangles");
    count(duplicate, "repeated triangle(s) dropped (the same vertices as another face)");
    if (!changed.empty())
        notes.push_back(fmt::format("{}: {} ({}): {}", file, o.place, o.name, changed));
    std::vector<std::vector<Vec2>>& uvs = result.uvs;
    VertexNormals& normals = result.normals;
    if (o.flip) {
        for (Polygon& p : out) std::reverse(p.begin(), p.end());
        for (auto& uv : uvs) std::reverse(uv.begin(), uv.end());
        for (auto& vn : normals) {  // the front turns: so do the normals
            std::reverse(vn.begin(), vn.end());
            for (Vec3& n : vn) n = -n;
        }
    }
    size_t backward = 0;  // faces whose normals do not all point to their front
    for (size_t k = 0; k < normals.size(); ++k) backward += !keep_front_normals(out[k], normals[k]);
    if (backward)
        notes.push_back(fmt::format(
            "{}: {} ({}): {} of {} face(s) kept flat: a vertex normal is zero, not finite or "
            "points to the back of the face",
            file, o.place, o.name, backward, normals.size()));
    if (o.two_sided || twins) {
        const size_t n = out.size();
        for (size_t k = 0; k < n; ++k) out.emplace_back(out[k].rbegin(), out[k].rend());
        for (size_t k = 0; k < uvs.size() && k < n; ++k)
            uvs.emplace_back(uvs[k].rbegin(), uvs[k].rend());
        for (size_t k = 0; k < normals.size() && k < n; ++k) {  // reversed, to the twin's front
            normals.emplace_back(normals[k].rbegin(), normals[k].rend());
            for (Vec3& v : normals.back()) v = -v;
        }
    }
    return result;
}

// The bounds of the faces and the normalisation into the unit ball; returns the half
// diagonal of the bounds (user units).
double normalise(Scene& scene, const std::vector<ObjectFaces>& faces, const std::string& file) {
    Vec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
    size_t face_total = 0;
    for (const auto& fs : faces)
        for (const Polygon& p : fs.polygons) {
            ++face_total;
            for (const Vec3& x : p) lo = glm::min(lo, x), hi = glm::max(hi, x);
        }
    if (face_total == 0) fail(file, "objects", "the objects produce no faces");
    scene.user_bounds_min = lo;
    scene.user_bounds_max = hi;
    const double half_diagonal = 0.5 * glm::length(hi - lo);
    scene.normalisation.center = 0.5 * (lo + hi);
    scene.normalisation.scale = kNormalisedRadius / half_diagonal;
    scene.faces.reserve(face_total);
    return half_diagonal;
}

// The objects and their faces in normalised coordinates, with planes, areas and twins.
void add_objects(Scene& scene, const SceneDescription& d, const std::vector<ObjectFaces>& faces) {
    for (size_t i = 0; i < d.objects.size(); ++i) {
        const ObjectDesc& o = d.objects[i];
        SceneObject so;
        so.name = o.name;
        so.type = o.type;
        so.first_face = static_cast<int>(scene.faces.size());
        so.face_count = static_cast<int>(faces[i].polygons.size());
        scene.objects.push_back(so);
        for (size_t k = 0; k < faces[i].polygons.size(); ++k) {
            const Polygon& p = faces[i].polygons[k];
            Face f;
            if (k < faces[i].uvs.size()) f.uv = faces[i].uvs[k];
            if (k < faces[i].normals.size()) f.vertex_normals = faces[i].normals[k];
            f.id = static_cast<int>(scene.faces.size());
            f.object = static_cast<int>(i);
            f.material = o.material;
            f.vertices.reserve(p.size());
            for (const Vec3& x : p) f.vertices.push_back(scene.normalisation.to_normalised(x));
            const Vec3 nv = newell_vector(f.vertices);
            const double len = glm::length(nv);
            VLF_CHECK(len > 0);
            f.normal = nv / len;
            f.area = 0.5 * len;
            f.plane_offset = glm::dot(f.normal, polygon_centroid(f.vertices));
            scene.faces.push_back(std::move(f));
        }
        const bool glass = d.materials[size_t(o.material)].dielectric;
        if (o.two_sided || glass) {  // the second half of the object's faces reverses the first
            const int half = so.face_count / 2;
            for (int k = 0; k < half; ++k) {
                scene.faces[so.first_face + k].twin = so.first_face + half + k;
                scene.faces[so.first_face + half + k].twin = so.first_face + k;
                scene.faces[so.first_face + half + k].inner = glass;
            }
        }
    }
}

Scene build(SceneDescription& d, const std::vector<ImportedMesh>& meshes, const std::string& file,
            const LoadOptions& options) {
    Scene scene;
    scene.source = file;
    scene.units = d.units;
    scene.materials = d.materials;
    scene.cameras = d.cameras;
    scene.lights = d.lights;
    scene.load_notes = d.notes;
    scene.textures = d.textures;

    double diameter = 0;
    std::vector<VertexNormals> raw_normals;
    const std::vector<std::vector<Polygon>> raw =
        transformed_shapes(d, meshes, diameter, file, raw_normals);
    if (!(diameter > 0) || !std::isfinite(diameter))
        fail(file, "objects", "the scene's geometry has no extent");
    const double tol = kRelativeTolerance * diameter;
    std::vector<ObjectFaces> faces(d.objects.size());
    for (size_t i = 0; i < d.objects.size(); ++i) {
        ObjectDesc& o = d.objects[i];
        const bool glass = d.materials[size_t(o.material)].dielectric;
        faces[i] =
            checked_faces(o, raw[i], raw_normals[i], meshes[i], tol, file, scene.load_notes, glass);
        if (!glass) continue;
        // Its outer faces are the first half (the second are their inner twins).
        const std::vector<Polygon> outer(
            faces[i].polygons.begin(),
            faces[i].polygons.begin() + std::ptrdiff_t(faces[i].polygons.size() / 2));
        const auto why = open_edge(outer, tol);
        if (!why) continue;
        if (!o.glass_fallback)
            fail(file, fmt::format("{} ({})", o.place, o.name),
                 "a dielectric object must be closed, its faces turned outward: " + *why);
        // A model file's glass that came apart where faces were dropped or turned: the
        // file's other material, as for glass that is open in the file (scene_import.cpp).
        scene.load_notes.push_back(
            fmt::format("{}: not made glass after all: its faces are not closed once repaired: {}",
                        o.glass_source, *why));
        o.material = static_cast<int>(d.materials.size());
        d.materials.push_back(*o.glass_fallback);
        scene.materials.push_back(*o.glass_fallback);
        std::vector<std::string> again;  // (the repairs were noted the first time)
        faces[i] = checked_faces(o, raw[i], raw_normals[i], meshes[i], tol, file, again, false);
    }

    const double half_diagonal = normalise(scene, faces, file);
    add_objects(scene, d, faces);
    const bool lights_emit = std::any_of(scene.lights.begin(), scene.lights.end(),
                                         [](const Light& l) { return l.emits(); });
    if (scene.emitter_count() == 0 && !lights_emit)
        fail(file, "objects",
             std::any_of(d.objects.begin(), d.objects.end(),
                         [](const ObjectDesc& o) { return o.type == "import"; })
                 ? "no emitter: no face uses a material with emission > 0 (an imported file "
                   "emits through its materials' Ke or emissive colour; else place it with "
                   "{\"type\": \"import\", \"file\": ...} in a JSON scene that has a lamp, "
                   "docs/scenes.md)"
                 : "no emitter: no face uses a material with emission > 0");

    // Texel size: the caller's, else the file's, else the bounding-sphere radius / 32.
    if (options.texel_size_user > 0)
        scene.texel_size_user = options.texel_size_user;
    else if (d.texel_size)
        scene.texel_size_user = *d.texel_size;
    else
        scene.texel_size_user = half_diagonal / options.texel_divisions;
    const double texel = scene.texel_size_user * scene.normalisation.scale;
    const int cap = options.max_texels_per_side;
    // Faces that another face runs right across are cut along the contact line, so that no
    // texel straddles it (imprint.hpp): faces of at least 4 texels.
    const ImprintResult cut =
        imprint_contacts(scene, 4.0 * texel * texel, tol * scene.normalisation.scale);
    if (cut.cut_faces > 0)
        scene.load_notes.push_back(fmt::format(
            "{} face(s) cut into {} along the lines where other faces run across them, so "
            "that no texel straddles a contact line (docs/charts.md \"Contact lines\")",
            cut.cut_faces, cut.pieces));
    build_charts(scene, texel, cap, options.chart_angle_deg);
    scene.seal_gap = texel;
    subtract_sealed_areas(scene, scene.seal_gap);
    compute_texel_albedo(scene);
    return scene;
}

void check_options(const LoadOptions& options) {
    if (!std::isfinite(options.texel_size_user))
        throw ParameterError(
            fmt::format("texel size must be finite (got {})", options.texel_size_user));
    if (options.texel_divisions < 1)
        throw ParameterError(
            fmt::format("texel divisions must be >= 1 (got {})", options.texel_divisions));
    if (options.max_texels_per_side < 1)
        throw ParameterError(
            fmt::format("max texels per side must be >= 1 (got {})", options.max_texels_per_side));
    if (!(options.chart_angle_deg >= 0.0 && options.chart_angle_deg < 90.0))
        throw ParameterError(fmt::format("chart angle must be in [0, 90) degrees (got {})",
                                         options.chart_angle_deg));
}

}  // namespace

namespace {

// The stages after parsing. The JSON reader throws vlf::Error; a scene's are SceneErrors.
Scene load_tree(const Json& root, const std::string& name, const std::string& base_dir,
                const LoadOptions& options) {
    SceneDescription desc;
    try {
        desc = validate(root, name, base_dir);
    } catch (const SceneError&) {
        throw;
    } catch (const Error& e) {
        throw SceneError(e.what());
    }
    const std::vector<ImportedMesh> meshes = load_resources(desc, name);
    return build(desc, meshes, name, options);
}

template <class Parse>
Json parse_scene(Parse&& parse) {
    try {
        return parse();
    } catch (const SceneError&) {
        throw;
    } catch (const Error& e) {
        throw SceneError(e.what());
    }
}

}  // namespace

Scene load_scene_from_string(const std::string& json_text, const std::string& name,
                             const std::string& base_dir, const LoadOptions& options) {
    check_options(options);
    const Json root = parse_scene([&] { return parse_json<Json>(json_text, name); });
    return load_tree(root, name, base_dir, options);
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
    check_options(options);
    if (lower_extension(path) != ".json" && is_importable_scene_file(path)) {
        // A model file on its own: one import object, its materials and cameras as they are.
        const std::filesystem::path p(path);
        const Json root = {{"materials", Json::object()},
                           {"objects", Json::array({{{"type", "import"},
                                                     {"name", p.stem().string()},
                                                     {"file", p.filename().string()}}})}};
        return load_tree(root, path, p.parent_path().string(), options);
    }
    const Json root = parse_scene([&] { return read_json_file<Json>(path); });
    const std::string base_dir = std::filesystem::path(path).parent_path().string();
    return load_tree(root, path, base_dir, options);
}

}  // namespace vlf
