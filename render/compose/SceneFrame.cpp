#include "render/compose/SceneFrame.h"

#include "render/solids/SceneSolids.h"

namespace sph::render::compose {
namespace {

std::vector<splat::SplatKind> kindsOf(scene::RenderDesc::Splat s) {
  if (s == scene::RenderDesc::Splat::Point) return {splat::SplatKind::Point};
  if (s == scene::RenderDesc::Splat::Quad) return {splat::SplatKind::Quad};
  return {splat::SplatKind::Point, splat::SplatKind::Quad};
}

}  // namespace

SceneFrame::SceneFrame(const scene::Scene& scene, const scene::RenderDesc& desc,
                       const BoundaryPositions& boundary, const SceneParts& parts)
    : renderer_(desc, scene.solver.spacing, scene.solver.restDensity), kinds_(kindsOf(desc.splat)) {
  std::vector<frame::FrameLayer*> layers;
  if (desc.solids == scene::RenderSolids::Opaque) {
    solids_ = solids::sceneSolids(scene);
    layers.push_back(solids_.get());
  } else if (desc.solids == scene::RenderSolids::Points && parts.boundaryPoints) {
    const auto b = boundary();
    renderer_.setBoundary(b[0], b[1], b[2]);
  }
  if (parts.lights && scene.lights) {
    lights_ = std::make_unique<lights::SceneLights>(scene, desc);
    renderer_.setExtraLights(&lights_->volume());
    renderer_.setBackground(lights_->background());
  }
  if (parts.rain) {
    rain_ = rain::SceneRain::create(
        scene, static_cast<float>(desc.width) / static_cast<float>(desc.height));
  }
  if (rain_) {
    layers.push_back(&rain_->layer());
    renderer_.setSpotlight(scene.rain->spotlight);
  }
  renderer_.setLayers(std::move(layers));
}

void SceneFrame::setWater(const Particles& fluid) {
  renderer_.prepare(fluid);
}

double SceneFrame::updateLights(const Particles& fluid, double time,
                                const scene::CameraDesc* camera, float aspect) {
  return lights_ ? lights_->update(fluid, time, camera, aspect) : 0.0;
}

Pictures SceneFrame::draw(const Particles& fluid, double time, const scene::CameraDesc& camera) {
  Pictures out;
  setWater(fluid);
  out.lightSeconds = updateLights(fluid, time, &camera);
  for (splat::SplatKind kind : kinds_)
    out.pictures.push_back({kind, renderer_.render(kind, camera)});
  return out;
}

splat::FrameTimings SceneFrame::drawToScreen(splat::SplatKind kind, const scene::CameraDesc& camera,
                                             int width, int height) {
  return renderer_.drawToScreen(kind, camera, width, height);
}

}  // namespace sph::render::compose
