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
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
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

// OBJ text, line by line: every vertex has three coordinates that are finite in single
// precision (the readers parse floats and drop, or shift the indices past, such vertices),
// and with `faces`, every face has at least 3 vertices and no repeated index (OpenMesh
// drops such faces without a word).
void check_obj_text(const std::string& path, bool faces) {
    std::ifstream in(path);
    std::string line;
    long vertices = 0;
    for (size_t number = 1; std::getline(in, line); ++number) {
        if (line.size() < 2 || (line[1] != ' ' && line[1] != '\t')) continue;
        if (line[0] == 'v') {
            ++vertices;
            const char* s = line.c_str() + 1;
            for (int k = 0; k < 3; ++k) {
                while (*s == ' ' || *s == '\t') ++s;
                char* end = nullptr;
                const double v = std::strtod(s, &end);
                if (end == s)
                    throw Error(fmt::format("{}:{}: vertex has {} coordinate{} (needs 3 numbers)",
                                            path, number, k, k == 1 ? "" : "s"));
                if (!std::isfinite(v) || std::abs(v) > std::numeric_limits<float>::max())
                    throw Error(fmt::format("{}:{}: vertex coordinate '{}' is not a finite number",
                                            path, number, std::string(s, size_t(end - s))));
                s = end;
            }
        } else if (line[0] == 'f' && faces) {
            std::istringstream words(line.substr(2));
            std::vector<long> idx;
            for (std::string w; words >> w;) {
                if (w[0] == '#') break;
                const long i = std::strtol(w.c_str(), nullptr, 10);
                idx.push_back(i < 0 ? vertices + 1 + i : i);  // 1-based; negative: relative
            }
            if (idx.size() < 3)
                throw Error(fmt::format("{}:{}: face has {} vertex index(es) (needs at least 3)",
                                        path, number, idx.size()));
            std::vector<long> sorted = idx;
            std::sort(sorted.begin(), sorted.end());
            if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
                throw Error(fmt::format("{}:{}: face repeats a vertex index", path, number));
        }
    }
}

bool is_supported_mesh_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

ImportedMesh import_mesh(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw Error(fmt::format("mesh file '{}' is a directory, not a file", path));
    if (!std::filesystem::is_regular_file(path, ec))
        throw Error(fmt::format("mesh file '{}' does not exist", path));
    if (!std::ifstream(path).good())
        throw Error(fmt::format("mesh file '{}' cannot be read", path));
    if (!is_supported_mesh_file(path))
        throw Error(fmt::format(
            "mesh file '{}' has an unsupported extension (use .obj, .ply, .off or .stl)", path));

    if (lower_extension(path) == ".obj") check_obj_text(path, true);

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
