// walkthrough — renders views of a VLF bake by lookup (VLF §6). Thin: options in, the
// library renders.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

#include "vlf/error.hpp"

namespace {

struct Options {
    std::string bake, camera, eye, look_at, up, size = "512x512", mode = "texture", output, path;
    double fov = 0.0, exposure = 0.0;
    int spp = 64, threads = 0;
    bool interactive = false;
};

int run(const Options& o) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(o.bake))
        throw vlf::Error(o.bake + ": not a bake bundle (no such directory)");
    if (!fs::exists(fs::path(o.bake) / "manifest.json"))
        throw vlf::Error(o.bake + ": not a bake bundle (manifest.json is missing)");
    throw vlf::Error(o.bake + ": this build cannot read bake bundles yet (format pending)");
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"walkthrough: render views of a VLF bake by lookup (Khanna et al., VLF §6).\n"
                 "Example: walkthrough out/cornell.vlf --camera default -o out/cornell.png"};
    app.add_option("bake", o.bake, "Bake bundle written by propagate (OUT.vlf)")->required();
    app.add_option("--camera", o.camera, "Named camera of the scene");
    app.add_option("--eye", o.eye, "Eye position x,y,z (scene units)");
    app.add_option("--look-at", o.look_at, "Point looked at x,y,z (scene units)");
    app.add_option("--up", o.up, "Up vector x,y,z");
    app.add_option("--fov", o.fov, "Vertical field of view, degrees");
    app.add_option("--size", o.size, "Image size WxH")->capture_default_str();
    app.add_option("--mode", o.mode, "rays | texture | raytrace | pathtrace")->capture_default_str();
    app.add_option("--spp", o.spp, "Samples per pixel (pathtrace)")->capture_default_str();
    app.add_option("--threads", o.threads, "Worker threads (0 = all cores)")->capture_default_str();
    app.add_option("--exposure", o.exposure, "Exposure in stops for PNG output")->capture_default_str();
    app.add_option("--path", o.path, "Camera path (JSON keyframes); -o is then a directory");
    app.add_option("-o,--output", o.output, "Image to write (.exr linear, .png tone-mapped)");
    app.add_flag("--interactive", o.interactive, "Open the interactive window (GLFW)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        std::fputs(app.help().c_str(), stdout);
        return 0;
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "walkthrough: %s\n", e.what());
        return 2;
    }
    try {
        return run(o);
    } catch (const vlf::Error& e) {
        std::fprintf(stderr, "walkthrough: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "walkthrough: internal error: %s\n", e.what());
        return 1;
    }
}
