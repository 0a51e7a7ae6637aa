// The reference image the splat renderers are scored against (DESIGN.md, "An error figure for a
// render compares it to a reference image of the same SPH iso-surface"): a CPU ray-marcher of the
// SD iso-surface of the same density field, with the same camera and lighting. Each ray marches
// in steps of a quarter kernel radius from where it enters the particles' box, and bisects the
// first crossing of SD to a thousandth of the radius; the normal is -gradC there.
#pragma once

#include <cstdint>
#include <vector>

#include "render/frame/Lighting.h"
#include "render/frame/RenderImage.h"
#include "render/splat/DensityField.h"
#include "sim/scene/CameraDesc.h"

namespace sph::render::splat {

// What the GL renderer draws around the water, as the reference sees it: the opaque solids'
// colours (sRGB, row 0 at the top) and their distance along the camera's view axis (m; infinity
// where there is none). SplatRenderer::drawBackdrop makes one.
struct Backdrop {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  std::vector<float> viewDepth;
};

// The iso-surface D = SD. With a backdrop (same size as the image), each ray stops at the solid
// it hits first: the solid's pixel shows where no water is in front of it, and a solid in front
// of the water hides it (not covered), as in the GL picture.
frame::RenderImage raymarchReference(const DensityField& field, float SD,
                                     const scene::CameraDesc& camera, int width, int height,
                                     const frame::Lighting& lighting,
                                     const Backdrop* backdrop = nullptr);

// Every particle as a ball of `radius` (m), ray-traced exactly, shaded with -gradC like the rest:
// what the particles are, thin jets and lone drops included, which the SD surface drops where
// their D stays below SD. A picture to judge the splats' jets by, not an error reference.
frame::RenderImage raytraceParticleBalls(const DensityField& field, float radius,
                                         const scene::CameraDesc& camera, int width, int height,
                                         const frame::Lighting& lighting,
                                         const Backdrop* backdrop = nullptr);

}  // namespace sph::render::splat
