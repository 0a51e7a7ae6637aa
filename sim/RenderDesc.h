// The scene's `render` section (docs/scene-format.md): how frames are drawn by the splat renderer
// (render/splat/SplatBuilder.h, render/splat/Lighting.h). Plain data; render/ turns it into its
// parameters.
#pragma once

#include <string>

namespace sph {

struct RenderDesc {
  enum class Splat { Point, Quad, Both } splat = Splat::Quad;
  int width = 960, height = 540;  // pixels
  int every = 1;                  // render every n-th output frame
  float kernelRadius = 2.5f;      // spacings, R of the renderer's density field
  float surfaceThreshold = 0;     // SD / ID; 0 = automatic
  float splatSize = 1.5f;         // spacings, centre to corner
  bool perVertexDensity = true;   // eq. (6) PD per vertex (false: per particle, the paper)
  bool newtonProjection = true;   // a Newton step onto SD (default), or the paper's eq. (6)
  bool environment = true;        // sky reflection
  float alpha = 1.0f;             // splat opacity
  bool cullBackFaces = true;      // opaque: skip splats facing away from the camera
  // How the walls and containers are drawn (never in `compare`'s error figures): translucent
  // boundary particles, lit opaque surfaces (render/solids), or not at all.
  enum class Solids { Points, Opaque, None } solids = Solids::Points;
  std::string directory;          // PNGs of rendered frames ("" = next to the cache, or none)
  bool toCache = true;            // also store the frames in the HDF5 cache
};

}  // namespace sph
