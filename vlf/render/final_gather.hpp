// final_gather.hpp — light for the faces the field cannot resolve (docs/charts.md "Final
// gather"; issue 11).
//
// A chart stores diffuse light at the scene's texel density. A chart of a few texels (a patch
// of a curved model, a sliver along a crease, a small object) holds few rays of each
// direction, and its texels average faces of different orientation: on a model of
// thousands of small triangles some faces then read far darker or brighter than the light
// that reaches them. For those faces the light is gathered again from the finished field at
// every vertex (faces_to_gather), as lightmap bakers do in a final gather:
//
//   E(x)/pi = (1/K) sum_k L(x, w_k)                 K cosine-weighted, stratified rays w_k
//           + (1/pi) (1/K) sum_k Le cos_x cos_y / (r^2 p_A)   K light samples of the lamps
//           + (1/pi) E_delta(x)                    point, spot, sun: exact, shadowed
//
// where L(x, w) is the radiance the bake gives a ray from x along w in raytrace mode (the
// texels of the diffuse face it meets, mirrors and glass followed recursively), less the
// emission of a lamp met first, which the light samples count instead (a lamp seen in a
// mirror or through glass counts in L). The face's radiance at a point is then its emission
// plus its albedo there times E/pi interpolated between its vertices (vertex_light.hpp).
// Vertices at the same position whose faces' normals lie within kGatherShareDeg of each
// other share one gather point (normal: the faces' area-weighted mean), so a curved model
// shades smoothly across its charts and triangles. Light a point or spot light sends
// through glass, or through more mirrors than the path tracer's image sources, does not
// reach gathered faces (those caustics stay in the field's texels only).
//
// The gather changes what the bake shows, never the field, its ledger or its texels.
// Deterministic: each gather point has its own random stream, seeded by its index.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "vlf/bake/bake.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Only faces of at most this many texels of area are gathered: on a larger face the texels
// resolve the light more finely than its vertices (a wall panel lit by a window, its
// corners in the room's shadowed corners, would read dark all over).
inline constexpr double kGatherFaceTexels = 2.0;

// Faces at one position share a gather point while their normals lie within this angle of
// the first one's.
inline constexpr double kGatherShareDeg = 30.0;

struct GatherStats {
    int64_t faces = 0;      // faces gathered
    int64_t points = 0;     // gather points (shared vertices)
    int64_t centroids = 0;  // faces with a corner in a fold, gathered at their centroid too
};
nlohmann::json to_json(const GatherStats& s);

// The faces the final gather covers: diffuse and not specular (a lamp that also reflects
// included), of at most kGatherFaceTexels texels of area, in charts whose area is below
// `below_texels` texel areas or that are curved (not planar); increasing ids. A large face,
// or a face of a large planar chart (a floor of many triangles), keeps its chart's texels:
// there the field resolves the light finer than vertices could.
std::vector<int> faces_to_gather(const Scene& scene, double below_texels);

// Sets bake.vertex_light from the finished field in `bake` (its light maps), with
// bake.params.gather rays and light samples per point, for
// faces_to_gather(bake.scene, bake.params.gather_below); clears it when gather is 0.
GatherStats final_gather(Bake& bake);

}  // namespace vlf
