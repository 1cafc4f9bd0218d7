#include "vlf/scene/raycaster.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

const char* error_name(RTCError e) {
    switch (e) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_UNKNOWN:
            return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
    }
    return "unrecognised error";
}

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

struct RayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<int> face_of;  // primID -> face id
    // What a hit reads of each face, packed (a Face is 152 bytes; a scene of many small
    // faces does not fit the cache as Faces).
    struct HitFace {
        Vec3 normal;
        double plane_offset;
        int twin;
    };
    std::vector<HitFace> faces;  // per face id
    std::mutex error_mutex;
    std::string error;  // first message reported by Embree's error callback

    static void on_error(void* user, RTCError code, const char* str) {
        auto* self = static_cast<Impl*>(user);
        std::lock_guard<std::mutex> lock(self->error_mutex);
        if (self->error.empty())
            self->error = fmt::format("{}: {}", error_name(code), str ? str : "");
    }

    // Throws when the device has an error pending (after a build step).
    void check(const char* what) {
        const RTCError e = rtcGetDeviceError(device);
        std::lock_guard<std::mutex> lock(error_mutex);
        if (e == RTC_ERROR_NONE && error.empty()) return;
        const std::string msg = !error.empty() ? error : error_name(e);
        throw Error(fmt::format("ray caster: Embree {} failed: {}", what, msg));
    }

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RayCaster::RayCaster(const Scene& scene, int without_object)
    : m_scene(scene), m_impl(std::make_unique<Impl>()) {
    Impl& im = *m_impl;
    im.device = rtcNewDevice(nullptr);
    if (!im.device)
        throw Error(fmt::format("ray caster: cannot create the Embree device: {}",
                                error_name(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(im.device, &Impl::on_error, &im);
    // A library built with back-face culling would drop hits on the back of faces; the
    // queries are two-sided, so then every triangle is also added with reversed winding.
    const bool culling =
        rtcGetDeviceProperty(im.device, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED) != 0;

    // Fan triangulation of the convex faces (vertices as Embree wants them: float3).
    std::vector<float> vertices;
    std::vector<unsigned> indices;
    for (const Face& f : scene.faces) {
        if (f.vertices.size() < 3) continue;  // degenerate: nothing to hit
        if (f.object == without_object) continue;
        // A two-sided surface goes in once: a hit on it is reported as the side facing the
        // ray (intersect), on the same plane, so its twin would only double the work.
        if (f.twin >= 0 && f.twin < f.id) continue;
        for (size_t k = 0; k < f.vertices.size(); ++k)
            if (!finite(f.vertices[k]))
                throw Error(
                    fmt::format("{}: face {}: vertex {} is not finite", scene.source, f.id, k));
        const unsigned base = static_cast<unsigned>(vertices.size() / 3);
        for (const Vec3& v : f.vertices) {
            vertices.push_back(static_cast<float>(v.x));
            vertices.push_back(static_cast<float>(v.y));
            vertices.push_back(static_cast<float>(v.z));
        }
        for (size_t k = 1; k + 1 < f.vertices.size(); ++k) {
            const unsigned a = base, b = base + unsigned(k), c = base + unsigned(k + 1);
            indices.insert(indices.end(), {a, b, c});
            im.face_of.push_back(f.id);
            if (culling) {
                indices.insert(indices.end(), {a, c, b});
                im.face_of.push_back(f.id);
            }
        }
    }
    m_triangles = static_cast<int>(im.face_of.size());
    im.faces.reserve(scene.faces.size());
    for (const Face& f : scene.faces) im.faces.push_back({f.normal, f.plane_offset, f.twin});

    im.scene = rtcNewScene(im.device);
    im.check("scene creation");
    if (!im.scene) throw Error("ray caster: Embree returned no scene");
    // Robust traversal: no ray slips through the shared edges of a fan or of a mesh.
    // intersect_past drops hits by a context filter (Debian's library has them).
    if (rtcGetDeviceProperty(im.device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) == 0)
        throw Error("ray caster: this Embree library was built without filter functions");
    rtcSetSceneFlags(im.scene,
                     RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);
    if (m_triangles > 0) {
        RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        im.check("geometry creation");
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               vertices.size() / 3));
        auto* ib = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(unsigned), indices.size() / 3));
        if (!vb || !ib) {
            rtcReleaseGeometry(geom);
            im.check("buffer allocation");
            throw Error("ray caster: Embree could not allocate the geometry buffers");
        }
        std::copy(vertices.begin(), vertices.end(), vb);
        std::copy(indices.begin(), indices.end(), ib);
        rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(im.scene, geom, 0);
        rtcReleaseGeometry(geom);  // the scene holds it
        im.check("geometry commit");
    }
    rtcCommitScene(im.scene);
    im.check("scene build");
}

RayCaster::~RayCaster() = default;

namespace {

void fill_ray(RTCRay& r, const Vec3& o, const Vec3& d, double tmin, double tmax) {
    r.org_x = static_cast<float>(o.x);
    r.org_y = static_cast<float>(o.y);
    r.org_z = static_cast<float>(o.z);
    r.dir_x = static_cast<float>(d.x);
    r.dir_y = static_cast<float>(d.y);
    r.dir_z = static_cast<float>(d.z);
    r.tnear = static_cast<float>(std::max(0.0, tmin));
    r.tfar = tmax >= double(std::numeric_limits<float>::max())
                 ? std::numeric_limits<float>::infinity()
                 : static_cast<float>(tmax);
    r.time = 0.0f;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}

bool valid_query(const Vec3& o, const Vec3& d, double tmin, double tmax) {
    return finite(o) && finite(d) && glm::dot(d, d) > 0.0 && !(tmax < tmin) && !std::isnan(tmin) &&
           !std::isnan(tmax);
}

// An intersection context that drops the hits on two faces (intersect_past).
struct SkipContext {
    RTCIntersectContext ctx;  // first: Embree hands the filter a pointer to it
    const int* face_of;
    int a, b;
};

void skip_faces(const RTCFilterFunctionNArguments* args) {
    const auto* c = reinterpret_cast<const SkipContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const int f = c->face_of[RTCHitN_primID(args->hit, args->N, i)];
        if (f == c->a || f == c->b) args->valid[i] = 0;
    }
}

}  // namespace

bool RayCaster::intersect(const Vec3& origin, const Vec3& dir, double tmin, double tmax,
                          RayHit& hit) const {
    return intersect_past(-1, origin, dir, tmin, tmax, hit);
}

bool RayCaster::intersect_past(int skip, const Vec3& origin, const Vec3& dir, double tmin,
                               double tmax, RayHit& hit) const {
    hit = RayHit{};
    if (m_triangles == 0 || !valid_query(origin, dir, tmin, tmax)) return false;
    SkipContext sc;  // per call: queries share nothing mutable
    RTCIntersectContext& ctx = sc.ctx;
    rtcInitIntersectContext(&ctx);
    if (skip >= 0) {
        sc.face_of = m_impl->face_of.data();
        sc.a = skip;
        sc.b = m_impl->faces[size_t(skip)].twin;
        ctx.filter = &skip_faces;
    }
    RTCRayHit rh;
    fill_ray(rh.ray, origin, dir, tmin, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    const std::vector<Impl::HitFace>& faces = m_impl->faces;
    hit.face = m_impl->face_of[rh.hit.primID];
    // A two-sided surface is a face and its reversed twin on one polygon; which of the two
    // Embree reports is arbitrary. The side a ray meets is the one facing it.
    if (const int twin = faces[size_t(hit.face)].twin;
        twin >= 0 && glm::dot(faces[size_t(hit.face)].normal, dir) > 0.0)
        hit.face = twin;
    // Refine t in double precision on the face's plane (Embree's float t is good to about
    // 1e-7 of the ray length; the plane gives the exact point on the face).
    const Impl::HitFace& f = faces[size_t(hit.face)];
    const double nd = glm::dot(f.normal, dir);
    double t = static_cast<double>(rh.ray.tfar);
    if (std::abs(nd) > 1e-9 * glm::length(dir)) {
        const double tp = (f.plane_offset - glm::dot(f.normal, origin)) / nd;
        // Keep Embree's value when the plane disagrees grossly (a degenerate face).
        if (std::isfinite(tp) && std::abs(tp - t) <= 1e-4 * (1.0 + std::abs(t))) t = tp;
    }
    hit.t = t;
    hit.point = origin + t * dir;
    return true;
}

bool RayCaster::occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const {
    if (m_triangles == 0 || !valid_query(origin, dir, tmin, tmax)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    fill_ray(r, origin, dir, tmin, tmax);
    rtcOccluded1(m_impl->scene, &ctx, &r);
    return r.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

}  // namespace vlf
