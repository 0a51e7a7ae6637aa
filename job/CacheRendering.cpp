#include "job/CacheRendering.h"

#include <cerrno>
#include <cstdlib>

#include "job/CacheScene.h"
#include "io/cache/CacheWriter.h"
#include "io/MessageText.h"
#include "render/lights/SceneLights.h"
#include "sim/scene/EnumNames.h"
#include "sim/InputError.h"

namespace sph::job {
namespace {

void applySize(const std::string& size, scene::RenderDesc& d) {
  if (size.empty()) return;
  // WIDTHxHEIGHT, each 16-8192: strtol with its end checked (sscanf's %d overflows silently).
  auto dimension = [](const std::string& text, long& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtol(text.c_str(), &end, 10);
    return !text.empty() && errno == 0 && *end == 0 && value >= 16 && value <= 8192;
  };
  const std::size_t x = size.find_first_of("xX");
  long w = 0, h = 0;
  if (x == std::string::npos || !dimension(size.substr(0, x), w) ||
      !dimension(size.substr(x + 1), h)) {
    throw InputError(
        "--size: expected WIDTHxHEIGHT between 16 and 8192 pixels, e.g. 960x540, got '" +
        io::printable(size) + "'");
  }
  d.width = static_cast<int>(w), d.height = static_cast<int>(h);
}

}  // namespace

CacheRendering::CacheRendering(const std::string& path_, const std::vector<std::string>& overrides,
                               const std::string& splat, const std::string& size)
    : path(path_),
      open(std::make_unique<io::cache::CacheReader>(path_)),
      summary(open->summary()),
      scene(sceneOfCache(summary, overrides)) {
  desc = scene.render ? *scene.render : scene::RenderDesc{};
  if (!splat.empty()) desc.splat = *scene::parseEnum<scene::RenderDesc::Splat>(splat);
  applySize(size, desc);
  cameraFromScene = scene.camera.has_value();
  if (cameraFromScene) camera = *scene.camera;
}

io::cache::CacheReader& CacheRendering::reader() {
  if (!open) open = std::make_unique<io::cache::CacheReader>(path);
  return *open;
}

io::cache::FieldSet fieldsToDraw(const scene::Scene& scene) {
  io::cache::FieldSet fields;
  for (auto f : {io::cache::Field::X, io::cache::Field::Y, io::cache::Field::Z})
    fields.set(static_cast<std::size_t>(f));
  // Lights coloured by speed need the velocities (docs/lights.md, "Replay").
  if (render::lights::lightsNeedVelocity(scene))
    for (auto f : {io::cache::Field::VX, io::cache::Field::VY, io::cache::Field::VZ})
      fields.set(static_cast<std::size_t>(f));
  return fields;
}

Particles CacheRendering::positions(std::size_t frame) {
  Particles p = reader().readFrame(frame, fieldsToDraw(scene));
  checkPositions(p.x, p.y, p.z, scene, "frame " + std::to_string(frame), path);
  return p;
}

std::array<std::vector<float>, 3> CacheRendering::boundary() {
  const auto b = reader().readBoundary();
  checkPositions(b[0], b[1], b[2], scene, "the boundary", path);
  return {b[0], b[1], b[2]};
}

void CacheRendering::store(const std::string& renderer, std::size_t frame,
                           const render::frame::RenderImage& image) {
  open.reset();
  std::unique_ptr<io::cache::CacheWriter> writer =
      io::cache::CacheWriter::append(path, frameCount());
  writer->writeRenderedFrame(renderer, frame, image.width, image.height, image.rgb.data());
  writer->close();
}

}  // namespace sph::job
