#include "render/cdt/CdtGlPass.h"

namespace sph::render::cdt {

CdtGlPass::CdtGlPass(const sph::cdt::Settings& settings, const gl::ShaderLibrary& shaders)
    : context_(gl::GlContext::headless()), cdt_(std::make_unique<CdtGl>(settings, shaders)) {}

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

}  // namespace sph::render::cdt
