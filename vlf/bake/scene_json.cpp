// scene_json.cpp — Scene <-> the bundle's scene.json (scene_json.hpp).
#include "vlf/bake/scene_json.hpp"

#include <fmt/format.h>

#include <cmath>

#include "vlf/core/error.hpp"

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
    const TexelFrame& t = f.texels;
    return {{"id", f.id},
            {"object", f.object},
            {"material", f.material},
            {"vertices", verts},
            {"normal", vec_json(f.normal)},
            {"plane_offset", f.plane_offset},
            {"area", f.area},
            {"texels",
             {{"origin", vec_json(t.origin)},
              {"axis_u", vec_json(t.axis_u)},
              {"axis_v", vec_json(t.axis_v)},
              {"size", t.size},
              {"width", t.width},
              {"height", t.height}}},
            {"texel_area", f.texel_area}};
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
        {"cameras", cameras}};
}

// ---------------------------------------------------------------------------------------

namespace {

Vec3 vec_from(const json& j) {
    if (!j.is_array() || j.size() != 3) throw Error("expected an array of 3 numbers");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

Material read_material(const json& m) {
    Material mat;
    mat.name = m.at("name").get<std::string>();
    mat.diffuse = vec_from(m.at("diffuse"));
    mat.specular = vec_from(m.at("specular"));
    mat.emission = vec_from(m.at("emission"));
    return mat;
}

SceneObject read_object(const json& o) {
    SceneObject obj;
    obj.name = o.at("name").get<std::string>();
    obj.type = o.at("type").get<std::string>();
    obj.first_face = o.at("first_face").get<int>();
    obj.face_count = o.at("face_count").get<int>();
    return obj;
}

Face read_face(const json& fj, size_t k, const Scene& s) {
    const int nm = static_cast<int>(s.materials.size()), no = static_cast<int>(s.objects.size());
    Face f;
    f.id = fj.at("id").get<int>();
    if (f.id != static_cast<int>(k)) throw Error(fmt::format("id {} is not its index", f.id));
    f.object = fj.at("object").get<int>();
    f.material = fj.at("material").get<int>();
    if (f.object < 0 || f.object >= no) throw Error("object index out of range");
    if (f.material < 0 || f.material >= nm) throw Error("material index out of range");
    for (const json& v : fj.at("vertices")) f.vertices.push_back(vec_from(v));
    if (f.vertices.size() < 3) throw Error("fewer than 3 vertices");
    f.normal = vec_from(fj.at("normal"));
    f.plane_offset = fj.at("plane_offset").get<double>();
    f.area = fj.at("area").get<double>();
    const json& t = fj.at("texels");
    f.texels.origin = vec_from(t.at("origin"));
    f.texels.axis_u = vec_from(t.at("axis_u"));
    f.texels.axis_v = vec_from(t.at("axis_v"));
    f.texels.size = t.at("size").get<double>();
    f.texels.width = t.at("width").get<int>();
    f.texels.height = t.at("height").get<int>();
    if (f.texels.width < 1 || f.texels.height < 1 || f.texels.width > kMaxTexelsPerSide ||
        f.texels.height > kMaxTexelsPerSide || !(f.texels.size > 0))
        throw Error("invalid texel grid");
    f.texel_area = fj.at("texel_area").get<std::vector<double>>();
    if (f.texel_area.size() != size_t(f.texels.width) * size_t(f.texels.height))
        throw Error(fmt::format("texel_area has {} entries for a {}x{} grid", f.texel_area.size(),
                                f.texels.width, f.texels.height));
    return f;
}

Camera read_camera(const json& c) {
    Camera cam;
    cam.name = c.at("name").get<std::string>();
    cam.eye = vec_from(c.at("eye"));
    cam.look_at = vec_from(c.at("look_at"));
    cam.up = vec_from(c.at("up"));
    cam.fov_y_deg = c.at("fov_y_deg").get<double>();
    return cam;
}

// Everything but the faces, objects and cameras; `where` names the JSON place being read.
void read_frame(const json& j, Scene& s, std::string& where) {
    where = "units";
    s.units = j.at("units").get<std::string>();
    where = "normalisation";
    s.normalisation.center = vec_from(j.at("normalisation").at("center"));
    s.normalisation.scale = j.at("normalisation").at("scale").get<double>();
    if (!(s.normalisation.scale > 0) || !std::isfinite(s.normalisation.scale))
        throw Error("scale must be positive");
    where = "user_bounds";
    s.user_bounds_min = vec_from(j.at("user_bounds_min"));
    s.user_bounds_max = vec_from(j.at("user_bounds_max"));
    where = "texel_size_user";
    s.texel_size_user = j.at("texel_size_user").get<double>();
}

}  // namespace

Scene scene_from_json(const json& j, const std::string& name) {
    Scene s;
    s.source = name;
    std::string where;  // the JSON place being read, for messages
    try {
        read_frame(j, s, where);
        const json& mats = j.at("materials");
        for (size_t k = 0; k < mats.size(); ++k) {
            where = fmt::format("materials[{}]", k);
            s.materials.push_back(read_material(mats.at(k)));
        }
        const json& objs = j.at("objects");
        for (size_t k = 0; k < objs.size(); ++k) {
            where = fmt::format("objects[{}]", k);
            s.objects.push_back(read_object(objs.at(k)));
        }
        const json& faces = j.at("faces");
        for (size_t k = 0; k < faces.size(); ++k) {
            where = fmt::format("faces[{}]", k);
            s.faces.push_back(read_face(faces.at(k), k, s));
        }
        for (size_t k = 0; k < s.objects.size(); ++k) {
            const SceneObject& o = s.objects[k];
            where = fmt::format("objects[{}]", k);
            if (o.first_face < 0 || o.face_count < 0 ||
                size_t(o.first_face) + size_t(o.face_count) > s.faces.size())
                throw Error("face range out of range");
        }
        const json& cams = j.at("cameras");
        for (size_t k = 0; k < cams.size(); ++k) {
            where = fmt::format("cameras[{}]", k);
            s.cameras.push_back(read_camera(cams.at(k)));
        }
        where.clear();
        if (s.faces.empty()) throw Error("no faces");
    } catch (const json::exception& e) {
        throw Error(fmt::format("{}: {}{}{}", name, where, where.empty() ? "" : ": ", e.what()));
    } catch (const Error& e) {
        throw Error(fmt::format("{}: {}{}{}", name, where, where.empty() ? "" : ": ", e.what()));
    }
    return s;
}

}  // namespace vlf
