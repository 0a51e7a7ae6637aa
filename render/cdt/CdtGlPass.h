// cdt-gl as the step's collision pass (sim/CollisionPass.h): owns a headless context and the
// CdtGl state; each apply() uploads the integrated particles, runs one CDT step with
// integrate = false (the SPH step already integrated) and reads the result back.
#pragma once

#include <memory>
#include <string>

#include "render/cdt/CdtGl.h"
#include "render/gl/GlContext.h"
#include "sim/scene/CollisionDesc.h"
#include "sim/CollisionPass.h"

namespace sph::render::cdt {

class CdtGlPass final : public CollisionPass {
 public:
  // Creates the headless context and compiles the shaders. Throws gl::GlUnavailable /
  // gl::ShaderError.
  explicit CdtGlPass(const sph::cdt::Settings& settings,
                     const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());
  ~CdtGlPass() override;

  std::string name() const override { return enumName(scene::CollisionMethod::CdtGl); }
  void apply(Particles& particles, const CollisionContext& context) override;

  const gl::GlInfo& info() const { return context_.info(); }

 private:
  gl::GlContext context_;  // first member: destroyed after the GL objects
  std::unique_ptr<CdtGl> cdt_;
};

}  // namespace sph::render::cdt
