// The scene's `render` section (docs/scene-format.md): how frames are drawn by the splat renderer
// (render/splat/SplatBuilder.h, render/frame/Lighting.h). Plain data; render/ turns it into its
// parameters.
#pragma once

#include <string>

#include "sim/scene/EnumNames.h"

namespace sph::scene {

// Where a quad splat's vertices go (scene key render.projection; render/splat/SplatBuilder.h).
enum class SplatProjection {
  Equation6,  // seed 003 eq. (6): by R (SD - PD) / (ID - PD), the density assumed linear
  Newton,     // one Newton step onto SD along the normal, (SD - PD) / |gradD| (ours, the default)
};
constexpr const char* nameOf(SplatProjection v) {
  switch (v) {
    case SplatProjection::Equation6:
      return "eq6";
    case SplatProjection::Newton:
      return "newton";
  }
  return nullptr;
}

// How the walls and containers are drawn (scene key render.solids; render/compose/SceneFrame.cpp).
enum class RenderSolids {
  Points,  // their boundary particles, translucent grey squares (the default)
  Opaque,  // lit surfaces: a tank as a cut-away, cup, block, sphere, plane closed and opaque
  None,
};
constexpr const char* nameOf(RenderSolids v) {
  switch (v) {
    case RenderSolids::Points:
      return "points";
    case RenderSolids::Opaque:
      return "opaque";
    case RenderSolids::None:
      return "none";
  }
  return nullptr;
}

struct RenderDesc {
  enum class Splat { Point, Quad, Both } splat = Splat::Quad;
  int width = 960, height = 540;  // pixels
  int every = 1;                  // render every n-th output frame
  float kernelRadius = 2.5f;      // spacings, R of the renderer's density field
  float surfaceThreshold = 0;     // SD / ID; 0 = automatic
  float splatSize = 1.5f;         // spacings, centre to corner
  bool perVertexDensity = true;   // eq. (6) PD per vertex (false: per particle, the paper)
  SplatProjection projection = SplatProjection::Newton;
  bool environment = true;    // sky reflection
  float alpha = 1.0f;         // splat opacity
  bool cullBackFaces = true;  // opaque: skip splats facing away from the camera
  // How the walls and containers are drawn (never in `compare`'s error figures): translucent
  // boundary particles, lit opaque surfaces (render/solids), or not at all.
  RenderSolids solids = RenderSolids::Points;
  std::string directory;  // PNGs of rendered frames ("" = next to the cache, or none)
  bool toCache = true;    // also store the frames in the HDF5 cache
};
// Scene key render.splat and `render --splat`.
constexpr const char* nameOf(RenderDesc::Splat v) {
  switch (v) {
    case RenderDesc::Splat::Point:
      return "point";
    case RenderDesc::Splat::Quad:
      return "quad";
    case RenderDesc::Splat::Both:
      return "both";
  }
  return nullptr;
}

}  // namespace sph::scene
