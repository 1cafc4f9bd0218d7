// decimate_mesh.cpp — quadric-error decimation of a triangle mesh to a target face count with
// Debian's OpenMesh (libopenmesh-dev, already a VLF dependency). Not part of the CMake build:
// it made scenes/meshes/stanford-bunny-1k.obj (scenes/meshes/README.md), built and run by hand:
//   g++ -O2 -std=c++17 bench/decimate_mesh.cpp -o /tmp/decimate_mesh -lOpenMeshCore -lOpenMeshTools
//   /tmp/decimate_mesh scenes/meshes/stanford-bunny.obj 1000 scenes/meshes/stanford-bunny-1k.obj
// Collapses that would flip a face normal are refused (ModNormalFlipping), so the result has
// no folded triangles; vertices no face uses are dropped; it writes positions and faces only.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <cstdio>
#include <cstdlib>

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s IN.obj FACES OUT.obj\n", argv[0]);
        return 2;
    }
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
        std::fprintf(stderr, "%s: cannot read\n", argv[1]);
        return 2;
    }
    const size_t before = mesh.n_faces();
    OpenMesh::Decimater::DecimaterT<Mesh> decimater(mesh);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle flipping;
    decimater.add(quadric);
    decimater.add(flipping);
    decimater.initialize();
    decimater.decimate_to_faces(0, std::strtoul(argv[2], nullptr, 10));
    // The scan has vertices no face uses (1113 in the bunny); they would be written too.
    for (const auto v : mesh.vertices())
        if (mesh.is_isolated(v)) mesh.delete_vertex(v, false);
    mesh.garbage_collection();
    if (!OpenMesh::IO::write_mesh(mesh, argv[3], OpenMesh::IO::Options::Default, 6)) {
        std::fprintf(stderr, "%s: cannot write\n", argv[3]);
        return 2;
    }
    std::printf("%zu -> %zu faces, %zu vertices\n", before, mesh.n_faces(), mesh.n_vertices());
    return 0;
}
