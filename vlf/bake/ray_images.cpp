// ray_images.cpp — the bake's stored rays: lookups, and the ray sources that stream them a
// direction at a time (ray_images.hpp).
#include "vlf/bake/ray_images.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <memory>

#include "vlf/core/error.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/transport/resample.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

bool RayImages::samples(int d, int i, int j, uint64_t& begin, uint64_t& end) const {
    if (d < 0 || d >= directions || i < 0 || j < 0 || i >= resolution || j >= resolution)
        return false;
    const size_t p = (size_t(d) * resolution + size_t(j)) * resolution + size_t(i);
    begin = pixel_offset[p];
    end = pixel_offset[p + 1];
    return true;
}

bool RayImages::lookup(int d, int i, int j, int face_id, RgbF& out) const {
    uint64_t b = 0, e = 0;
    if (!samples(d, i, j, b, e)) return false;
    for (uint64_t k = b; k < e; ++k)
        if (face[k] == face_id) {
            out = radiance[k];
            return true;
        }
    return false;
}

RaySource ray_source(const RayImages& rays) {
    return [&rays](int d, DirectionRays& out) {
        const size_t px = size_t(rays.resolution) * rays.resolution;
        const uint64_t b = rays.pixel_offset[size_t(d) * px];
        const uint64_t e = rays.pixel_offset[size_t(d + 1) * px];
        out.counts.resize(px);
        for (size_t k = 0; k < px; ++k)
            out.counts[k] = static_cast<uint32_t>(rays.pixel_offset[size_t(d) * px + k + 1] -
                                                  rays.pixel_offset[size_t(d) * px + k]);
        out.face.assign(rays.face.begin() + b, rays.face.begin() + e);
        out.radiance.assign(rays.radiance.begin() + b, rays.radiance.begin() + e);
    };
}

namespace {

// What resampling needs: the scene's ray caster and the resampler that traces with it.
struct Tracing {
    RayCaster caster;
    SpecularResampler resampler;
    Tracing(const Scene& s, Transport& t) : caster(s), resampler(t, caster) {}
};

struct Sample {
    uint32_t pixel;
    int32_t face;
    RgbF radiance;
};

// The samples of direction d in each stored face's local ray order (its fragments in tile
// row-major order, each in edge-table order); rasterising the face alone with the same
// rotation recovers the pixel of every entry. With a resampler, each face it resamples is
// resampled from that raster first.
void face_samples(const Scene& scene, const PropagateParams& params, const Transport& transport,
                  const SpecularResampler* resampler, int d, TwinRasters& twins, FaceRaster& raster,
                  std::vector<Sample>& samples) {
    const int N = params.field.resolution, m = params.field.tile;
    const RadianceMaps& spec = transport.specular_maps();
    const RadianceMaps& other = transport.other_maps();
    samples.clear();
    twins.clear();
    // The stored faces in ascending face id (per-pixel order is by face): the two maps' face
    // lists, each ascending and disjoint (a face is specular or not), merged; a walk over
    // all the scene's faces would read every Face of a million-triangle scene in every
    // direction.
    for (size_t a = 0, b = 0; a < spec.faces.size() || b < other.faces.size();) {
        VLF_DCHECK(a == spec.faces.size() || b == other.faces.size() ||
                   spec.faces[a] != other.faces[b]);
        const bool specular =
            b == other.faces.size() || (a < spec.faces.size() && spec.faces[a] < other.faces[b]);
        const Face& f = scene.faces[size_t(specular ? spec.faces[a++] : other.faces[b++])];
        const RadianceMaps* maps = specular ? &spec : &other;
        const uint64_t begin = maps->begin(d, f.id), count = maps->count(d, f.id);
        if (count == 0) continue;  // no ray here (most of a tessellated ball's faces)
        twins.rasterise(f, transport.rotations()[d], N, m, raster);
        VLF_CHECK(raster.covered == count);
        if (resampler != nullptr && maps == &spec) resampler->face(d, f.id, raster);
        uint64_t k = begin;
        for (const FaceFragment& frag : raster.fragments)
            raster.edge_table(frag).for_each_ray([&](int u, int v, int) {
                const uint32_t i = uint32_t(frag.s) * m + u, j = uint32_t(frag.t) * m + v;
                samples.push_back({j * uint32_t(N) + i, f.id, maps->total[k++]});
            });
    }
}

// The stored rays of a propagation, resampled first where `tracing` is given (it is kept
// alive by the source).
RaySource rays_of(const Scene& scene, const PropagateParams& params, const Transport& transport,
                  std::shared_ptr<const Tracing> tracing) {
    // A counting sort of the faces' samples by pixel (stable: each pixel keeps ascending
    // face order) gives the layered depth image. Each thread has its own scratch: the bake
    // writer asks for several directions at once.
    struct State {
        TwinRasters twins;
        FaceRaster raster;
        std::vector<Sample> samples;
        std::vector<uint32_t> cursor;
    };
    auto state = std::make_shared<tbb::enumerable_thread_specific<State>>();
    return [&scene, &params, &transport, state, tracing](int d, DirectionRays& out) {
        const int N = params.field.resolution;
        const size_t px = size_t(N) * N;
        State& st = state->local();
        face_samples(scene, params, transport, tracing ? &tracing->resampler : nullptr, d, st.twins,
                     st.raster, st.samples);
        out.counts.assign(px, 0);
        for (const Sample& s : st.samples) ++out.counts[s.pixel];
        st.cursor.resize(px);
        uint32_t at = 0;
        for (size_t p = 0; p < px; ++p) {
            st.cursor[p] = at;
            at += out.counts[p];
        }
        out.face.resize(st.samples.size());
        out.radiance.resize(st.samples.size());
        for (const Sample& s : st.samples) {
            const uint32_t k = st.cursor[s.pixel]++;
            out.face[k] = s.face;
            out.radiance[k] = s.radiance;
        }
    };
}

}  // namespace

RaySource ray_source(const Scene& scene, const PropagateParams& params,
                     const Transport& transport) {
    return rays_of(scene, params, transport, nullptr);
}

RaySource resampling_ray_source(const Scene& scene, const PropagateParams& params,
                                Transport& transport) {
    return rays_of(scene, params, transport, std::make_shared<const Tracing>(scene, transport));
}

RayImages gather_rays(const RaySource& source, int directions, int resolution, int tile) {
    const size_t px = size_t(resolution) * resolution;
    RayImages rays;
    rays.directions = directions;
    rays.resolution = resolution;
    rays.tile = tile;
    rays.pixel_offset.assign(size_t(directions) * px + 1, 0);
    DirectionRays dr;
    uint64_t at = 0;
    for (int d = 0; d < directions; ++d) {
        source(d, dr);
        for (size_t p = 0; p < px; ++p) {
            rays.pixel_offset[size_t(d) * px + p] = at;
            at += dr.counts[p];
        }
        rays.face.insert(rays.face.end(), dr.face.begin(), dr.face.end());
        rays.radiance.insert(rays.radiance.end(), dr.radiance.begin(), dr.radiance.end());
    }
    rays.pixel_offset.back() = at;
    return rays;
}

}  // namespace vlf
