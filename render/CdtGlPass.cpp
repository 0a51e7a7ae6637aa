#include "render/CdtGlPass.h"

namespace sph::render {

CdtGlPass::CdtGlPass(const cdt::Settings& settings, const ShaderLibrary& shaders)
    : context_(GlContext::headless()), cdt_(std::make_unique<CdtGl>(settings, shaders)) {}

CdtGlPass::~CdtGlPass() {
  context_.makeCurrent();
  cdt_.reset();
}

void CdtGlPass::apply(Particles& particles, const CollisionContext& context) {
  context_.makeCurrent();
  cdt_->upload(particles);
  cdt_->step(static_cast<float>(context.dt), false);
  cdt_->download(particles);
}

}  // namespace sph::render
