// scene_loader.cpp — JSON scene files to a Scene (DESIGN §3), in four stages:
//
//   parse     text -> JSON tree; syntax errors name line and column, numbers that overflow
//             a double (1e999) name their JSON place, duplicate keys are errors;
//   validate  JSON tree -> SceneDescription: every key known, every type and range checked,
//             materials resolved; nothing is read from disk yet;
//   load      mesh files -> ImportedMesh (OpenMesh readers);
//   build     shapes -> transformed polygons (user units) -> checked convex planar faces
//             -> normalisation into the unit ball -> texel frames.
//
// Keys (anything else is an error; "?" = optional, with its default):
//   top level   materials {name: material}, objects [object, ...] (non-empty),
//               cameras? [camera, ...], settings? {texel_size? (> 0, user units), units? (string)}
//   material    diffuse? [r,g,b] = 0, specular? [r,g,b] = 0 (each in [0,1], diffuse+specular <= 1
//               per channel), emission? [r,g,b] = 0 (>= 0, W m^-2 sr^-1)
//   object      type (polygon|box|sphere|cylinder|mesh), material, name? = "<type>#<index>",
//               two_sided? = false, flip? = false, scale? = 1 (number or [sx,sy,sz], > 0),
//               rotate_x_deg? / rotate_y_deg? / rotate_z_deg? = 0, translate? = [0,0,0]
//               applied as: scale, rotate x, y, z (about the pivot), translate. Pivot: box
//               centre, sphere centre, cylinder axis midpoint; the origin for polygon and mesh.
//     polygon   vertices [[x,y,z] x >= 3] (counter-clockwise seen from the front), triangulate? =
//     false box       min, max (max > min per axis) sphere    center? = [0,0,0], radius (> 0),
//     subdivisions? = 2 (integer 0..6) cylinder  radius (> 0), height (> 0), inner_radius? = 0 (0
//     <= inner < radius),
//               center? = [0,0,0] (base centre; axis +y), segments? = 32 (3..4096), caps? = true
//     mesh      file (.obj .ply .off .stl, relative to the scene file's directory), triangulate? =
//     false
//   camera      name? = "camera#<index>", eye, look_at (!= eye), up? = [0,1,0] (not parallel to
//               the view direction), fov_y_deg (0 < fov < 180); user units
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
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "vlf/core/error.hpp"
#include "vlf/scene/mesh_import.hpp"
#include "vlf/scene/primitives.hpp"
#include "vlf/scene/sealed_areas.hpp"
#include "vlf/scene/texel_frame.hpp"

namespace vlf {

namespace {

using Json = nlohmann::ordered_json;  // keeps file order: materials are indexed as written

constexpr double kRelativeTolerance = 1e-6;
constexpr double kNormalisedRadius = 0.999;  // geometry strictly inside the unit ball

[[noreturn]] void fail(const std::string& file, const std::string& place, const std::string& what) {
    throw SceneError(fmt::format("{}: {}: {}", file, place, what));
}

// ================================ stage 1: parse ========================================

// A SAX handler that builds the tree itself so it always knows the JSON place of the
// value being read: nlohmann's DOM parser reports a number overflow (1e999) without one.
class TreeBuilder {
  public:
    using number_integer_t = Json::number_integer_t;
    using number_unsigned_t = Json::number_unsigned_t;
    using number_float_t = Json::number_float_t;
    using string_t = Json::string_t;
    using binary_t = Json::binary_t;

    TreeBuilder(const std::string& file, const std::string& text) : m_file(file), m_text(text) {}

    Json& root() { return m_root; }

    bool null() { return add(Json(nullptr)); }
    bool boolean(bool v) { return add(Json(v)); }
    bool number_integer(number_integer_t v) { return add(Json(v)); }
    bool number_unsigned(number_unsigned_t v) { return add(Json(v)); }
    bool number_float(number_float_t v, const string_t& s) {
        if (!std::isfinite(v))
            fail(m_file, next_place(), fmt::format("number '{}' is not finite", s));
        return add(Json(v));
    }
    bool string(string_t& v) { return add(Json(v)); }
    bool binary(binary_t&) { return add(Json(nullptr)); }  // not produced by the JSON reader
    bool start_object(std::size_t) {
        Json* j = add_container(Json::object());
        m_stack.push_back({j, false, {}, -1, {}});
        return true;
    }
    bool key(string_t& k) {
        Frame& f = m_stack.back();
        if (!f.keys.insert(k).second) fail(m_file, join(place_of_stack(), k), "duplicate key");
        f.key = k;
        return true;
    }
    bool end_object() {
        m_stack.pop_back();
        return true;
    }
    bool start_array(std::size_t) {
        Json* j = add_container(Json::array());
        m_stack.push_back({j, true, {}, -1, {}});
        return true;
    }
    bool end_array() {
        m_stack.pop_back();
        return true;
    }
    bool parse_error(std::size_t position, const std::string& /*last_token*/,
                     const nlohmann::detail::exception& ex) {
        if (ex.id == 406)  // out_of_range: number overflow, e.g. 1e999
            fail(m_file, next_place(), fmt::format("number is not finite (it overflows a double)"));
        // Line and column of the offending character, from nlohmann's byte count.
        const std::size_t at = position == 0 ? 0 : std::min(position - 1, m_text.size());
        std::size_t line = 1, line_start = 0;
        for (std::size_t i = 0; i < at; ++i)
            if (m_text[i] == '\n') ++line, line_start = i + 1;
        const std::size_t column = at - line_start + 1;
        std::string what = ex.what();
        // "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..."
        if (auto p = what.find("parse error"); p != std::string::npos)
            if (auto q = what.find(": ", p); q != std::string::npos) what = what.substr(q + 2);
        fail(m_file, fmt::format("line {}, column {}", line, column), "malformed JSON: " + what);
    }

  private:
    struct Frame {
        Json* value;
        bool is_array;
        std::string key;
        long index;
        std::set<std::string> keys;
    };

    static std::string join(const std::string& parent, const std::string& key) {
        return parent.empty() ? key : parent + "." + key;
    }
    // Place of the container on top of the stack.
    std::string place_of_stack() const {
        std::string p;
        for (size_t i = 0; i + 1 < m_stack.size(); ++i) {
            const Frame& f = m_stack[i];
            p = f.is_array ? p + fmt::format("[{}]", f.index) : join(p, f.key);
        }
        return p;
    }
    // Place of the value about to be added to the top container.
    std::string next_place() const {
        if (m_stack.empty()) return "(top level)";
        const Frame& f = m_stack.back();
        const std::string parent = place_of_stack();
        return f.is_array ? parent + fmt::format("[{}]", f.index + 1) : join(parent, f.key);
    }
    bool add(Json v) {
        if (m_stack.empty()) {
            m_root = std::move(v);
        } else if (Frame& f = m_stack.back(); f.is_array) {
            ++f.index;
            f.value->push_back(std::move(v));
        } else {
            (*f.value)[f.key] = std::move(v);
        }
        return true;
    }
    Json* add_container(Json v) {
        if (m_stack.empty()) {
            m_root = std::move(v);
            return &m_root;
        }
        Frame& f = m_stack.back();
        if (f.is_array) {
            ++f.index;
            f.value->push_back(std::move(v));
            return &f.value->back();
        }
        (*f.value)[f.key] = std::move(v);
        return &(*f.value)[f.key];
    }

    const std::string& m_file;
    const std::string& m_text;
    Json m_root;
    // Pointers into the tree stay valid: only the innermost open container ever grows.
    std::vector<Frame> m_stack;
};

Json parse_json(const std::string& text, const std::string& file) {
    TreeBuilder builder(file, text);
    const bool ok = Json::sax_parse(text, &builder);
    if (!ok) fail(file, "(top level)", "malformed JSON");
    return std::move(builder.root());
}

// =============================== stage 2: validate ======================================

struct ObjectDesc {
    std::string place;  // "objects[3]"
    std::string name;
    std::string type;
    int material = 0;
    bool two_sided = false, flip = false, triangulate = false;
    Vec3 scale{1.0}, rotate_deg{0.0}, translate{0.0};
    std::vector<Vec3> vertices;  // polygon
    Vec3 box_min{0.0}, box_max{0.0};
    Vec3 center{0.0};  // sphere
    double radius = 0;
    int subdivisions = 2;
    CylinderShape cylinder;
    std::string file, file_path;  // mesh: as written, resolved against the scene directory
};

struct SceneDescription {
    std::vector<Material> materials;
    std::vector<ObjectDesc> objects;
    std::vector<Camera> cameras;
    std::optional<double> texel_size;
    std::string units;
};

// Typed, place-naming accessors over the JSON tree.
class Validator {
  public:
    explicit Validator(const std::string& file) : m_file(file) {}

    [[noreturn]] void error(const std::string& place, const std::string& what) const {
        fail(m_file, place, what);
    }

    static std::string key_place(const std::string& parent, const std::string& key) {
        return parent.empty() ? key : parent + "." + key;
    }

    void expect_object(const Json& j, const std::string& place) const {
        if (!j.is_object()) error(place, fmt::format("expected an object, got {}", describe(j)));
    }

    void check_keys(const Json& obj, const std::string& place,
                    const std::vector<std::string>& allowed,
                    const std::string& context = "") const {
        for (const auto& [k, v] : obj.items()) {
            if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            error(key_place(place, k),
                  fmt::format("unknown key{} (expected one of: {})", context, list));
        }
    }

    const Json& required(const Json& obj, const std::string& place, const std::string& key) const {
        auto it = obj.find(key);
        if (it == obj.end()) error(place, fmt::format("missing required key '{}'", key));
        return *it;
    }

    static const Json* optional(const Json& obj, const std::string& key) {
        auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }

    double number(const Json& j, const std::string& place) const {
        if (!j.is_number()) error(place, fmt::format("expected a number, got {}", describe(j)));
        const double v = j.get<double>();
        if (!std::isfinite(v)) error(place, "number is not finite");
        return v;
    }

    double positive(const Json& j, const std::string& place) const {
        const double v = number(j, place);
        if (!(v > 0)) error(place, fmt::format("must be > 0 (got {})", v));
        return v;
    }

    int integer(const Json& j, const std::string& place, int lo, int hi) const {
        const double v = number(j, place);
        if (v != std::floor(v)) error(place, fmt::format("expected an integer, got {}", v));
        if (v < lo || v > hi) error(place, fmt::format("must be in [{}, {}] (got {})", lo, hi, v));
        return static_cast<int>(v);
    }

    bool boolean(const Json& j, const std::string& place) const {
        if (!j.is_boolean())
            error(place, fmt::format("expected true or false, got {}", describe(j)));
        return j.get<bool>();
    }

    std::string string(const Json& j, const std::string& place) const {
        if (!j.is_string()) error(place, fmt::format("expected a string, got {}", describe(j)));
        return j.get<std::string>();
    }

    Vec3 vec3(const Json& j, const std::string& place) const {
        if (!j.is_array())
            error(place, fmt::format("expected an array of 3 numbers, got {}", describe(j)));
        if (j.size() != 3)
            error(place, fmt::format("expected an array of 3 numbers, got {} element{}", j.size(),
                                     j.size() == 1 ? "" : "s"));
        Vec3 v;
        for (int i = 0; i < 3; ++i) v[i] = number(j[i], fmt::format("{}[{}]", place, i));
        return v;
    }

    Vec3 positive_vec3(const Json& j, const std::string& place) const {
        Vec3 v = vec3(j, place);
        for (int i = 0; i < 3; ++i)
            if (!(v[i] > 0))
                error(fmt::format("{}[{}]", place, i), fmt::format("must be > 0 (got {})", v[i]));
        return v;
    }

    static std::string describe(const Json& j) {
        if (j.is_array()) return "an array";
        if (j.is_object()) return "an object";
        if (j.is_string()) return fmt::format("a string ('{}')", j.get<std::string>());
        if (j.is_boolean()) return j.get<bool>() ? "true" : "false";
        if (j.is_null()) return "null";
        if (j.is_number()) return fmt::format("the number {}", j.get<double>());
        return j.type_name();
    }

  private:
    const std::string& m_file;
};

Material validate_material(const Validator& v, const std::string& name, const Json& j) {
    const std::string place = "materials." + name;
    v.expect_object(j, place);
    v.check_keys(j, place, {"diffuse", "specular", "emission"});
    Material m;
    m.name = name;
    auto rgb = [&](const char* key, double upper) {
        Rgb c(0.0);
        const Json* e = Validator::optional(j, key);
        if (!e) return c;
        const std::string p = place + "." + key;
        c = v.vec3(*e, p);
        for (int i = 0; i < 3; ++i) {
            const std::string pi = fmt::format("{}[{}]", p, i);
            if (c[i] < 0) v.error(pi, fmt::format("must be >= 0 (got {})", c[i]));
            if (c[i] > upper) v.error(pi, fmt::format("reflectance must be <= 1 (got {})", c[i]));
        }
        return c;
    };
    const double inf = std::numeric_limits<double>::infinity();
    m.diffuse = rgb("diffuse", 1.0);
    m.specular = rgb("specular", 1.0);
    m.emission = rgb("emission", inf);
    for (int i = 0; i < 3; ++i)
        if (m.diffuse[i] + m.specular[i] > 1.0)
            v.error(place,
                    fmt::format("diffuse + specular = {} > 1 in channel {} (reflectance must not "
                                "exceed 1)",
                                m.diffuse[i] + m.specular[i], i));
    return m;
}

void validate_transform(const Validator& v, const Json& j, const std::string& place,
                        ObjectDesc& o) {
    if (const Json* s = Validator::optional(j, "scale")) {
        const std::string p = place + ".scale";
        if (s->is_number())
            o.scale = Vec3(v.positive(*s, p));
        else if (s->is_array())
            o.scale = v.positive_vec3(*s, p);
        else
            v.error(p, fmt::format("expected a number or an array of 3 numbers, got {}",
                                   Validator::describe(*s)));
    }
    const char* rot[3] = {"rotate_x_deg", "rotate_y_deg", "rotate_z_deg"};
    for (int a = 0; a < 3; ++a)
        if (const Json* r = Validator::optional(j, rot[a]))
            o.rotate_deg[a] = v.number(*r, place + "." + rot[a]);
    if (const Json* t = Validator::optional(j, "translate"))
        o.translate = v.vec3(*t, place + ".translate");
}

ObjectDesc validate_object(const Validator& v, const Json& j, int index,
                           const std::vector<Material>& materials, const std::string& base_dir) {
    ObjectDesc o;
    o.place = fmt::format("objects[{}]", index);
    const std::string& place = o.place;
    auto at = [&](const char* key) { return place + "." + key; };
    v.expect_object(j, place);

    o.type = v.string(v.required(j, place, "type"), at("type"));
    const std::vector<std::string> common = {
        "type",  "material",     "name",         "two_sided",    "flip",
        "scale", "rotate_x_deg", "rotate_y_deg", "rotate_z_deg", "translate"};
    std::vector<std::string> specific;
    if (o.type == "polygon")
        specific = {"vertices", "triangulate"};
    else if (o.type == "box")
        specific = {"min", "max"};
    else if (o.type == "sphere")
        specific = {"center", "radius", "subdivisions"};
    else if (o.type == "cylinder")
        specific = {"radius", "inner_radius", "height", "center", "segments", "caps"};
    else if (o.type == "mesh")
        specific = {"file", "triangulate"};
    else
        v.error(at("type"),
                fmt::format("unknown type '{}' (expected polygon, box, sphere, cylinder or mesh)",
                            o.type));
    std::vector<std::string> allowed = common;
    allowed.insert(allowed.end(), specific.begin(), specific.end());
    v.check_keys(j, place, allowed, " for a " + o.type);

    const std::string mat = v.string(v.required(j, place, "material"), at("material"));
    auto it = std::find_if(materials.begin(), materials.end(),
                           [&](const Material& m) { return m.name == mat; });
    if (it == materials.end()) v.error(at("material"), fmt::format("unknown material '{}'", mat));
    o.material = static_cast<int>(it - materials.begin());

    o.name = fmt::format("{}#{}", o.type, index);
    if (const Json* n = Validator::optional(j, "name")) o.name = v.string(*n, at("name"));
    if (const Json* b = Validator::optional(j, "two_sided"))
        o.two_sided = v.boolean(*b, at("two_sided"));
    if (const Json* b = Validator::optional(j, "flip")) o.flip = v.boolean(*b, at("flip"));
    if (const Json* b = Validator::optional(j, "triangulate"))
        o.triangulate = v.boolean(*b, at("triangulate"));
    validate_transform(v, j, place, o);

    if (o.type == "polygon") {
        const Json& vs = v.required(j, place, "vertices");
        if (!vs.is_array())
            v.error(at("vertices"),
                    fmt::format("expected an array of points, got {}", Validator::describe(vs)));
        if (vs.size() < 3)
            v.error(at("vertices"),
                    fmt::format("a polygon needs at least 3 vertices (got {})", vs.size()));
        for (size_t i = 0; i < vs.size(); ++i)
            o.vertices.push_back(v.vec3(vs[i], fmt::format("{}[{}]", at("vertices"), i)));
    } else if (o.type == "box") {
        o.box_min = v.vec3(v.required(j, place, "min"), at("min"));
        o.box_max = v.vec3(v.required(j, place, "max"), at("max"));
        for (int a = 0; a < 3; ++a)
            if (!(o.box_max[a] > o.box_min[a]))
                v.error(fmt::format("{}[{}]", at("max"), a),
                        fmt::format("must be greater than min[{}] ({} <= {})", a, o.box_max[a],
                                    o.box_min[a]));
    } else if (o.type == "sphere") {
        if (const Json* c = Validator::optional(j, "center")) o.center = v.vec3(*c, at("center"));
        o.radius = v.positive(v.required(j, place, "radius"), at("radius"));
        if (const Json* s = Validator::optional(j, "subdivisions"))
            o.subdivisions = v.integer(*s, at("subdivisions"), 0, 6);
    } else if (o.type == "cylinder") {
        CylinderShape& c = o.cylinder;
        c.radius = v.positive(v.required(j, place, "radius"), at("radius"));
        c.height = v.positive(v.required(j, place, "height"), at("height"));
        if (const Json* r = Validator::optional(j, "inner_radius")) {
            c.inner_radius = v.number(*r, at("inner_radius"));
            if (!(c.inner_radius >= 0 && c.inner_radius < c.radius))
                v.error(at("inner_radius"), fmt::format("must be >= 0 and < radius {} (got {})",
                                                        c.radius, c.inner_radius));
        }
        if (const Json* b = Validator::optional(j, "center"))
            c.base_center = v.vec3(*b, at("center"));
        if (const Json* s = Validator::optional(j, "segments"))
            c.segments = v.integer(*s, at("segments"), 3, 4096);
        if (const Json* b = Validator::optional(j, "caps")) c.caps = v.boolean(*b, at("caps"));
    } else if (o.type == "mesh") {
        o.file = v.string(v.required(j, place, "file"), at("file"));
        if (o.file.empty()) v.error(at("file"), "empty file name");
        std::filesystem::path p(o.file);
        o.file_path = (p.is_absolute() || base_dir.empty())
                          ? p.string()
                          : (std::filesystem::path(base_dir) / p).string();
        if (!is_supported_mesh_file(o.file))
            v.error(at("file"),
                    fmt::format("'{}': unsupported mesh format (use .obj, .ply, .off or .stl)",
                                o.file));
    }
    return o;
}

Camera validate_camera(const Validator& v, const Json& j, int index) {
    const std::string place = fmt::format("cameras[{}]", index);
    auto at = [&](const char* key) { return place + "." + key; };
    v.expect_object(j, place);
    v.check_keys(j, place, {"name", "eye", "look_at", "up", "fov_y_deg"});
    Camera c;
    c.name = fmt::format("camera#{}", index);
    if (const Json* n = Validator::optional(j, "name")) c.name = v.string(*n, at("name"));
    c.eye = v.vec3(v.required(j, place, "eye"), at("eye"));
    c.look_at = v.vec3(v.required(j, place, "look_at"), at("look_at"));
    if (const Json* u = Validator::optional(j, "up")) c.up = v.vec3(*u, at("up"));
    c.fov_y_deg = v.number(v.required(j, place, "fov_y_deg"), at("fov_y_deg"));
    if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180))
        v.error(at("fov_y_deg"), fmt::format("must be in (0, 180) degrees (got {})", c.fov_y_deg));
    const Vec3 d = c.look_at - c.eye;
    if (!(glm::length(d) > 0)) v.error(at("look_at"), "equals eye (no view direction)");
    if (!(glm::length(c.up) > 0)) v.error(at("up"), "is the zero vector");
    const double s = glm::length(glm::cross(glm::normalize(d), glm::normalize(c.up)));
    if (!(s > 1e-6)) v.error(at("up"), "is parallel to the view direction (look_at - eye)");
    return c;
}

SceneDescription validate(const Json& root, const std::string& file, const std::string& base_dir) {
    Validator v(file);
    SceneDescription d;
    v.expect_object(root, "(top level)");
    v.check_keys(root, "", {"materials", "objects", "cameras", "settings"});

    const Json& mats = v.required(root, "(top level)", "materials");
    v.expect_object(mats, "materials");
    for (const auto& [name, m] : mats.items()) {
        if (name.empty()) v.error("materials", "empty material name");
        d.materials.push_back(validate_material(v, name, m));
    }

    const Json& objs = v.required(root, "(top level)", "objects");
    if (!objs.is_array())
        v.error("objects", fmt::format("expected an array, got {}", Validator::describe(objs)));
    if (objs.empty()) v.error("objects", "the scene has no objects");
    for (size_t i = 0; i < objs.size(); ++i)
        d.objects.push_back(
            validate_object(v, objs[i], static_cast<int>(i), d.materials, base_dir));

    if (const Json* cams = Validator::optional(root, "cameras")) {
        if (!cams->is_array())
            v.error("cameras",
                    fmt::format("expected an array, got {}", Validator::describe(*cams)));
        std::set<std::string> names;
        for (size_t i = 0; i < cams->size(); ++i) {
            d.cameras.push_back(validate_camera(v, (*cams)[i], static_cast<int>(i)));
            if (!names.insert(d.cameras.back().name).second)
                v.error(fmt::format("cameras[{}].name", i),
                        fmt::format("duplicate camera name '{}'", d.cameras.back().name));
        }
    }

    if (const Json* s = Validator::optional(root, "settings")) {
        v.expect_object(*s, "settings");
        v.check_keys(*s, "settings", {"texel_size", "units"});
        if (const Json* t = Validator::optional(*s, "texel_size"))
            d.texel_size = v.positive(*t, "settings.texel_size");
        if (const Json* u = Validator::optional(*s, "units"))
            d.units = v.string(*u, "settings.units");
    }

    const bool any_emitter =
        std::any_of(d.objects.begin(), d.objects.end(),
                    [&](const ObjectDesc& o) { return d.materials[o.material].is_emitter(); });
    if (!any_emitter) v.error("objects", "no emitter: no object uses a material with emission > 0");
    return d;
}

// ================================ stage 3: load =========================================

std::vector<ImportedMesh> load_resources(const SceneDescription& d, const std::string& file) {
    std::vector<ImportedMesh> meshes(d.objects.size());
    for (size_t i = 0; i < d.objects.size(); ++i) {
        const ObjectDesc& o = d.objects[i];
        if (o.type != "mesh") continue;
        try {
            meshes[i] = import_mesh(o.file_path);
        } catch (const Error& e) {
            fail(file, o.place + ".file", e.what());
        }
    }
    return meshes;
}

// ================================ stage 4: build ========================================

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
};

// The untransformed faces of an object and the pivot its transform acts about.
std::vector<Polygon> shape_faces(const ObjectDesc& o, const ImportedMesh& mesh, Vec3& pivot) {
    pivot = Vec3(0.0);
    if (o.type == "polygon") return {o.vertices};
    if (o.type == "box") {
        pivot = 0.5 * (o.box_min + o.box_max);
        return make_box(o.box_min, o.box_max);
    }
    if (o.type == "sphere") {
        pivot = o.center;
        return make_icosphere(o.center, o.radius, o.subdivisions);
    }
    if (o.type == "cylinder") {
        pivot = o.cylinder.base_center + Vec3(0, 0.5 * o.cylinder.height, 0);
        return make_cylinder(o.cylinder);
    }
    std::vector<Polygon> out;  // mesh
    out.reserve(mesh.faces.size());
    for (const auto& f : mesh.faces) {
        Polygon p;
        p.reserve(f.size());
        for (int vi : f) p.push_back(mesh.vertices[static_cast<size_t>(vi)]);
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
    if (o.type == "polygon") fail(file, o.place + ".vertices", problem);
    const std::string what = o.type == "mesh" ? fmt::format("mesh {}", o.file) : o.type;
    fail(file, fmt::format("{} ({})", o.place, what), fmt::format("face {} {}", face, rest));
}

Scene build(const SceneDescription& d, const std::vector<ImportedMesh>& meshes,
            const std::string& file, const LoadOptions& options) {
    Scene scene;
    scene.source = file;
    scene.units = d.units;
    scene.materials = d.materials;
    scene.cameras = d.cameras;

    // Shapes in user units, transformed.
    std::vector<std::vector<Polygon>> raw(d.objects.size());
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < d.objects.size(); ++i) {
        Vec3 pivot;
        raw[i] = shape_faces(d.objects[i], meshes[i], pivot);
        const Transform xf(d.objects[i], pivot);
        for (Polygon& p : raw[i])
            for (Vec3& x : p) {
                x = xf(x);
                lo = glm::min(lo, x), hi = glm::max(hi, x);
            }
    }
    const double diameter = glm::length(hi - lo);
    if (!(diameter > 0) || !std::isfinite(diameter))
        fail(file, "objects", "the scene's geometry has no extent");
    const double tol = kRelativeTolerance * diameter;

    // Checked convex planar faces per object, oriented, doubled when two-sided.
    std::vector<std::vector<Polygon>> faces(d.objects.size());
    for (size_t i = 0; i < d.objects.size(); ++i) {
        const ObjectDesc& o = d.objects[i];
        std::vector<Polygon>& out = faces[i];
        for (size_t k = 0; k < raw[i].size(); ++k) {
            const Polygon& p = raw[i][k];
            if (o.triangulate) {
                auto tris = triangulate_polygon(p, tol, tol);
                if (!tris)
                    face_error(file, o, k,
                               "polygon cannot be triangulated (its outline crosses itself)");
                out.insert(out.end(), tris->begin(), tris->end());
            } else {
                if (auto problem = polygon_problem(p, tol, tol)) face_error(file, o, k, *problem);
                out.push_back(p);
            }
        }
        if (o.flip)
            for (Polygon& p : out) std::reverse(p.begin(), p.end());
        if (o.two_sided) {
            const size_t n = out.size();
            for (size_t k = 0; k < n; ++k) out.emplace_back(out[k].rbegin(), out[k].rend());
        }
    }

    // Bounds of what is left, and the normalisation into the unit ball.
    lo = Vec3(std::numeric_limits<double>::infinity()), hi = -lo;
    size_t face_total = 0;
    for (const auto& fs : faces)
        for (const Polygon& p : fs) {
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
    for (size_t i = 0; i < d.objects.size(); ++i) {
        const ObjectDesc& o = d.objects[i];
        SceneObject so;
        so.name = o.name;
        so.type = o.type;
        so.first_face = static_cast<int>(scene.faces.size());
        so.face_count = static_cast<int>(faces[i].size());
        scene.objects.push_back(so);
        for (const Polygon& p : faces[i]) {
            Face f;
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
        if (o.two_sided) {  // the second half of the object's faces reverses the first
            const int half = so.face_count / 2;
            for (int k = 0; k < half; ++k) {
                scene.faces[so.first_face + k].twin = so.first_face + half + k;
                scene.faces[so.first_face + half + k].twin = so.first_face + k;
            }
        }
    }
    if (scene.emitter_count() == 0)
        fail(file, "objects", "no emitter: no face uses a material with emission > 0");

    // Texel size: the caller's, else the file's, else the bounding-sphere radius / 32.
    if (options.texel_size_user > 0)
        scene.texel_size_user = options.texel_size_user;
    else if (d.texel_size)
        scene.texel_size_user = *d.texel_size;
    else
        scene.texel_size_user = half_diagonal / options.texel_divisions;
    const double texel = scene.texel_size_user * scene.normalisation.scale;
    const int cap = options.max_texels_per_side;
    tbb::parallel_for(size_t(0), scene.faces.size(),
                      [&](size_t k) { build_texel_frame(scene.faces[k], texel, cap); });
    scene.seal_gap = texel;
    subtract_sealed_areas(scene, scene.seal_gap);
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
}

}  // namespace

Scene load_scene_from_string(const std::string& json_text, const std::string& name,
                             const std::string& base_dir, const LoadOptions& options) {
    check_options(options);
    const Json root = parse_json(json_text, name);
    const SceneDescription desc = validate(root, name, base_dir);
    const std::vector<ImportedMesh> meshes = load_resources(desc, name);
    return build(desc, meshes, name, options);
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(fmt::format("{}: (file): cannot open the scene file", path));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw SceneError(fmt::format("{}: (file): cannot read the scene file", path));
    const std::string base_dir = std::filesystem::path(path).parent_path().string();
    return load_scene_from_string(text.str(), path, base_dir, options);
}

}  // namespace vlf
