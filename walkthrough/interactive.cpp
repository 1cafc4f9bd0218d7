// interactive.cpp — the GLFW walkthrough window (VLF §6; DESIGN §7). See interactive.hpp
// for the controls and the automation variables.
//
// The renderer produces linear radiance on the CPU; the window tone-maps it with the PNG
// tone map (vlf::tone_map_srgb8: exposure, Reinhard, sRGB), draws the status text into the
// 8-bit image with stb_easy_font and shows it as one texture on a full-window quad
// (OpenGL 2.1 is enough). A new image is rendered only when the view changed (camera, mode,
// size) or a still pathtrace view accumulates more samples; otherwise the window sleeps in
// glfwWaitEventsTimeout.
#include "interactive.hpp"

#include <GLFW/glfw3.h>  // also includes <GL/gl.h>
#include <fmt/format.h>
#include <stb_image_write.h>  // implementation lives in libstb: do not define the macro
// stb_easy_font is header-only with static functions, some of which this file does not use.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "vlf/core/error.hpp"
#include "vlf/render/image_io.hpp"  // tone_map_srgb8: the PNG tone map, reused for display
#include "vlf/render/render.hpp"

namespace {

using vlf::Camera;
using vlf::Image;
using vlf::RenderMode;
using vlf::Vec3;

// VLF §6.3: the progressive mode shows the cheap texture lookup while the user moves and
// switches to the ray-traced specular image once the camera has been still this long.
constexpr double kStillSeconds = 0.3;
// Pathtrace in the window: few samples per frame, accumulated while the view is still.
constexpr int kPathtraceSppMoving = 1;
constexpr int kPathtraceSppStill = 2;
constexpr int kPathtraceMaxSpp = 1024;
// Automation: a virtual clock so the scripted run does not depend on how fast it renders.
constexpr double kAutomationFrameSeconds = 0.1;
constexpr double kLookRadiansPerPixel = 0.004;
constexpr double kExposureStep = 0.5;  // stops per +/- press

// ---------------------------------------------------------------------------------------
// GLFW errors: the last message, used when a call fails.

std::string g_glfw_error;

void on_glfw_error(int code, const char* description) {
    g_glfw_error = fmt::format("{} (GLFW error 0x{:x})", description ? description : "?", code);
}

// ---------------------------------------------------------------------------------------
// Fly camera: yaw about the start camera's up vector, pitch towards it. User units.

class FlyCamera {
  public:
    explicit FlyCamera(const Camera& c) : m_start(c) { reset(); }

    void reset() {
        m_eye = m_start.eye;
        m_up = safe_normalize(m_start.up, Vec3(0, 1, 0));
        Vec3 f = safe_normalize(m_start.look_at - m_start.eye, Vec3(0, 0, 1));
        m_focus = std::max(glm::length(m_start.look_at - m_start.eye), 1e-6);
        Vec3 h = f - glm::dot(f, m_up) * m_up;  // horizontal part of the view direction
        if (glm::length(h) < 1e-9) {            // looking straight along up: pick any
            h = std::abs(m_up.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 0, 1);
            h -= glm::dot(h, m_up) * m_up;
        }
        m_fwd0 = glm::normalize(h);
        m_right0 = glm::normalize(glm::cross(m_fwd0, m_up));
        m_yaw = 0.0;
        m_pitch = std::asin(std::clamp(glm::dot(f, m_up), -1.0, 1.0));
        clamp_pitch();
    }

    Vec3 forward() const { return std::cos(m_pitch) * horizontal() + std::sin(m_pitch) * m_up; }
    Vec3 right() const {
        return std::cos(m_yaw) * m_right0 - std::sin(m_yaw) * m_fwd0;  // horizontal x up
    }
    const Vec3& up() const { return m_up; }

    void move(const Vec3& delta) { m_eye += delta; }
    void look(double d_yaw, double d_pitch) {
        m_yaw += d_yaw;
        m_pitch += d_pitch;
        clamp_pitch();
    }

    Camera camera() const {
        Camera c = m_start;
        c.name = "interactive";
        c.eye = m_eye;
        c.look_at = m_eye + forward() * m_focus;
        c.up = m_up;
        return c;
    }

  private:
    static Vec3 safe_normalize(const Vec3& v, const Vec3& fallback) {
        double l = glm::length(v);
        return l > 1e-12 ? v / l : fallback;
    }
    Vec3 horizontal() const { return std::cos(m_yaw) * m_fwd0 + std::sin(m_yaw) * m_right0; }
    void clamp_pitch() {
        constexpr double lim = 89.0 * vlf::kPi / 180.0;  // keep up and forward apart
        m_pitch = std::clamp(m_pitch, -lim, lim);
    }

    Camera m_start;
    Vec3 m_eye{0.0}, m_up{0, 1, 0}, m_fwd0{0, 0, 1}, m_right0{1, 0, 0};
    double m_yaw = 0.0, m_pitch = 0.0, m_focus = 1.0;
};

// Scene size in user units, for a movement speed that suits both a room in mm and in m.
double scene_extent(const vlf::Renderer& renderer, const Camera& start) {
    const vlf::Scene& s = renderer.bake().scene;
    double e = glm::length(s.user_bounds_max - s.user_bounds_min);
    if (e > 0.0 && std::isfinite(e)) return e;
    if (s.normalisation.scale > 0.0) return 2.0 * std::sqrt(3.0) / s.normalisation.scale;
    return std::max(glm::length(start.look_at - start.eye), 1.0);
}

// ---------------------------------------------------------------------------------------
// The status text, drawn with stb_easy_font: it emits every glyph as axis-aligned quads
// (four vertices of x, y, z floats and four colour bytes, y down), which are filled into
// the image `scale` pixels per font unit.

struct FontVertex {
    float x, y, z;
    uint8_t color[4];
};

// Draws text lines at the top left of an RGB8 image (row 0 at the top) over a darkened
// box, so it stays legible on the bright walls of a lit room.
void draw_text(std::vector<uint8_t>& rgb, int w, int h, const std::vector<std::string>& lines) {
    const int scale = std::max(1, std::min(w / 400, h / 300) + 1);
    const int line_h = 12 * scale, margin = 3 * scale;
    int longest = 0;
    for (const std::string& l : lines) {
        std::string text = l;
        longest = std::max(longest, stb_easy_font_width(text.data()));
    }
    const int box_w = std::min(w, longest * scale + 2 * margin);
    const int box_h = std::min(h, int(lines.size()) * line_h + 2 * margin);
    for (int y = 0; y < box_h; ++y)
        for (int x = 0; x < box_w; ++x)
            for (int c = 0; c < 3; ++c) {
                uint8_t& v = rgb[(size_t(y) * w + x) * 3 + c];
                v = uint8_t(v / 3);
            }
    std::vector<FontVertex> quads(16384);
    for (size_t li = 0; li < lines.size(); ++li) {
        std::string text = lines[li];
        const int n = stb_easy_font_print(0.0f, 0.0f, text.data(), nullptr, quads.data(),
                                          int(quads.size() * sizeof(FontVertex)));
        const int y0 = margin + int(li) * line_h;
        for (int q = 0; q < n; ++q) {
            const FontVertex* v = &quads[size_t(q) * 4];
            const int xa = margin + int(std::lround(v[0].x * scale));
            const int xb = margin + int(std::lround(v[2].x * scale));
            const int ya = y0 + int(std::lround(v[0].y * scale));
            const int yb = y0 + int(std::lround(v[2].y * scale));
            for (int y = std::max(0, std::min(ya, yb)); y < std::min(h, std::max(ya, yb)); ++y)
                for (int x = std::max(0, std::min(xa, xb)); x < std::min(w, std::max(xa, xb));
                     ++x) {
                    uint8_t* p = &rgb[(size_t(y) * w + x) * 3];
                    p[0] = 255, p[1] = 240, p[2] = 120;  // warm yellow, visible on white
                }
        }
    }
}

// ---------------------------------------------------------------------------------------
// OpenGL: the image as one texture on a full-window quad (fixed function, GL 2.1).

class Display {
  public:
    Display() {
        glGenTextures(1, &m_texture);
        glBindTexture(GL_TEXTURE_2D, m_texture);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    ~Display() { glDeleteTextures(1, &m_texture); }
    Display(const Display&) = delete;
    Display& operator=(const Display&) = delete;

    void upload(const std::vector<uint8_t>& rgb, int w, int h) {
        glBindTexture(GL_TEXTURE_2D, m_texture);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        if (w != m_w || h != m_h) {
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, w, h, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
            m_w = w, m_h = h;
        } else {
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
        }
    }

    void draw(int fb_w, int fb_h) const {
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_LIGHTING);
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, m_texture);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
        // Image row 0 is the top; texture t = 0 is the first row uploaded.
        glBegin(GL_QUADS);
        glTexCoord2f(0, 1), glVertex2f(-1, -1);
        glTexCoord2f(1, 1), glVertex2f(1, -1);
        glTexCoord2f(1, 0), glVertex2f(1, 1);
        glTexCoord2f(0, 0), glVertex2f(-1, 1);
        glEnd();
        glDisable(GL_TEXTURE_2D);
    }

  private:
    GLuint m_texture = 0;
    int m_w = -1, m_h = -1;
};

// Saves the back buffer (call before swapping) as PNG, rows flipped to top-first.
void save_screenshot(const std::string& path, int w, int h) {
    std::vector<uint8_t> px(size_t(w) * h * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, px.data());
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        throw vlf::Error(fmt::format("{}: glReadPixels failed (GL error 0x{:x})", path, e));
    std::vector<uint8_t> flipped(px.size());
    const size_t row = size_t(w) * 3;
    for (int y = 0; y < h; ++y)
        std::copy_n(&px[size_t(h - 1 - y) * row], row, &flipped[size_t(y) * row]);
    if (!stbi_write_png(path.c_str(), w, h, 3, flipped.data(), int(row)))
        throw vlf::Error(path + ": cannot write the screenshot");
}

// ---------------------------------------------------------------------------------------
// Window state shared with the GLFW key callback.

struct ViewState {
    RenderMode selected = RenderMode::Texture;
    bool progressive = true;
    double exposure = 0.0;  // stops
    bool reset_camera = false;
};

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    auto& v = *static_cast<ViewState*>(glfwGetWindowUserPointer(window));
    auto select = [&](RenderMode m) {
        v.selected = m;
        v.progressive = false;  // an explicit mode choice overrides progressive
    };
    switch (key) {
        case GLFW_KEY_ESCAPE:
            glfwSetWindowShouldClose(window, GLFW_TRUE);
            break;
        case GLFW_KEY_1:
        case GLFW_KEY_KP_1:
            select(RenderMode::Rays);
            break;
        case GLFW_KEY_2:
        case GLFW_KEY_KP_2:
            select(RenderMode::Texture);
            break;
        case GLFW_KEY_3:
        case GLFW_KEY_KP_3:
            select(RenderMode::Raytrace);
            break;
        case GLFW_KEY_4:
        case GLFW_KEY_KP_4:
            select(RenderMode::Pathtrace);
            break;
        case GLFW_KEY_P:
            if (action == GLFW_PRESS) v.progressive = !v.progressive;
            break;
        case GLFW_KEY_EQUAL:
        case GLFW_KEY_KP_ADD:
            v.exposure += kExposureStep;
            break;
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT:
            v.exposure -= kExposureStep;
            break;
        case GLFW_KEY_R:
            v.reset_camera = true;
            break;
        default:
            break;
    }
}

// Continuous input: WASD/QE/Space/Ctrl movement and mouse-drag look. Returns true when the
// camera changed.
class InputPoller {
  public:
    bool apply(GLFWwindow* win, FlyCamera& cam, double dt, double speed) {
        auto down = [&](int k) { return glfwGetKey(win, k) == GLFW_PRESS; };
        Vec3 d{0.0};
        if (down(GLFW_KEY_W)) d += cam.forward();
        if (down(GLFW_KEY_S)) d -= cam.forward();
        if (down(GLFW_KEY_D)) d += cam.right();
        if (down(GLFW_KEY_A)) d -= cam.right();
        if (down(GLFW_KEY_E) || down(GLFW_KEY_SPACE)) d += cam.up();
        if (down(GLFW_KEY_Q) || down(GLFW_KEY_LEFT_CONTROL) || down(GLFW_KEY_RIGHT_CONTROL))
            d -= cam.up();
        bool changed = false;
        if (glm::length(d) > 0.0) {
            const bool fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT);
            cam.move(glm::normalize(d) * speed * (fast ? 4.0 : 1.0) * dt);
            changed = true;
        }
        const bool dragging = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS ||
                              glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        double x = 0, y = 0;
        glfwGetCursorPos(win, &x, &y);
        if (dragging && m_dragging && (x != m_x || y != m_y)) {
            // Drag right turns right, drag up looks up.
            cam.look((x - m_x) * kLookRadiansPerPixel, -(y - m_y) * kLookRadiansPerPixel);
            changed = true;
        }
        m_dragging = dragging, m_x = x, m_y = y;
        m_active = dragging || glm::length(d) > 0.0;
        return changed;
    }
    bool active() const { return m_active; }  // keys held or dragging: keep polling

  private:
    bool m_dragging = false, m_active = false;
    double m_x = 0, m_y = 0;
};

// Per-mode render counts and times, for the automation summary.
struct Stats {
    std::array<int, 4> renders{};
    std::array<double, 4> seconds{};
    double fps = 0.0;  // smoothed 1 / (render + tone map + upload + draw) of new frames
    double last_render_ms = 0.0;

    void add_frame(RenderMode m, double render_s, double frame_s) {
        renders[size_t(m)] += 1;
        seconds[size_t(m)] += render_s;
        last_render_ms = render_s * 1e3;
        const double inst = 1.0 / std::max(frame_s, 1e-6);
        fps = fps == 0.0 ? inst : 0.8 * fps + 0.2 * inst;
    }
};

int automation_frames() {
    const char* s = std::getenv("VLF_INTERACTIVE_FRAMES");
    if (!s || !*s) return 0;
    char* end = nullptr;
    long n = std::strtol(s, &end, 10);
    if (*end != '\0' || n <= 0 || n > 1000000)
        throw vlf::Error(
            fmt::format("VLF_INTERACTIVE_FRAMES: expected a positive integer, got '{}'", s));
    return int(n);
}

std::string mode_label(const ViewState& v, RenderMode shown) {
    if (!v.progressive) return vlf::to_string(shown);
    return fmt::format("progressive: {} ({})", vlf::to_string(shown),
                       shown == RenderMode::Raytrace ? "still" : "moving");
}

}  // namespace

int vlf_run_interactive(const vlf::Renderer& renderer, const vlf::Camera& start, int width,
                        int height) {
    if (width <= 0 || height <= 0)
        throw vlf::Error(fmt::format("interactive window: bad size {}x{}", width, height));
    const int auto_frames = automation_frames();
    const char* shot_env = std::getenv("VLF_INTERACTIVE_SCREENSHOT");
    const std::string screenshot = shot_env ? shot_env : "";

    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit())
        throw vlf::Error("interactive window: cannot initialise GLFW: " + g_glfw_error +
                         " (needs an X display; try xvfb-run)");
    struct Terminate {
        ~Terminate() { glfwTerminate(); }
    } terminate_glfw;

    // OpenGL 2.1 (compatibility) is all the fixed-function quad needs.
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    std::unique_ptr<GLFWwindow, void (*)(GLFWwindow*)> window(
        glfwCreateWindow(width, height, "VLF walkthrough", nullptr, nullptr), glfwDestroyWindow);
    if (!window) throw vlf::Error("interactive window: cannot open a window: " + g_glfw_error);
    GLFWwindow* win = window.get();
    glfwMakeContextCurrent(win);
    glfwSwapInterval(0);  // rendering is the bottleneck; do not wait for vsync on top

    ViewState view;
    glfwSetWindowUserPointer(win, &view);
    glfwSetKeyCallback(win, on_key);

    FlyCamera cam(start);
    const double speed = 0.3 * scene_extent(renderer, start);  // user units per second
    Display display;  // after the window: destroyed while the context is still current
    InputPoller input;
    Stats stats;

    if (!auto_frames)
        std::printf(
            "walkthrough: WASD move, Q/E down/up, drag to look, 1-4 rays/texture/"
            "raytrace/pathtrace, P progressive, +/- exposure, R reset, Esc quit\n");

    Image linear;  // the current view, linear radiance (pathtrace: running mean)
    int accumulated_spp = 0;
    RenderMode shown = RenderMode::Texture;
    bool have_image = false;
    double shown_exposure = std::numeric_limits<double>::quiet_NaN();
    std::vector<uint8_t> ldr, frame;  // tone-mapped view; view + text
    double last_move = -1e30, prev_time = 0.0, last_title = -1e30;
    const double t_start = glfwGetTime();

    for (int n = 0;; ++n) {
        if (auto_frames && n >= auto_frames) break;
        const bool busy = auto_frames || input.active() || !have_image ||
                          (view.progressive && shown != RenderMode::Raytrace) ||
                          (shown == RenderMode::Pathtrace && accumulated_spp < kPathtraceMaxSpp);
        if (busy)
            glfwPollEvents();
        else
            glfwWaitEventsTimeout(0.1);  // nothing to render: sleep until input
        if (glfwWindowShouldClose(win)) break;

        const double now = auto_frames ? n * kAutomationFrameSeconds : glfwGetTime() - t_start;
        const double dt = std::clamp(now - prev_time, 0.0, 0.25);
        prev_time = now;

        bool moved = false;
        if (auto_frames) {
            // Scripted: strafe and turn a little during the first half, then hold still.
            if (n < auto_frames / 2) {
                cam.move(cam.right() * (0.004 * speed / 0.3));
                cam.look(0.005, 0.0);
                moved = true;
            }
        } else {
            moved = input.apply(win, cam, dt, speed);
        }
        if (view.reset_camera) {
            cam.reset();
            view.reset_camera = false;
            moved = true;
        }
        if (moved) last_move = now;

        // VLF §6.3 progressive: texture while moving, raytrace once still long enough.
        const bool still = now - last_move >= kStillSeconds - 1e-9;
        const RenderMode target =
            view.progressive ? (still ? RenderMode::Raytrace : RenderMode::Texture) : view.selected;

        int fb_w = 0, fb_h = 0;
        glfwGetFramebufferSize(win, &fb_w, &fb_h);
        if (fb_w <= 0 || fb_h <= 0) continue;  // minimised

        const bool fresh = !have_image || moved || target != shown || fb_w != linear.width ||
                           fb_h != linear.height;
        const bool accumulate =
            !fresh && target == RenderMode::Pathtrace && accumulated_spp < kPathtraceMaxSpp;
        const double t0 = glfwGetTime();
        double render_s = 0.0;
        if (fresh || accumulate) {
            vlf::RenderSettings rs;
            rs.width = fb_w;
            rs.height = fb_h;
            rs.mode = target;
            rs.spp = fresh ? kPathtraceSppMoving : kPathtraceSppStill;
            rs.seed = fresh ? 1 : uint64_t(accumulated_spp) + 1;  // new streams per pass
            Image img = renderer.render(cam.camera(), rs);
            render_s = glfwGetTime() - t0;
            const int spp = target == RenderMode::Pathtrace ? rs.spp : 1;
            if (accumulate) {  // running mean, weighted by samples
                const double a = double(spp) / double(accumulated_spp + spp);
                for (size_t i = 0; i < linear.pixels.size(); ++i)
                    linear.pixels[i] += (img.pixels[i] - linear.pixels[i]) * a;
                accumulated_spp += spp;
            } else {
                linear = std::move(img);
                accumulated_spp = spp;
            }
            shown = target;
            have_image = true;
            shown_exposure = std::numeric_limits<double>::quiet_NaN();  // re-tone-map
        }
        if (!(shown_exposure == view.exposure)) {
            ldr = vlf::tone_map_srgb8(linear, view.exposure);
            shown_exposure = view.exposure;
        }

        std::string label = mode_label(view, shown);
        if (shown == RenderMode::Pathtrace) label += fmt::format(" {} spp", accumulated_spp);
        frame = ldr;
        draw_text(frame, linear.width, linear.height,
                  {label, fmt::format("{:.1f} fps  {:.0f} ms  exp {:+.1f}", stats.fps,
                                      stats.last_render_ms, view.exposure)});
        display.upload(frame, linear.width, linear.height);
        display.draw(fb_w, fb_h);
        if (auto_frames && n == auto_frames - 1 && !screenshot.empty())
            save_screenshot(screenshot, fb_w, fb_h);
        glfwSwapBuffers(win);
        if (fresh || accumulate) stats.add_frame(shown, render_s, glfwGetTime() - t0);

        if (now - last_title > 0.25 || fresh) {
            glfwSetWindowTitle(
                win, fmt::format("VLF walkthrough - {} - {:.1f} fps - exposure {:+.1f}", label,
                                 stats.fps, view.exposure)
                         .c_str());
            last_title = now;
        }
    }

    if (auto_frames) {
        std::string per_mode;
        for (RenderMode m :
             {RenderMode::Rays, RenderMode::Texture, RenderMode::Raytrace, RenderMode::Pathtrace}) {
            const size_t i = size_t(m);
            if (!stats.renders[i]) continue;
            per_mode += fmt::format(" {}={} ({:.1f} ms)", vlf::to_string(m), stats.renders[i],
                                    1e3 * stats.seconds[i] / stats.renders[i]);
        }
        std::printf("interactive: frames=%d size=%dx%d renders:%s fps=%.1f\n", auto_frames,
                    linear.width, linear.height, per_mode.c_str(), stats.fps);
    }
    return 0;
}
