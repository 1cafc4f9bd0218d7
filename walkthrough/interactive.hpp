// interactive.hpp — the optional interactive walkthrough window (GLFW; VLF §6, DESIGN §7).
//
// Built only when CMake finds GLFW 3.3 and OpenGL (option VLF_BUILD_INTERACTIVE); callers
// guard the call with #ifdef VLF_HAVE_INTERACTIVE.
//
// Controls: WASD move, Q/E (or Ctrl/Space) down/up, Shift faster, drag with a mouse button
// held to look around; 1 rays, 2 texture, 3 raytrace, 4 pathtrace (accumulates while the
// camera is still); P progressive (the default: texture while moving, raytrace once the
// camera has been still for 0.3 s — VLF §6.3); +/- exposure by half a stop; R resets the
// camera; Esc quits. The mode, fps and exposure are shown in the title and in the image.
//
// Automation (used by tests/interactive_test.cmake):
//   VLF_INTERACTIVE_FRAMES=n      show n frames on a scripted camera move, then exit
//                                 (first half moving, second half still, on a virtual
//                                 clock of 0.1 s per frame so both progressive paths run);
//                                 prints one summary line on stdout;
//   VLF_INTERACTIVE_SCREENSHOT=p  save the last framebuffer as PNG at p (glReadPixels).
#pragma once

namespace vlf {
class Renderer;
struct Camera;
}  // namespace vlf

// Runs the window until Esc / close (or the automation frame count). `start` is in the
// scene's user units; width x height is the initial window and render size in pixels.
// Returns the exit code (0). Throws vlf::Error when no window can be opened (no DISPLAY,
// no OpenGL) or the screenshot cannot be written.
int vlf_run_interactive(const vlf::Renderer& renderer, const vlf::Camera& start, int width,
                        int height);
