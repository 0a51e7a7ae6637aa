// The reference image the splat renderers are scored against (DESIGN.md, "An error figure for a
// render compares it to a reference image of the same SPH iso-surface"): a CPU ray-marcher of the
// SD iso-surface of the same density field, with the same camera and lighting. Each ray marches
// in steps of a quarter kernel radius from where it enters the particles' box, and bisects the
// first crossing of SD to a thousandth of the radius; the normal is -gradC there.
#pragma once

#include "render/splat/DensityField.h"
#include "render/splat/Lighting.h"
#include "render/splat/RenderImage.h"
#include "sim/CameraDesc.h"

namespace sph::render::splat {

RenderImage raymarchReference(const DensityField& field, float SD, const CameraDesc& camera,
                              int width, int height, const Lighting& lighting);

}  // namespace sph::render::splat
