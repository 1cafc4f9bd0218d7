// winding.hpp — one front side throughout every imported surface (issue 12). VLF faces are
// one-sided (DESIGN §3: counter-clockwise seen from the front; the back is black and
// absorbing), so a model file whose faces disagree about their winding shows black patches.
// orient_faces turns faces so that neighbours agree and each part faces its viewer:
//   1. Vertices are welded by exact position (a file's meshes and materials split vertices
//      that are one point); faces are neighbours across an edge that exactly two faces share
//      (a manifold edge). Neighbours agree when they run through the shared edge in opposite
//      directions. A face on the vertices of an earlier face (a repeat, or the back of a
//      two-sided sheet) is nobody's neighbour and keeps its winding relative to that face.
//   2. Each part (faces connected through manifold edges) is made to agree by a breadth-first
//      walk from its first face in file order. A part that cannot agree throughout (one-sided,
//      like a Möbius strip) keeps the walk's assignment and is counted.
//   3. The part's side: a closed part (every edge manifold, agreeing throughout, enclosing
//      volume) faces outward (positive signed volume), unless it encloses one of the
//      `viewpoints` (the file's cameras and lights): then it is a room seen from inside and
//      faces inward. Any other part keeps the side of the larger area of its faces as the
//      file has them (a mostly right file stays as it is; a tie keeps the walk's start).
// Positions are in any one frame (the file's units); only signs and ratios are used.
#pragma once

#include <cstddef>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/mesh_import.hpp"

namespace vlf {

// What orient_faces changed in one mesh. A part spanning several meshes is counted in each.
struct WindingChanges {
    size_t faces = 0;              // the mesh's faces
    size_t agreed = 0;             // faces turned to agree with their neighbours
    size_t outward_faces = 0;      // faces turned with a closed part that faced inward ...
    size_t outward_parts = 0;      // ... and those parts
    size_t inward_faces = 0;       // faces turned with a closed part around a viewpoint ...
    size_t inward_parts = 0;       // ... and those parts
    size_t non_orientable = 0;     // parts that cannot agree throughout (Möbius strips)
    size_t disagreeing_edges = 0;  // their edges whose faces still disagree

    size_t turned() const { return agreed + outward_faces + inward_faces; }
    bool changed() const { return turned() > 0 || non_orientable > 0; }
};

// Turns faces of `meshes` (reverses their vertex lists; per-vertex texture coordinates go
// with the vertices) as the header comment says; parts may span meshes. `viewpoints` are
// positions in the meshes' frame. Returns one WindingChanges per mesh, in order. A mesh whose
// faces already agree and face their viewers is left bit-identical.
std::vector<WindingChanges> orient_faces(const std::vector<ImportedMesh*>& meshes,
                                         const std::vector<Vec3>& viewpoints);

}  // namespace vlf
