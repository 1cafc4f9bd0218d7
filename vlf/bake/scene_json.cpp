// scene_json.cpp — Scene <-> the bundle's scene.json (scene_json.hpp).
#include "vlf/bake/scene_json.hpp"

#include <fmt/format.h>

#include "vlf/core/json_reader.hpp"

namespace vlf {

using nlohmann::json;

json vec_json(const Vec3& v) {
    return json::array({v.x, v.y, v.z});
}

json scene_to_json(const Scene& scene) {
    json materials = json::array();
    for (const Material& m : scene.materials)
        materials.push_back({{"name", m.name},
                             {"diffuse", vec_json(m.diffuse)},
                             {"specular", vec_json(m.specular)},
                             {"emission", vec_json(m.emission)},
                             {"diffuse_texture", m.diffuse_texture},
                             {"transmission", m.transmission},
                             {"dielectric", m.dielectric},
                             {"ior", m.ior},
                             {"absorption", vec_json(m.absorption)}});
    json objects = json::array();
    for (const SceneObject& o : scene.objects)
        objects.push_back({{"name", o.name},
                           {"type", o.type},
                           {"first_face", o.first_face},
                           {"face_count", o.face_count}});

    json cameras = json::array();
    for (const Camera& c : scene.cameras)
        cameras.push_back({{"name", c.name},
                           {"eye", vec_json(c.eye)},
                           {"look_at", vec_json(c.look_at)},
                           {"up", vec_json(c.up)},
                           {"fov_y_deg", c.fov_y_deg}});
    json lights = json::array();
    for (const Light& l : scene.lights)
        lights.push_back({{"name", l.name},
                          {"type", light_type_name(l.type)},
                          {"position", vec_json(l.position)},
                          {"direction", vec_json(l.direction)},
                          {"intensity", vec_json(l.intensity)},
                          {"cos_inner", l.cos_inner},
                          {"cos_outer", l.cos_outer},
                          {"irradiance", vec_json(l.irradiance)},
                          {"angular_diameter_deg", l.angular_diameter_deg}});
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
        {"cameras", cameras},
        {"lights", lights}};
}

// ---------------------------------------------------------------------------------------

namespace {

Material read_material(const JsonReader& r) {
    r.only_keys({"name", "diffuse", "specular", "emission", "diffuse_texture", "transmission",
                 "dielectric", "ior", "absorption"});
    Material m;
    m.name = r.required("name").string();
    m.diffuse = r.required("diffuse").vec3();
    m.specular = r.required("specular").vec3();
    m.emission = r.required("emission").vec3();
    m.diffuse_texture = r.required("diffuse_texture").integer(-1);
    m.transmission = r.required("transmission").number();
    m.ior = r.required("ior").number();
    m.dielectric = r.required("dielectric").boolean();
    m.absorption = r.required("absorption").vec3();
    if (!(m.transmission >= 0.0 && m.transmission <= 1.0))
        r.required("transmission").fail("must be in [0, 1]");
    if (!(m.ior >= 1.0)) r.required("ior").fail("must be >= 1");
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

Light read_light(const JsonReader& r) {
    r.only_keys({"name", "type", "position", "direction", "intensity", "cos_inner", "cos_outer",
                 "irradiance", "angular_diameter_deg"});
    Light l;
    l.name = r.required("name").string();
    const size_t t = r.required("type").one_of({"point", "spot", "directional"}, "light type");
    l.type = t == 0 ? LightType::Point : t == 1 ? LightType::Spot : LightType::Directional;
    l.position = r.required("position").vec3();
    l.direction = r.required("direction").vec3();
    l.intensity = r.required("intensity").vec3();
    l.cos_inner = r.required("cos_inner").number(-1, 1);
    l.cos_outer = r.required("cos_outer").number(-1, 1);
    l.irradiance = r.required("irradiance").vec3();
    l.angular_diameter_deg = r.required("angular_diameter_deg").number(0, 30);
    return l;
}

}  // namespace

Scene scene_from_json(const json& j, const std::string& file) {
    const JsonReader r(j, file);
    r.only_keys({"units", "normalisation", "user_bounds_min", "user_bounds_max", "texel_size_user",
                 "materials", "objects", "cameras", "lights"});
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
    for (const JsonReader& c : r.required("cameras").elements())
        s.cameras.push_back(read_camera(c));
    // (Bakes of format 5 written before lights existed have none.)
    if (const auto lights = r.optional("lights"))
        for (const JsonReader& l : lights->elements()) s.lights.push_back(read_light(l));
    return s;
}

}  // namespace vlf
