// face_probe.hpp — what a bake gives each face against the path tracer, face by face (issue
// 11: "no face of a lit model darker than half the path tracer's value"). A face is seen
// straight on from just above its centroid, so a face smaller than a pixel of any camera is
// still measured, and faces a camera does not see count too.
#pragma once

#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/render/render.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// One ray per face: from the centroid, kProbeLift (normalised units) along the normal,
// straight back at the face.
inline constexpr double kProbeLift = 1e-4;
std::vector<PrimaryRay> face_probe_rays(const Scene& scene, const std::vector<int>& faces);

struct FaceProbe {
    int face = 0;
    double value = 0.0;      // the bake's radiance (mean of the channels), in `mode`
    double reference = 0.0;  // the path tracer's, same units
    double std_error = 0.0;  // the path tracer's standard error (from independent batches)
};

// The faces' values in `mode` (Texture or Rays) beside a path-traced reference of
// `batches` independent batches of `spp` paths each (batches >= 2; std_error from their
// spread).
std::vector<FaceProbe> probe_faces(const Renderer& renderer, const std::vector<int>& faces,
                                   RenderMode mode, int spp, int batches);

// The faces whose value is below `fraction` of the reference by more than `sigmas` of the
// reference's standard error: value < fraction * (reference - sigmas * std_error).
std::vector<FaceProbe> darker_than(const std::vector<FaceProbe>& probes, double fraction,
                                   double sigmas);

}  // namespace vlf
