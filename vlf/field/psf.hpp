// psf.hpp — one parallel subfield (PSF): the scene rotated so its direction is +z and
// rasterised into N x N parallel rays over [-1,1]^2, cut into (N/m)^2 tiles of m x m rays;
// each tile holds the list of polygon fragments that its rays intersect, each with its
// edge table (VLF §3, eq. (1); DESIGN §4).
//
// Ray (i, j) passes through the pixel centre ((2i+1)/N - 1, (2j+1)/N - 1) (eq. (1)), and
// travels along +z of the rotated frame; its depth along the ray is the rotated z, always
// recomputed from the face's plane equation, never stored. A polygon covers a ray when
// the pixel centre lies inside its projection under a half-open fill rule that treats a
// shared edge identically from both sides, so meshes are watertight: every ray crosses
// a closed surface exactly once per crossing.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/coverage.hpp"
#include "vlf/field/edge_table.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Resolution N, tile size m. Valid: 1 <= m <= N <= 4096, N a multiple of m.
void validate_raster(int resolution, int tile);  // throws ParameterError

struct Fragment {
    int32_t face = 0;
    uint16_t row_begin = 0;  // tile-local first row of the edge table
    uint16_t rows = 0;
    uint32_t span_offset = 0;  // into Tile::spans
    uint32_t ray_offset = 0;   // covered rays of earlier fragments in this tile
    uint32_t covered = 0;      // covered rays of this fragment
    int8_t facing = 0;         // +1: front side towards +z (sends along +z); -1: towards -z
};

struct Tile {
    uint16_t s = 0, t = 0;            // tile column and row
    std::vector<Fragment> fragments;  // in ascending face id
    std::vector<Span> spans;          // all edge-table rows of all fragments
    uint32_t covered = 0;             // sum of the fragments' covered rays

    EdgeTable edge_table(const Fragment& f) const {
        return EdgeTable{f.row_begin, f.rows, spans.data() + f.span_offset};
    }
};

// Area of one pixel of an N x N ray grid over [-1,1]^2, (2/N)^2: the beam cross-section a
// of DESIGN §5.
inline double ray_area(int resolution) {
    return 4.0 / (double(resolution) * resolution);
}

// Pixel-centre coordinate of ray i of an N x N grid over [-1,1]^2 (eq. (1)).
inline double ray_coord(int i, int resolution) {
    return (2.0 * i + 1.0) / resolution - 1.0;
}

struct Psf {
    int direction = -1;   // index into the direction set (or -1 for a free direction)
    Vec3 omega{0, 0, 1};  // the direction, scene frame
    Mat3 rotation{1.0};   // rotation * omega = +z
    int resolution = 0;   // N
    int tile_size = 0;    // m
    int tiles_per_side() const { return resolution / tile_size; }
    std::vector<Tile> tiles;       // non-empty tiles, in row-major (t, s) order
    std::vector<int32_t> tile_of;  // n*n entries: index into tiles, or -1 when empty

    // Pixel-centre coordinates of ray (i, j) in the rotated frame (eq. (1)).
    double ray_x(int i) const { return ray_coord(i, resolution); }
    double ray_y(int j) const { return ray_coord(j, resolution); }
    // Area of one pixel, (2/N)^2: the beam cross-section a of DESIGN §5.
    double ray_area() const { return vlf::ray_area(resolution); }
};

// Depth (rotated z) of the face's plane on the ray through (x, y) of the rotated frame.
inline double plane_depth(const Face& f, const Mat3& rotation, double x, double y) {
    const Vec3 n = rotation * f.normal;
    return (f.plane_offset - n.x * x - n.y * y) / n.z;
}

// A face's plane in one PSF, for many rays: where ray (i, j) of the N x N grid meets it,
// as depth (rotated z) and as a scene-frame point.
struct PlaneInPsf {
    PlaneInPsf(const Face& f, const Mat3& rotation, int resolution)
        : offset(f.plane_offset),
          n(rotation * f.normal),
          back(glm::transpose(rotation)),
          N(resolution) {}
    double depth(int i, int j) const {
        return (offset - n.x * ray_coord(i, N) - n.y * ray_coord(j, N)) / n.z;
    }
    Vec3 point(int i, int j) const {
        return back * Vec3(ray_coord(i, N), ray_coord(j, N), depth(i, j));
    }
    double offset;
    Vec3 n;     // the normal, rotated
    Mat3 back;  // rotated frame -> scene frame
    int N;
};

// |n . omega| below which a face is edge-on and covers no ray.
inline constexpr double kEdgeOnCosine = 1e-12;

// Rasterise every face of the scene for direction omega (unit). Faces seen edge-on
// (|n.omega| < 1e-12) cover no ray.
Psf rasterise_psf(const Scene& scene, const Vec3& omega, int direction, int resolution,
                  int tile_size);

// Same with an explicit rotation (perturbed PSFs: rotation * omega must be +z).
// `coverage`, when given, was measured with this very rotation and resolution as
// `direction` (count_covered): a face it measured that covers no ray there is not
// rasterised again (most of a fine mesh's faces in most directions); the PSF is the same.
Psf rasterise_psf(const Scene& scene, const Mat3& rotation, int direction, int resolution,
                  int tile_size, const Coverage* coverage = nullptr);

// One face rasterised alone: its fragments in tile row-major order (the same fragments,
// in the same order, as it has in the full PSF). Used where a single face is needed in a
// direction without rasterising the scene (specular targets, perturbed transfers).
struct FaceFragment {
    uint16_t s = 0, t = 0;
    uint16_t row_begin = 0, rows = 0;
    uint32_t span_offset = 0;
    uint32_t covered = 0;
};
struct FaceRaster {
    int8_t facing = 0;  // 0 when edge-on (no fragments)
    std::vector<FaceFragment> fragments;
    std::vector<Span> spans;
    uint32_t covered = 0;
    EdgeTable edge_table(const FaceFragment& f) const {
        return EdgeTable{f.row_begin, f.rows, spans.data() + f.span_offset};
    }
};
void rasterise_face(const Face& face, const Mat3& rotation, int resolution, int tile_size,
                    FaceRaster& out);
// The rays the face covers in that frame (rasterise_face's `covered`) without the
// fragments: for a caller that only counts.
uint32_t count_covered(const Face& face, const Mat3& rotation, int resolution);

// A face and its twin (Face::twin: glass, two-sided objects) are one polygon, their vertices
// the same points in reverse order, and a raster depends on the points alone (row_spans
// orders each edge's ends): the twin covers the same rays in the same fragments and faces
// the other way. Within one direction, this keeps the raster of each face whose twin has a
// greater id and hands it to the twin, instead of rasterising the polygon twice (a glass
// ball's inner faces are half its faces, their ids after the outer ones').
class TwinRasters {
  public:
    // Rasterises `face` (as rasterise_face) or copies its twin's raster, kept when the twin
    // was given since the last clear(). Every call since then must have the same rotation,
    // resolution and tile size.
    void rasterise(const Face& face, const Mat3& rotation, int resolution, int tile_size,
                   FaceRaster& out);
    // Forgets the kept rasters (before another direction or rotation).
    void clear();

  private:
    std::vector<int32_t> m_kept_at;  // per face id: index into m_kept, or -1
    std::vector<int32_t> m_kept_faces;
    std::vector<FaceRaster> m_kept;  // reused from direction to direction
    size_t m_count = 0;
};

// Bytes held by the PSF's tiles, fragments and edge tables.
struct PsfMemory {
    size_t tiles = 0, fragments = 0, edge_tables = 0;
};
PsfMemory memory_of(const Psf& psf);

}  // namespace vlf
