// lightfield_exr.cpp — the stored rays as one deep tiled OpenEXR part per direction
// (lightfield_exr.hpp).
#include "vlf/bake/lightfield_exr.hpp"

#include <Iex.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepTiledInputPart.h>
#include <OpenEXR/ImfDeepTiledOutputPart.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfVecAttribute.h>
#include <fmt/format.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

const char* const kRayChannels[3] = {"R", "G", "B"};

std::string part_name(int d) {
    return fmt::format("dir{}", d);
}

Imf::Header part_header(const FieldParams& field, const DirectionSet& directions, int d) {
    const int N = field.resolution, m = field.tile;
    Imf::Header h(N, N);
    h.setName(part_name(d));
    h.setType(Imf::DEEPTILE);
    h.setTileDescription(Imf::TileDescription(m, m, Imf::ONE_LEVEL));
    h.compression() = Imf::ZIPS_COMPRESSION;  // ZIP and PIZ are rejected for deep data
    h.channels().insert("face", Imf::Channel(Imf::UINT));
    for (const char* c : kRayChannels) h.channels().insert(c, Imf::Channel(Imf::FLOAT));
    const Vec3 w = directions.direction(d);
    h.insert("vlfDirectionIndex", Imf::IntAttribute(d));
    h.insert("vlfDirection", Imf::V3dAttribute(Imath::V3d(w.x, w.y, w.z)));
    h.insert("vlfSolidAngle", Imf::DoubleAttribute(directions.solid_angle(d)));
    return h;
}

// Per-pixel sample pointers of a deep frame buffer: into face[] and radiance[] at each
// pixel's first sample, null for empty pixels.
struct DeepPointers {
    std::vector<char*> face, rgb[3];

    explicit DeepPointers(size_t px) : face(px) {
        for (auto& p : rgb) p.resize(px);
    }
    // Returns the number of samples addressed.
    template <class FaceT>
    uint64_t point(const std::vector<uint32_t>& counts, FaceT* faces, RgbF* radiance) {
        uint64_t at = 0;
        for (size_t k = 0; k < counts.size(); ++k) {
            if (counts[k] == 0) {
                face[k] = rgb[0][k] = rgb[1][k] = rgb[2][k] = nullptr;
                continue;
            }
            face[k] = reinterpret_cast<char*>(faces + at);
            for (int c = 0; c < 3; ++c) rgb[c][k] = reinterpret_cast<char*>(&radiance[at].x + c);
            at += counts[k];
        }
        return at;
    }
    Imf::DeepFrameBuffer frame_buffer(std::vector<uint32_t>& counts, int N) {
        Imf::DeepFrameBuffer fb;
        fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()),
                                             sizeof(uint32_t), sizeof(uint32_t) * N));
        fb.insert("face", Imf::DeepSlice(Imf::UINT, reinterpret_cast<char*>(face.data()),
                                         sizeof(char*), sizeof(char*) * N, sizeof(uint32_t)));
        for (int c = 0; c < 3; ++c)
            fb.insert(kRayChannels[c],
                      Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(rgb[c].data()),
                                     sizeof(char*), sizeof(char*) * N, sizeof(RgbF)));
        return fb;
    }
};

}  // namespace

uint64_t write_lightfield_exr(const std::string& file, const FieldParams& field,
                              const DirectionSet& directions, const RaySource& source) {
    const int N = field.resolution, l = field.directions;
    std::unique_ptr<Imf::MultiPartOutputFile> out;
    {
        std::vector<Imf::Header> headers;  // the library keeps its own copies
        headers.reserve(l);
        for (int d = 0; d < l; ++d) headers.push_back(part_header(field, directions, d));
        out = std::make_unique<Imf::MultiPartOutputFile>(file.c_str(), headers.data(), l);
    }
    const size_t px = size_t(N) * N;
    DeepPointers ptr(px);
    uint64_t samples = 0;
    // A pipeline: the source makes the next directions' rays on the other threads while
    // one direction at a time is compressed and written, in direction order.
    int next = 0;
    const size_t in_flight = 2 * size_t(tbb::this_task_arena::max_concurrency());
    using Job = std::shared_ptr<std::pair<int, DirectionRays>>;  // (tokens are copied)
    tbb::parallel_pipeline(
        in_flight,
        tbb::make_filter<void,
                         Job>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control& fc) -> Job {
            if (next == l) {
                fc.stop();
                return nullptr;
            }
            auto job = std::make_shared<std::pair<int, DirectionRays>>();
            job->first = next++;
            return job;
        }) & tbb::make_filter<Job, Job>(tbb::filter_mode::parallel, [&](Job job) {
            source(job->first, job->second);
            return job;
        }) & tbb::make_filter<Job, void>(tbb::filter_mode::serial_in_order, [&](Job job) {
            const int d = job->first;
            DirectionRays& rays = job->second;
            VLF_CHECK(rays.counts.size() == px && rays.face.size() == rays.radiance.size());
            const uint64_t at = ptr.point(rays.counts, rays.face.data(), rays.radiance.data());
            VLF_CHECK(at == rays.face.size());
            samples += at;
            Imf::DeepTiledOutputPart part(*out, d);
            part.setFrameBuffer(ptr.frame_buffer(rays.counts, N));
            part.writeTiles(0, part.numXTiles() - 1, 0, part.numYTiles() - 1);
        }));
    return samples;
}

namespace {

void check_part_header(const Imf::Header& h, int d, const LightfieldLayout& layout,
                       const BundleErrors& errors, const std::string& part) {
    const int N = layout.resolution, m = layout.tile;
    if (!h.hasName() || h.name() != part_name(d))
        errors.fail(part, fmt::format("is not named {} (part {} is missing)", part_name(d), d));
    if (!h.hasType() || h.type() != Imf::DEEPTILE) errors.fail(part, "is not a deep tiled part");
    const Imath::Box2i dw = h.dataWindow();
    if (dw.min.x != 0 || dw.min.y != 0 || dw.max.x != N - 1 || dw.max.y != N - 1)
        errors.mismatch(part, fmt::format("data window is not {}x{}", N, N));
    if (!h.hasTileDescription()) errors.mismatch(part, "no tile description");
    const Imf::TileDescription td = h.tileDescription();
    if (int(td.xSize) != m || int(td.ySize) != m || td.mode != Imf::ONE_LEVEL)
        errors.mismatch(part, fmt::format("tiles are {}x{}, the parameters say {}x{}", td.xSize,
                                          td.ySize, m, m));
    const Imf::Channel* fc = h.channels().findChannel("face");
    if (!fc || fc->type != Imf::UINT) errors.fail(part, "channel 'face' (UINT) is missing");
    for (const char* n : kRayChannels) {
        const Imf::Channel* c = h.channels().findChannel(n);
        if (!c || c->type != Imf::FLOAT)
            errors.fail(part, fmt::format("channel '{}' (FLOAT) is missing", n));
    }
}

// One part's samples, in pixel order.
struct PartSamples {
    std::vector<uint32_t> counts;
    std::vector<uint32_t> face;
    std::vector<RgbF> radiance;
};

void read_part(Imf::MultiPartInputFile& in, int d, const LightfieldLayout& layout,
               const BundleErrors& errors, const std::string& part, DeepPointers& ptr,
               PartSamples& s) {
    const int N = layout.resolution;
    const uint32_t faces = uint32_t(layout.stored.size());
    Imf::DeepTiledInputPart tp(in, d);
    s.counts.resize(size_t(N) * N);
    tp.setFrameBuffer(ptr.frame_buffer(s.counts, N));
    const int nx = tp.numXTiles(), ny = tp.numYTiles();
    tp.readPixelSampleCounts(0, nx - 1, 0, ny - 1);
    uint64_t total = 0;
    for (uint32_t c : s.counts) {
        // A ray crosses each stored face at most once.
        if (c > faces) errors.fail(part, "a pixel holds more samples than there are faces");
        total += c;
    }
    s.face.assign(total, 0);
    s.radiance.assign(total, RgbF(0.0f));
    ptr.point(s.counts, s.face.data(), s.radiance.data());
    tp.readTiles(0, nx - 1, 0, ny - 1);
}

// Validates one part's samples (faces in range and stored, strictly ascending per pixel,
// finite radiance) and appends them to `rays` as direction d.
void append_part(const PartSamples& s, int d, const LightfieldLayout& layout,
                 const BundleErrors& errors, const std::string& part, RayImages& rays) {
    const uint32_t faces = uint32_t(layout.stored.size());
    const size_t px = s.counts.size();
    const size_t base = rays.face.size();
    uint64_t at = 0;
    for (size_t k = 0; k < px; ++k) {
        rays.pixel_offset[size_t(d) * px + k] = base + at;
        for (uint32_t n = 0; n < s.counts[k]; ++n, ++at) {
            const uint32_t f = s.face[at];
            if (f >= faces)
                errors.fail(part,
                            fmt::format("sample of face {} (the scene has {} faces)", f, faces));
            if (!layout.stored[f])
                errors.mismatch(part, fmt::format("face {} has no stored rays", f));
            if (n > 0 && s.face[at - 1] >= f)
                errors.fail(part, "samples of a pixel are not in ascending face order");
            const RgbF& v = s.radiance[at];
            if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
                errors.fail(part, "non-finite radiance");
        }
    }
    rays.face.insert(rays.face.end(), s.face.begin(), s.face.end());
    rays.radiance.insert(rays.radiance.end(), s.radiance.begin(), s.radiance.end());
}

}  // namespace

RayImages read_lightfield_exr(const std::string& file, const LightfieldLayout& layout,
                              const BundleErrors& errors) {
    const int l = layout.directions, N = layout.resolution;
    Imf::MultiPartInputFile in(file.c_str());
    if (in.parts() != l)
        errors.mismatch(kLightfieldFile,
                        fmt::format("{} parts, the parameters say {} directions", in.parts(), l));
    RayImages rays;
    rays.directions = l;
    rays.resolution = N;
    rays.tile = layout.tile;
    const size_t px = size_t(N) * N;
    rays.pixel_offset.assign(size_t(l) * px + 1, 0);
    DeepPointers ptr(px);
    PartSamples samples;
    for (int d = 0; d < l; ++d) {
        const std::string part = fmt::format("{}: part {}", kLightfieldFile, d);
        try {
            check_part_header(in.header(d), d, layout, errors, part);
            if (!in.partComplete(d)) errors.fail(part, "is incomplete");
            read_part(in, d, layout, errors, part, ptr, samples);
            append_part(samples, d, layout, errors, part, rays);
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) {  // Iex::BaseExc: damaged tiles, short file
            errors.fail(part, e.what());
        }
    }
    rays.pixel_offset.back() = rays.face.size();
    return rays;
}

}  // namespace vlf
