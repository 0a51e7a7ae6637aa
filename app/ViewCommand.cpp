// `sphsplat view CACHE`: a window that plays a cache with the splat renderer. Space plays and
// pauses, Left/Right step, PageUp/PageDown jump 10 frames, Home/End go to the ends, a click on the
// timeline bar seeks, M switches point/quad splats, dragging orbits, the wheel zooms, S saves a
// screenshot, Esc or Q quits. The frame, time and mode are drawn on the picture and in the title.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/CliChecks.h"
#include "app/Commands.h"
#include "io/MessageText.h"
#include "io/cache/CacheReader.h"
#include "io/exports/Png.h"
#include "job/CacheRain.h"
#include "job/CacheRendering.h"
#include "job/CacheScene.h"
#include "render/compose/SceneFrame.h"
#include "render/frame/HudText.h"
#include "render/frame/ReadPicture.h"
#include "render/gl/GlContext.h"
#include "sim/InputError.h"
#include "sim/scene/Camera.h"

namespace sph::app {
namespace {

struct ViewOptions {
  std::string cache;
  std::string splat = "quad";
  std::string frame = "0";
  double speed = 1.0;
  std::string screenshot;
  int exitAfter = 0;
  int width = 1280, height = 720;
  std::vector<std::string> overrides;
};

// What the user controls; everything else follows from it.
struct ViewerState {
  std::size_t frame = 0, frames = 1;
  bool playing = false;
  render::splat::SplatKind kind = render::splat::SplatKind::Quad;
  // Orbit around `target`: distance (m), yaw and pitch (rad).
  Vec3 target = Vec3::Zero();
  float distance = 1, yaw = 0, pitch = 0;
  bool dragging = false;
  bool touched = false;  // the user moved the camera: stop following the scene's camera path
  double lastX = 0, lastY = 0;
  bool quit = false, screenshot = false;
  bool frameChanged = true;

  void seek(long long f) {
    const long long last = static_cast<long long>(frames) - 1;
    const std::size_t next = static_cast<std::size_t>(std::max(0LL, std::min(f, last)));
    frameChanged |= next != frame;
    frame = next;
  }
  scene::CameraDesc camera(const scene::CameraDesc& lens) const {
    scene::CameraDesc c = lens;
    c.target = target;
    c.position = target + distance * Vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                          std::cos(pitch) * std::cos(yaw));
    c.up = Vec3::UnitY();
    c.near = std::max(1e-4f, 0.01f * distance);
    c.far = 100.0f * distance;
    return c;
  }
};

void saveScreenshot(const std::string& path, int width, int height) {
  const render::frame::RenderImage shot = render::frame::readWindow(width, height);
  io::exports::writePng(path, width, height, shot.rgb.data());
  io::sayWritten(path);
}

int view(const ViewOptions& o) {
  io::cache::CacheReader reader(o.cache);
  const scene::Scene scene = job::sceneOfCache(reader.summary(), o.overrides);
  if (reader.frameCount() == 0)
    throw InputError(o.cache + ": the cache has no complete frame to show");
  scene::RenderDesc desc = scene.render ? *scene.render : scene::RenderDesc{};
  render::gl::GlWindowOptions wo;
  wo.width = o.width, wo.height = o.height;
  wo.title = "sphsplat view - " + scene.name;
  render::gl::GlContext window = render::gl::GlContext::window(wo);
  render::compose::SceneFrame sceneFrame(scene, desc, [&] {
    const auto b = reader.readBoundary();
    job::checkPositions(b[0], b[1], b[2], scene, "the boundary", o.cache);
    return std::array<std::vector<float>, 3>{b[0], b[1], b[2]};
  });
  render::lights::SceneLights* const lights = sceneFrame.lights();
  // Rain (a rain section): the drops the run stored, else regenerated (job/CacheRain.h), and kept
  // where the camera looks when the user flies it (render/rain/SceneRain.h).
  render::rain::SceneRain* const rain = sceneFrame.rain();

  const io::cache::FieldSet xyz = job::fieldsToDraw(scene);
  ViewerState s;
  s.frames = reader.frameCount();
  s.frame = job::parseOneFrame(o.frame, s.frames, "--frame");
  s.kind = *scene::parseEnum<render::splat::SplatKind>(o.splat);
  const Particles first = reader.readFrame(s.frame, xyz);
  job::checkPositions(first.x, first.y, first.z, scene, "frame " + std::to_string(s.frame), o.cache);
  const scene::CameraDesc lens =
      scene.camera ? *scene.camera
                   : render::splat::framingCamera(first, static_cast<float>(o.width) / o.height);
  s.target = lens.target;
  const Vec3 offset = lens.position - lens.target;
  s.distance = offset.norm();
  s.yaw = std::atan2(offset.x(), offset.z());
  s.pitch = std::asin(std::clamp(offset.y() / s.distance, -1.0f, 1.0f));

  const int timeline = 6;  // pixels: the seek bar at the bottom
  window.setInputHandler([&](const render::gl::InputEvent& e) {
    using T = render::gl::InputEvent::Type;
    const auto size = window.framebufferSize();
    if (e.type == T::Key && e.press) {
      switch (e.key) {
        case render::gl::keys::kSpace:
          s.playing = !s.playing;
          break;
        case render::gl::keys::kRight:
          s.playing = false, s.seek(static_cast<long long>(s.frame) + 1);
          break;
        case render::gl::keys::kLeft:
          s.playing = false, s.seek(static_cast<long long>(s.frame) - 1);
          break;
        case render::gl::keys::kPageUp:
          s.seek(static_cast<long long>(s.frame) + 10);
          break;
        case render::gl::keys::kPageDown:
          s.seek(static_cast<long long>(s.frame) - 10);
          break;
        case render::gl::keys::kHome:
          s.seek(0);
          break;
        case render::gl::keys::kEnd:
          s.seek(static_cast<long long>(s.frames) - 1);
          break;
        case 'M':
          s.kind = s.kind == render::splat::SplatKind::Quad ? render::splat::SplatKind::Point
                                                            : render::splat::SplatKind::Quad;
          break;
        case 'S':
          s.screenshot = true;
          break;
        case 'Q':
        case render::gl::keys::kEscape:
          s.quit = true;
          break;
        default:
          break;
      }
    } else if (e.type == T::MouseButton && e.key == 0) {
      if (e.press && size[1] > 0 && e.y >= size[1] - 3 * timeline) {  // click on the timeline: seek
        s.seek(std::lround(e.x / std::max(size[0], 1) * (static_cast<double>(s.frames) - 1)));
      } else {
        s.dragging = e.press, s.lastX = e.x, s.lastY = e.y;
        s.touched = true;
      }
    } else if (e.type == T::CursorMove && s.dragging) {
      s.yaw -= static_cast<float>(e.x - s.lastX) * 0.01f;
      s.pitch = std::clamp(s.pitch + static_cast<float>(e.y - s.lastY) * 0.01f, -1.5f, 1.5f);
      s.lastX = e.x, s.lastY = e.y;
    } else if (e.type == T::Scroll) {
      s.distance *= std::pow(0.9f, static_cast<float>(e.y));
      s.touched = true;
    }
  });
  std::printf(
      "%s: %zu frames. Space play/pause, Left/Right step, PgUp/PgDn 10 frames, Home/End, click "
      "the\n"
      "  bottom bar to seek, M point/quad, drag to orbit, wheel to zoom, S screenshot, Esc quit.\n",
      scene.name.c_str(), s.frames);

  const double frameSeconds =
      1.0 / (reader.summary().fps > 0 ? reader.summary().fps : 30.0) / o.speed;
  render::frame::HudText hud;
  auto lastAdvance = std::chrono::steady_clock::now();
  int drawn = 0;
  // The particle lights (lights.cull): culled to the camera while it follows the scene's camera
  // path, where each frame brings its own accumulation anyway; once the user orbits or zooms,
  // the whole volume, accumulated once a frame, so that moving the camera costs nothing.
  Particles shown;
  float culledAspect = 0;  // the picture's aspect the volume is culled for; 0: whole volume
  while (!window.shouldClose() && !s.quit) {
    window.pollEvents();
    const auto now = std::chrono::steady_clock::now();
    if (s.playing && std::chrono::duration<double>(now - lastAdvance).count() >= frameSeconds) {
      s.seek(s.frame + 1 < s.frames ? static_cast<long long>(s.frame) + 1 : 0);
      lastAdvance = now;
    }
    const double time = reader.summary().frames[s.frame].time;
    // The scene's camera path until the user drags or zooms; then the user's orbit.
    const scene::CameraDesc camera =
        s.touched ? s.camera(lens) : cameraAt(lens, scene.cameraPath, time);
    const auto size = window.framebufferSize();
    const float aspect = static_cast<float>(size[0]) / static_cast<float>(std::max(size[1], 1));
    const bool cullLights = lights && scene.lights->cull && !s.touched;
    if (s.frameChanged) {
      shown = reader.readFrame(s.frame, xyz);
      job::checkPositions(shown.x, shown.y, shown.z, scene, "frame " + std::to_string(s.frame), o.cache);
      sceneFrame.setWater(shown);
      if (rain) job::showCachedRain(*rain, reader, s.frame, time, shown);
    }
    if (lights &&
        (s.frameChanged || (culledAspect != 0 && (!cullLights || aspect != culledAspect)))) {
      sceneFrame.updateLights(shown, time, cullLights ? &camera : nullptr, aspect);
      culledAspect = cullLights ? aspect : 0;
    }
    s.frameChanged = false;
    if (rain) rain->follow(camera);
    const render::splat::FrameTimings t = sceneFrame.drawToScreen(s.kind, camera, size[0], size[1]);
    // The timeline: the played part up to and including this frame.
    render::frame::drawTimeline(size[0], timeline,
                                static_cast<int>(size[0] * (s.frame + 1.0) / s.frames));
    char status[128], timing[64];
    std::snprintf(status, sizeof status, "frame %zu/%zu  t = %.3f s%s", s.frame, s.frames - 1,
                  reader.summary().frames[s.frame].time, s.playing ? "" : "  paused");
    std::snprintf(timing, sizeof timing, "%s splats  %.0f ms", scene::enumName(s.kind),
                  1e3 * t.total());
    // On the picture (window managers hide or cut titles), and in the title bar.
    hud.draw({scene.name, status, timing}, size[0], size[1]);
    window.setTitle("sphsplat view - " + scene.name + " - " + status + " - " + timing);
    ++drawn;
    const bool last = o.exitAfter > 0 && drawn >= o.exitAfter;
    if (s.screenshot || (last && !o.screenshot.empty())) {
      saveScreenshot(
          o.screenshot.empty() ? io::exports::framePngName("sphsplat_view", s.frame) : o.screenshot,
          size[0], size[1]);
      s.screenshot = false;
    }
    window.swapBuffers();
    if (last) break;
  }
  return job::kOk;
}

}  // namespace

std::function<int()> addViewCommand(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view",
                                     "Play a cache in a window (needs a display): play/pause, "
                                     "step, scrub, orbit, zoom, point/quad");
  cmd->add_option("cache", o->cache, "HDF5 cache written by `sphsplat run`")->required();
  cmd->add_option("--splat", o->splat,
                  "Splats to start with: " + scene::enumNameList<render::splat::SplatKind>())
      ->check(CLI::IsMember(scene::enumNames<render::splat::SplatKind>()))
      ->capture_default_str();
  cmd->add_option("--frame", o->frame, "Frame to start at (index or last)")->capture_default_str();
  cmd->add_option("--speed", o->speed, "Playback speed (1 = the cache's frame rate), up to 1000")
      ->check(positiveUpTo(1000, "times the cache's frame rate"))
      ->capture_default_str();
  cmd->add_option("--width", o->width, "Window width")
      ->check(integerIn(64, 8192))
      ->capture_default_str();
  cmd->add_option("--height", o->height, "Window height")
      ->check(integerIn(64, 8192))
      ->capture_default_str();
  cmd->add_option("--screenshot", o->screenshot,
                  "File for the S key's screenshot (default: sphsplat_view_NNNNN.png)");
  cmd->add_option(
         "--exit-after", o->exitAfter,
         "Quit after drawing N frames (scripts and tests; with --screenshot, saves the last)")
      ->check(integerIn(0, 1000000000));
  cmd->add_option("--set", o->overrides,
                  "Edit the recorded scene, e.g. --set render.projection=eq6 for the paper's rule "
                  "(repeatable)");
  cmd->footer(
      "Keys: Space play/pause, Left/Right step, PageUp/PageDown 10 frames, Home/End, M "
      "point/quad,\n"
      "S screenshot, Esc or Q quit; drag to orbit, wheel to zoom, click the bottom bar to seek.\n"
      "Needs a display and OpenGL 4.5. Exit codes: 0 done, 2 bad cache or flags, 4 no usable\n"
      "OpenGL or display.");
  return [o, cmd]() { return cmd->parsed() ? view(*o) : -1; };
}

}  // namespace sph::app
