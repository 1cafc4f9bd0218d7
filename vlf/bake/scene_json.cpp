// scene_json.cpp — Scene <-> the bundle's scene.json (scene_json.hpp).
#include "vlf/bake/scene_json.hpp"

#include <fmt/format.h>

#include "vlf/core/json_reader.hpp"

namespace vlf {

using nlohmann::json;

namespace {

constexpr int kMaxTexelsPerSide = 65536;

json vec_json(const Vec3& v) {
    return json::array({v.x, v.y, v.z});
}

json face_json(const Face& f) {
    json verts = json::array();
    for (const Vec3& v : f.vertices) verts.push_back(vec_json(v));
    json j = {{"id", f.id},
              {"object", f.object},
              {"material", f.material},
              {"chart", f.chart},
              {"vertices", verts},
              {"normal", vec_json(f.normal)},
              {"plane_offset", f.plane_offset},
              {"area", f.area}};
    if (f.twin >= 0) j["twin"] = f.twin;  // two-sided: the reverse face
    if (f.inner_edges != 0) {
        json inner = json::array();
        for (int e = 0; e < 64; ++e)
            if (f.inner_edges >> e & 1u) inner.push_back(e);
        j["inner_edges"] = inner;
    }
    return j;
}

json chart_json(const Chart& c) {
    const TexelFrame& t = c.texels;
    return {{"id", c.id},
            {"material", c.material},
            {"normal", vec_json(c.normal)},
            {"area", c.area},
            {"planar", c.planar},
            {"faces", c.faces},
            {"texels",
             {{"origin", vec_json(t.origin)},
              {"axis_u", vec_json(t.axis_u)},
              {"axis_v", vec_json(t.axis_v)},
              {"size", t.size},
              {"width", t.width},
              {"height", t.height}}},
            {"texel_area", c.texel_area}};
}

}  // namespace

json scene_to_json(const Scene& scene) {
    json materials = json::array();
    for (const Material& m : scene.materials)
        materials.push_back({{"name", m.name},
                             {"diffuse", vec_json(m.diffuse)},
                             {"specular", vec_json(m.specular)},
                             {"emission", vec_json(m.emission)}});
    json objects = json::array();
    for (const SceneObject& o : scene.objects)
        objects.push_back({{"name", o.name},
                           {"type", o.type},
                           {"first_face", o.first_face},
                           {"face_count", o.face_count}});
    json faces = json::array();
    for (const Face& f : scene.faces) faces.push_back(face_json(f));
    json charts = json::array();
    for (const Chart& c : scene.charts) charts.push_back(chart_json(c));
    json cameras = json::array();
    for (const Camera& c : scene.cameras)
        cameras.push_back({{"name", c.name},
                           {"eye", vec_json(c.eye)},
                           {"look_at", vec_json(c.look_at)},
                           {"up", vec_json(c.up)},
                           {"fov_y_deg", c.fov_y_deg}});
    // nlohmann writes doubles with the shortest text that round-trips exactly.
    return {
        {"units", scene.units},
        {"normalisation",
         {{"center", vec_json(scene.normalisation.center)}, {"scale", scene.normalisation.scale}}},
        {"user_bounds_min", vec_json(scene.user_bounds_min)},
        {"user_bounds_max", vec_json(scene.user_bounds_max)},
        {"texel_size_user", scene.texel_size_user},
        {"materials", materials},
        {"objects", objects},
        {"faces", faces},
        {"charts", charts},
        {"cameras", cameras}};
}

// ---------------------------------------------------------------------------------------

namespace {

Material read_material(const JsonReader& r) {
    r.only_keys({"name", "diffuse", "specular", "emission"});
    Material m;
    m.name = r.required("name").string();
    m.diffuse = r.required("diffuse").vec3();
    m.specular = r.required("specular").vec3();
    m.emission = r.required("emission").vec3();
    return m;
}

SceneObject read_object(const JsonReader& r) {
    r.only_keys({"name", "type", "first_face", "face_count"});
    SceneObject o;
    o.name = r.required("name").string();
    o.type = r.required("type").string();
    o.first_face = r.required("first_face").integer(0);
    o.face_count = r.required("face_count").integer(0);
    return o;
}

TexelFrame read_texels(const JsonReader& r) {
    r.only_keys({"origin", "axis_u", "axis_v", "size", "width", "height"});
    TexelFrame t;
    t.origin = r.required("origin").vec3();
    t.axis_u = r.required("axis_u").vec3();
    t.axis_v = r.required("axis_v").vec3();
    t.size = r.required("size").positive();
    t.width = r.required("width").integer(1, kMaxTexelsPerSide);
    t.height = r.required("height").integer(1, kMaxTexelsPerSide);
    return t;
}

Face read_face(const JsonReader& r, size_t index, size_t face_count, const Scene& s) {
    r.only_keys({"id", "object", "material", "chart", "vertices", "normal", "plane_offset", "area",
                 "twin", "inner_edges"});
    Face f;
    const JsonReader id = r.required("id");
    f.id = id.integer(0);
    if (f.id != static_cast<int>(index)) id.fail(fmt::format("id {} is not its index", f.id));
    f.object = r.required("object").integer(0, static_cast<int>(s.objects.size()) - 1);
    f.material = r.required("material").integer(0, static_cast<int>(s.materials.size()) - 1);
    if (const auto twin = r.optional("twin"))
        f.twin = twin->integer(0, static_cast<int>(face_count) - 1);
    for (const JsonReader& v : r.required("vertices").elements(3)) f.vertices.push_back(v.vec3());
    f.normal = r.required("normal").vec3();
    f.plane_offset = r.required("plane_offset").number();
    f.area = r.required("area").number();
    f.chart = r.required("chart").integer(0);
    if (const auto inner = r.optional("inner_edges")) {
        const int last = static_cast<int>(std::min<size_t>(f.vertices.size(), 64)) - 1;
        for (const JsonReader& e : inner->elements()) f.inner_edges |= uint64_t(1) << e.integer(0, last);
    }
    return f;
}

Chart read_chart(const JsonReader& r, size_t index, const Scene& s) {
    r.only_keys({"id", "material", "normal", "area", "planar", "faces", "texels", "texel_area"});
    Chart c;
    const JsonReader id = r.required("id");
    c.id = id.integer(0);
    if (c.id != static_cast<int>(index)) id.fail(fmt::format("id {} is not its index", c.id));
    c.material = r.required("material").integer(0, static_cast<int>(s.materials.size()) - 1);
    c.normal = r.required("normal").vec3();
    c.area = r.required("area").number();
    c.planar = r.required("planar").boolean();
    const int last = static_cast<int>(s.faces.size()) - 1;
    for (const JsonReader& f : r.required("faces").elements(1)) {
        c.faces.push_back(f.integer(0, last));
        if (s.faces[c.faces.back()].chart != c.id)
            f.fail(fmt::format("face {} names chart {}", c.faces.back(),
                               s.faces[c.faces.back()].chart));
    }
    c.texels = read_texels(r.required("texels"));
    const JsonReader area = r.required("texel_area");
    c.texel_area = area.numbers();
    if (c.texel_area.size() != size_t(c.texels.width) * size_t(c.texels.height))
        area.fail(fmt::format("{} entries for a {}x{} texel grid", c.texel_area.size(),
                              c.texels.width, c.texels.height));
    return c;
}

Camera read_camera(const JsonReader& r) {
    r.only_keys({"name", "eye", "look_at", "up", "fov_y_deg"});
    Camera c;
    c.name = r.required("name").string();
    c.eye = r.required("eye").vec3();
    c.look_at = r.required("look_at").vec3();
    c.up = r.required("up").vec3();
    c.fov_y_deg = r.required("fov_y_deg").number();
    return c;
}

}  // namespace

Scene scene_from_json(const json& j, const std::string& file) {
    const JsonReader r(j, file);
    r.only_keys({"units", "normalisation", "user_bounds_min", "user_bounds_max", "texel_size_user",
                 "materials", "objects", "faces", "charts", "cameras"});
    Scene s;
    s.source = file;
    s.units = r.required("units").string();
    const JsonReader norm = r.required("normalisation");
    norm.only_keys({"center", "scale"});
    s.normalisation.center = norm.required("center").vec3();
    s.normalisation.scale = norm.required("scale").positive();
    s.user_bounds_min = r.required("user_bounds_min").vec3();
    s.user_bounds_max = r.required("user_bounds_max").vec3();
    s.texel_size_user = r.required("texel_size_user").number();
    for (const JsonReader& m : r.required("materials").elements())
        s.materials.push_back(read_material(m));
    const std::vector<JsonReader> objects = r.required("objects").elements();
    for (const JsonReader& o : objects) s.objects.push_back(read_object(o));
    const std::vector<JsonReader> faces = r.required("faces").elements(1);
    for (size_t k = 0; k < faces.size(); ++k)
        s.faces.push_back(read_face(faces[k], k, faces.size(), s));
    for (const Face& f : s.faces)
        if (f.twin >= 0 && (f.twin == f.id || s.faces[f.twin].twin != f.id))
            faces[size_t(f.id)].required("twin").fail(
                fmt::format("face {} does not name face {} as its twin", f.twin, f.id));
    const std::vector<JsonReader> charts = r.required("charts").elements(1);
    for (size_t k = 0; k < charts.size(); ++k) s.charts.push_back(read_chart(charts[k], k, s));
    size_t in_charts = 0;
    for (const Chart& c : s.charts) in_charts += c.faces.size();
    for (const Face& f : s.faces)
        if (f.chart >= static_cast<int>(s.charts.size()))
            faces[size_t(f.id)].required("chart").fail(
                fmt::format("chart {} is out of range (the scene has {})", f.chart, s.charts.size()));
    if (in_charts != s.faces.size())
        r.required("charts").fail(
            fmt::format("{} faces in charts for {} faces", in_charts, s.faces.size()));
    for (size_t k = 0; k < s.objects.size(); ++k) {
        const SceneObject& o = s.objects[k];
        if (size_t(o.first_face) + size_t(o.face_count) > s.faces.size())
            objects[k].fail(fmt::format("faces {} to {} are out of range (the scene has {})",
                                        o.first_face, o.first_face + o.face_count - 1,
                                        s.faces.size()));
    }
    for (const JsonReader& c : r.required("cameras").elements())
        s.cameras.push_back(read_camera(c));
    return s;
}

}  // namespace vlf
