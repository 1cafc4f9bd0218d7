// mesh_import.cpp — OpenMesh readers to a plain vertex/face list.
//
// The IO header must come before the mesh header: including MeshIO.hh registers the
// readers (OpenMesh's documented pitfall).
#include "vlf/scene/mesh_import.hpp"

#include <fmt/core.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>

#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"

namespace vlf {

namespace {

// Double-precision points: the readers parse floats, but nothing after them loses more.
struct DoubleTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using ReadMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh reports dropped faces only on its global omerr() stream, which writes to
// std::cerr. While a mesh is read, std::cerr is pointed at a string buffer so a dropped face
// becomes an error instead of a stray line on stderr and a hole. (mostream::disconnect()
// leaks its target, so the stream is redirected rather than re-plumbed.)
class CaptureStderr {
  public:
    CaptureStderr() : m_old(std::cerr.rdbuf(m_text.rdbuf())) {}
    ~CaptureStderr() {
        ::omerr().flush();
        std::cerr.rdbuf(m_old);
    }
    CaptureStderr(const CaptureStderr&) = delete;
    CaptureStderr& operator=(const CaptureStderr&) = delete;
    std::string text() {
        ::omerr().flush();
        return m_text.str();
    }

  private:
    std::ostringstream m_text;
    std::streambuf* m_old;
};

std::mutex g_openmesh_mutex;  // omerr() and std::cerr are process-global

}  // namespace

bool is_supported_mesh_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

ImportedMesh import_mesh(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw Error(fmt::format("mesh file '{}' does not exist", path));
    if (!std::ifstream(path).good())
        throw Error(fmt::format("mesh file '{}' cannot be read", path));
    if (!is_supported_mesh_file(path))
        throw Error(fmt::format(
            "mesh file '{}' has an unsupported extension (use .obj, .ply, .off or .stl)", path));

    ReadMesh mesh;
    std::string log;
    bool ok = false;
    {
        std::lock_guard<std::mutex> lock(g_openmesh_mutex);
        CaptureStderr capture;
        OpenMesh::IO::Options opt;
        ok = OpenMesh::IO::read_mesh(mesh, path, opt);
        log = capture.text();
    }
    auto first_line = [&](const std::string& needle) {
        size_t at = log.find(needle);
        size_t end = log.find('\n', at);
        return log.substr(at, end == std::string::npos ? std::string::npos : end - at);
    };
    if (!ok) {
        std::string why = log.empty() ? std::string("OpenMesh could not parse it") : first_line("");
        throw Error(fmt::format("mesh file '{}' could not be read: {}", path, why));
    }
    // ImporterT drops faces with invalid or repeated vertex indices (it duplicates
    // non-manifold ones, which is harmless for us).
    if (log.find("ImporterT:") != std::string::npos)
        throw Error(fmt::format("mesh file '{}': OpenMesh dropped a face ({})", path,
                                first_line("ImporterT:")));

    ImportedMesh out;
    out.vertices.reserve(mesh.n_vertices());
    for (auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        out.vertices.emplace_back(p[0], p[1], p[2]);
    }
    out.faces.reserve(mesh.n_faces());
    for (auto fh : mesh.faces()) {
        std::vector<int> f;
        for (auto vh : mesh.fv_range(fh)) f.push_back(vh.idx());
        out.faces.push_back(std::move(f));
    }
    if (out.faces.empty()) throw Error(fmt::format("mesh file '{}' has no faces", path));
    return out;
}

}  // namespace vlf
