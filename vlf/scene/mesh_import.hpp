// mesh_import.hpp — polygon meshes from files (OBJ, PLY, OFF, STL) through OpenMesh's
// readers (DESIGN §2, §3). Positions, face outlines and vertex normals (OBJ `vn`, PLY
// nx/ny/nz, NOFF) are read; the scene loader checks and transforms them.
#pragma once

#include <string>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

struct ImportedMesh {
    std::vector<Vec3> vertices;           // file units
    std::vector<std::vector<int>> faces;  // vertex indices in the file's order (front = CCW)
    std::vector<Vec2> uvs;  // texture coordinates per vertex, or empty (scene imports only)
    // The file's vertex normals (file frame, per vertex; not checked: the loader drops
    // zero, non-finite or back-facing ones per face), or empty when it has none.
    std::vector<Vec3> normals;
    // Why a file's normals were not kept ("" when kept or when it has none), for a note.
    std::string normals_left_out;
};

// Checks an OBJ file's text (mesh_import.cpp): vertex coordinates must be finite numbers in
// single precision; with `faces`, faces need 3 or more distinct vertex indices. Throws
// vlf::Error "<path>:<line>: <what>".
void check_obj_text(const std::string& path, bool faces);

// The same for OFF (the header's counts against the body), binary STL (the triangle count
// against the size) and PLY (triangle strips are refused): "'<path>': <what>".
void check_off_text(const std::string& path);
void check_stl_size(const std::string& path);
void check_ply_header(const std::string& path);

// True when the file name ends in a supported extension (.obj .ply .off .stl, any case).
bool is_supported_mesh_file(const std::string& path);

// Reads a mesh. Throws vlf::Error with a message naming the problem but not the place
// (the caller prefixes "<scene file>: objects[i].file: "): missing or unreadable file,
// unsupported extension, a reader failure, faces OpenMesh had to drop.
ImportedMesh import_mesh(const std::string& path);

}  // namespace vlf
