// walkthrough — renders views of a VLF bake by lookup (VLF §6; DESIGN §7). Thin: options
// in, the library renders; errors print one line `walkthrough: ...` and exit 2.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "vlf/bake/bake.hpp"
#include "vlf/core/cli_main.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"
#include "vlf/core/memory.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/core/progress.hpp"
#include "vlf/core/stopwatch.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/image_metrics.hpp"
#include "vlf/render/render.hpp"

#ifdef VLF_HAVE_INTERACTIVE
#include "interactive.hpp"
#endif

namespace {

namespace fs = std::filesystem;

// Sub-pixel rays per side of the emitter mask behind --reference's "away from emitters":
// fixed, so the figures do not depend on --pixel-samples; as fine as the accuracy tests.
constexpr int kEmitterMaskSamples = 16;
constexpr int kMaxPixelSamples = 64;
constexpr int kMaxImageSide = 16384;

// Checks of the elements of "x,y,z" and "WxH" (CLI11 splits the value at the delimiter and
// reports a failure as one line naming the option: "--eye: 'x' is not a finite number
// (expected x,y,z)"). A value too short takes the next argument as its last element.
const CLI::Validator kFinite(
    [](std::string& s) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(s, v) || !std::isfinite(v))
            return "'" + s + "' is not a finite number (expected x,y,z)";
        return {};
    },
    "");
const CLI::Validator kImageSide(
    [](std::string& s) -> std::string {
        int v = 0;
        if (!CLI::detail::lexical_cast(s, v) || v < 1 || v > kMaxImageSide)
            return fmt::format("'{}' is not a whole number of pixels from 1 to {} (expected WxH)",
                               s, kMaxImageSide);
        return {};
    },
    "");

// A vector option "x,y,z" (three finite numbers).
CLI::Option* add_vec3(CLI::App& app, const std::string& name, std::array<double, 3>& v,
                      const std::string& help) {
    return app.add_option(name, v, help)->delimiter(',')->check(kFinite)->type_name("X,Y,Z");
}

struct Options {
    std::string bake, camera, mode = "texture", output, path;
    std::string format = "png", reference;
    std::array<double, 3> eye{}, look_at{}, up{};  // with has_*: given on the command line
    bool has_eye = false, has_look_at = false, has_up = false, has_fov = false;
    std::pair<int, int> size{512, 512};
    double fov = 0.0, exposure = 0.0;
    int spp = 64, threads = 0, max_depth = 16, pixel_samples = 1;
    uint64_t seed = 1;
    double light_paths = 1.0;
    bool interactive = false;
};

// The camera the options ask for: --camera NAME, or --eye/--look-at[/--up/--fov] on top of
// the scene's first camera (or defaults), or the scene's first camera.
vlf::Camera choose_camera(const Options& o, const vlf::Scene& scene) {
    const bool explicit_view = o.has_eye || o.has_look_at || o.has_up || o.has_fov;
    if (!o.camera.empty()) {
        if (explicit_view)
            throw vlf::ParameterError(
                "--camera: cannot be combined with --eye/--look-at/--up/--fov");
        for (const vlf::Camera& c : scene.cameras)
            if (c.name == o.camera) return c;
        std::string names;
        for (const vlf::Camera& c : scene.cameras) names += (names.empty() ? "" : ", ") + c.name;
        throw vlf::ParameterError("--camera: unknown camera '" + o.camera +
                                  "' (the scene has: " + (names.empty() ? "none" : names) + ")");
    }
    vlf::Camera cam;
    if (!scene.cameras.empty())
        cam = scene.cameras.front();
    else if (!explicit_view)
        throw vlf::ParameterError("the scene has no camera: give --camera or --eye and --look-at");
    if (explicit_view) {
        if (scene.cameras.empty() && (!o.has_eye || !o.has_look_at))
            throw vlf::ParameterError(
                "--eye and --look-at are both needed (the scene has no camera)");
        cam.name = "command line";
        auto vec = [](const std::array<double, 3>& v) { return vlf::Vec3(v[0], v[1], v[2]); };
        if (o.has_eye) cam.eye = vec(o.eye);
        if (o.has_look_at) cam.look_at = vec(o.look_at);
        if (o.has_up) cam.up = vec(o.up);
        if (o.has_fov) cam.fov_y_deg = o.fov;
    }
    vlf::validate_camera(cam, "camera");
    return cam;
}

void check_writable_dir(const fs::path& dir, const std::string& what) {
    std::error_code ec;
    const fs::path d = dir.empty() ? fs::path(".") : dir;
    if (!fs::is_directory(d, ec))
        throw vlf::Error(what + ": directory " + d.string() + " does not exist");
}

int run_path(const Options& o, const vlf::Renderer& renderer, const vlf::RenderSettings& rs) {
    const vlf::CameraPath path = vlf::load_camera_path(o.path);
    for (const auto& k : path.keyframes) vlf::validate_camera(k.camera, o.path);
    if (o.format != "png" && o.format != "exr")
        throw vlf::ParameterError("--format: '" + o.format + "' (expected png or exr)");
    const fs::path dir(o.output);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir, ec))
        throw vlf::Error(o.output + ": cannot create the output directory");
    std::vector<double> seconds;
    vlf::Progress bar("frames", path.frames, vlf::Progress::stderr_is_terminal());
    for (int k = 0; k < path.frames; ++k) {
        const vlf::Stopwatch frame_time;
        const vlf::Image im = renderer.render(path.frame(k), rs);
        seconds.push_back(frame_time.seconds());
        vlf::write_image((dir / fmt::format("frame_{:04d}.{}", k, o.format)).string(), im,
                         o.exposure);
        bar.advance();
    }
    bar.finish();
    std::vector<double> fps;
    for (double s : seconds) fps.push_back(s > 0 ? 1.0 / s : 0.0);
    std::sort(fps.begin(), fps.end());
    const size_t n = fps.size();
    const double median = n % 2 ? fps[n / 2] : 0.5 * (fps[n / 2 - 1] + fps[n / 2]);
    std::printf("walkthrough: %d frames %dx%d (%s) in %s: fps min %.2f median %.2f max %.2f\n",
                path.frames, rs.width, rs.height, vlf::to_string(rs.mode).c_str(), o.output.c_str(),
                fps.front(), median, fps.back());
    return 0;
}

int run(const Options& o) {
    // Validate every cheap option before the (possibly long) bundle read.
    vlf::RenderSettings rs;
    rs.width = o.size.first;
    rs.height = o.size.second;
    rs.mode = vlf::render_mode_from_string(o.mode);
    if (o.spp < 1) throw vlf::ParameterError("--spp: must be at least 1");
    if (o.threads < 0) throw vlf::ParameterError("--threads: must be >= 0");
    if (o.max_depth < 0) throw vlf::ParameterError("--max-depth: must be >= 0");
    if (o.pixel_samples < 1 || o.pixel_samples > kMaxPixelSamples)
        throw vlf::ParameterError(
            fmt::format("--pixel-samples: {} outside 1..{}", o.pixel_samples, kMaxPixelSamples));
    if (o.pixel_samples != 1 && o.interactive)
        throw vlf::ParameterError("--pixel-samples: not used by --interactive");
    rs.spp = o.spp;
    if (!(o.light_paths >= 0.0 && o.light_paths <= 1e3))
        throw vlf::ParameterError(
            fmt::format("--light-paths: {} outside 0..1000 per eye path", o.light_paths));
    rs.light_paths_per_sample = o.light_paths;
    rs.pixel_samples = o.pixel_samples;
    rs.max_depth = o.max_depth;
    rs.seed = o.seed;
    if (!std::isfinite(o.exposure)) throw vlf::ParameterError("--exposure: must be finite");
    if (!o.interactive && o.output.empty()) throw vlf::ParameterError("-o: an output is required");
    if (!o.path.empty()) {
        if (fs::exists(o.output) && !fs::is_directory(o.output))
            throw vlf::Error(
                o.output +
                ": exists and is not a directory (--path writes frames into a directory)");
    } else if (!o.output.empty()) {
        const std::string ext = vlf::lower_extension(o.output);
        if (ext != ".exr" && ext != ".png")
            throw vlf::ParameterError("-o: " + o.output + ": unknown image extension '" + ext +
                                      "' (use .exr or .png)");
        check_writable_dir(fs::path(o.output).parent_path(), "-o");
    }
    // The reference is small and read before the bundle, so a wrong size fails at once.
    vlf::Image reference;
    if (!o.reference.empty()) {
        if (!o.path.empty() || o.interactive)
            throw vlf::ParameterError("--reference: only with a single image (-o IMAGE)");
        reference = vlf::read_exr(o.reference);
        if (reference.width != rs.width || reference.height != rs.height)
            throw vlf::ParameterError(
                fmt::format("--reference: {} is {}x{}, the image {}x{} (render with --size {}x{})",
                            o.reference, reference.width, reference.height, rs.width, rs.height,
                            reference.width, reference.height));
    }

    const vlf::ThreadLimit limit(o.threads);
    const vlf::Stopwatch load_time;
    const vlf::Bake bake = vlf::read_bake(o.bake);
    const vlf::Renderer renderer(bake);
    std::printf("walkthrough: loaded %s in %.3f s\n", o.bake.c_str(), load_time.seconds());
    if (!o.path.empty()) {
        if (!o.camera.empty() || o.has_eye || o.has_look_at)
            throw vlf::ParameterError("--path: cannot be combined with --camera/--eye/--look-at");
        return run_path(o, renderer, rs);
    }
    const vlf::Camera cam = choose_camera(o, bake.scene);
    if (o.interactive) {
#ifdef VLF_HAVE_INTERACTIVE
        return vlf_run_interactive(renderer, cam, rs.width, rs.height);
#else
        throw vlf::Error("--interactive: this build has no window support (GLFW not found)");
#endif
    }
    // A view that sees mostly the backs of faces renders mostly black: say why.
    if (const double backs = renderer.back_face_fraction(cam, 32); backs > 0.5)
        std::fprintf(stderr,
                     "walkthrough: warning: %.0f%% of the view sees the backs of one-sided faces "
                     "(black): is camera '%s' inside a wall or outside the room?\n",
                     100.0 * backs, cam.name.c_str());
    const vlf::Stopwatch render_time;
    const vlf::Image im = renderer.render(cam, rs);
    const double s = render_time.seconds();
    vlf::write_image(o.output, im, o.exposure);
    if (!o.reference.empty()) {
        const vlf::PixelMask emitters =
            renderer.emitter_mask(cam, rs.width, rs.height, kEmitterMaskSamples);
        const vlf::ImageError e = vlf::image_error(im, reference, emitters);
        std::printf(
            "walkthrough: against %s: relative RMSE %.5f whole image, %.5f away from emitters "
            "(%zu of %zu pixels)\n",
            o.reference.c_str(), e.rmse, e.rmse_away, e.away_pixels, e.pixels);
        std::printf(
            "walkthrough: mean ratio image/reference away from emitters (R G B): %.4f %.4f "
            "%.4f\n",
            e.ratio_away.x, e.ratio_away.y, e.ratio_away.z);
    }
    std::printf(
        "walkthrough: %s %dx%d (%s%s) in %.3f s -> %s\n", cam.name.c_str(), rs.width, rs.height,
        vlf::to_string(rs.mode).c_str(),
        rs.mode == vlf::RenderMode::Pathtrace ? fmt::format(", {} spp", rs.spp).c_str() : "", s,
        o.output.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    vlf::restart_with_heap_settings(argv);
    Options o;
    CLI::App app{
        "walkthrough: render views of a VLF bake by lookup (Khanna et al., VLF §6).\n"
        "Example: walkthrough out/cornell.vlf --camera default -o out/cornell.png"};
    app.add_option("bake", o.bake, "Bake bundle written by propagate (OUT.vlf)")->required();
    app.add_option("--camera", o.camera, "Named camera of the scene (default: the first)");
    CLI::Option* eye = add_vec3(app, "--eye", o.eye, "Eye position x,y,z (scene units)");
    CLI::Option* look_at =
        add_vec3(app, "--look-at", o.look_at, "Point looked at x,y,z (scene units)");
    CLI::Option* up = add_vec3(app, "--up", o.up, "Up vector x,y,z");
    CLI::Option* fov = app.add_option("--fov", o.fov, "Vertical field of view, degrees");
    app.add_option("--size", o.size, "Image size WxH, e.g. 640x480")
        ->delimiter('x')
        ->check(kImageSide)
        ->type_name("WxH")
        ->default_str("512x512");
    app.add_option("--mode", o.mode, "rays | texture | raytrace | pathtrace")
        ->capture_default_str();
    app.add_option("--spp", o.spp, "Samples per pixel (pathtrace)")->capture_default_str();
    app.add_option("--light-paths", o.light_paths,
                   "Pathtrace: light paths from delta lights per eye path (their caustics "
                   "through glass and mirrors; 0 = none)")
        ->capture_default_str();
    app.add_option("--pixel-samples", o.pixel_samples,
                   "K: KxK rays per pixel, box-filtered (lookup modes; 1 = pixel centre)")
        ->capture_default_str();
    app.add_option("--max-depth", o.max_depth,
                   "Mirror bounces (raytrace and the lookup modes' fallback)")
        ->capture_default_str();
    app.add_option("--seed", o.seed, "Random seed (pathtrace)")->capture_default_str();
    app.add_option("--threads", o.threads, "Worker threads (0 = all cores)")->capture_default_str();
    app.add_option("--exposure", o.exposure, "Exposure in stops for PNG output")
        ->capture_default_str();
    app.add_option("--path", o.path, "Camera path (JSON keyframes); -o is then a directory");
    app.add_option("--format", o.format, "Frame format with --path: png | exr")
        ->capture_default_str();
    app.add_option("-o,--output", o.output, "Image to write (.exr linear, .png tone-mapped)");
    app.add_option("--reference", o.reference,
                   "Reference EXR of the same view and size: print the relative RMSE (whole "
                   "image and away from emitters) and the mean ratio away from emitters");
    app.add_flag("--interactive", o.interactive, "Open the interactive window (GLFW)");
    return vlf::cli_main(app, argc, argv, "walkthrough", [&] {
        o.has_eye = eye->count() > 0;
        o.has_look_at = look_at->count() > 0;
        o.has_up = up->count() > 0;
        o.has_fov = fov->count() > 0;
        return run(o);
    });
}
