// vertex_light.hpp — light gathered at the vertices of the faces whose charts are too small
// for the field to resolve (render/final_gather.hpp, docs/charts.md "Final gather"): per
// vertex of each such face, the irradiance over pi that arrives there. The face's diffuse
// radiance at a point is its emission plus its albedo there times the vertices' values
// interpolated (barycentric on a triangle, mean value coordinates on a polygon). Part of the
// bake (vertexlight.bin); empty when no face was gathered.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct VertexLight {
    // Per face of the scene: the index in `incident` of its first vertex's value, or -1
    // when the face is not gathered (it reads its chart's texels). Empty: none is.
    std::vector<int64_t> first;
    // E / pi per vertex of every gathered face, in the order of its vertices, radiance units
    // (W m^-2 sr^-1): what a white Lambertian surface there would send.
    std::vector<RgbF> incident;

    bool has(int face) const { return !first.empty() && first[size_t(face)] >= 0; }
    size_t face_count() const;
    // The interpolated E / pi at x (normalised coordinates, a point of f); f must be gathered.
    Rgb at(const Face& f, const Vec3& x) const;
};

}  // namespace vlf
