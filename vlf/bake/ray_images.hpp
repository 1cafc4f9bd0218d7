// ray_images.hpp — the stored rays of a bake as layered depth images (VLF §3; DESIGN §6):
// per direction d and pixel (i, j) of its PSF, the fragments along that ray as samples
// (face id + outgoing radiance L_T), for specular faces (and for every face with
// --store-all-rays). In memory as RayImages; streamed one direction at a time, straight
// from a finished propagation or from RayImages, as a RaySource.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "vlf/field/radiance_maps.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/parameters.hpp"

namespace vlf {

class Transport;

// The stored rays of every direction: for direction d and pixel (i, j), samples
// [pixel_offset[(d*N + j)*N + i], pixel_offset[... + 1]) of face/radiance.
struct RayImages {
    int directions = 0;
    int resolution = 0;
    int tile = 0;
    std::vector<uint64_t> pixel_offset;  // directions * N * N + 1
    std::vector<int32_t> face;
    std::vector<RgbF> radiance;  // L_T, W m^-2 sr^-1, travelling along the face's front sense
    // Radiance of `face` on ray (d, i, j); false when the ray holds no sample of that face.
    bool lookup(int d, int i, int j, int face, RgbF& out) const;
    // The samples of ray (d, i, j) are [begin, end) of face/radiance; false (and nothing
    // set) outside the images.
    bool samples(int d, int i, int j, uint64_t& begin, uint64_t& end) const;
};

// One direction's stored rays as a layered depth image: per pixel (row-major, N x N) a
// sample count, the samples in pixel order, ascending face id within a pixel.
struct DirectionRays {
    std::vector<uint32_t> counts;
    std::vector<int32_t> face;
    std::vector<RgbF> radiance;
};
// Fills `out` with the stored rays of direction d (0 <= d < directions). A source may be
// called from several threads at once, for different directions and outputs.
using RaySource = std::function<void(int d, DirectionRays& out)>;
RaySource ray_source(const RayImages& rays);
// Straight from a finished propagation's radiance maps: the bake's rays without holding
// all of them in memory (what propagate writes with).
RaySource ray_source(const Scene& scene, const PropagateParams& params, const Transport& transport);
// The same, each direction's specular maps resampled just before its rays are made
// (SpecularResampler, VLF §5): for a propagation run with RunOptions::resample_later, so the
// tracing overlaps the bake writer's serial compression. The bake is the same bits.
RaySource resampling_ray_source(const Scene& scene, const PropagateParams& params,
                                Transport& transport);

// Every direction of `source`, gathered into RayImages.
RayImages gather_rays(const RaySource& source, int directions, int resolution, int tile);

}  // namespace vlf
