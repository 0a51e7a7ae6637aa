// Constants of the CDT algorithm that the C++ side (sim/cdt/CdtCpu, render/cdt/CdtGl) and the GLSL
// side (shaders/cdt_constants.glsl) must agree on. Each is defined once here and once there;
// tests/test_cdt_cpu.cpp reads the GLSL file and fails if a value differs (STYLE.md rule 11).
#pragma once

#include <cstdint>

namespace sph::cdt {

// Most depth-peeled layers a collision detection texture may have.
inline constexpr int kMaxLayers = 4;
// Largest texel_collide_range r a loop may run to ((2r+1)^2 texels per layer).
inline constexpr int kMaxTexelRange = 16;
// Texel w of an empty texel; an occupied texel holds the particle id as a float in w.
inline constexpr float kEmptyTexel = -1.0f;
// Ids must stay below this to be exact in the texture's float w (2^24).
inline constexpr std::uint32_t kMaxId = 16777216u;
// Diagnostics: "no partner" and "not on the texture".
inline constexpr std::uint32_t kNoPartner = 0xFFFFFFFFu;
inline constexpr std::uint32_t kOffscreen = 0xFFFFFFFFu;

// Bits of CdtParams::flags.
inline constexpr std::uint32_t kFlagIntegrate = 1u;      // input is the step's start; integrate
inline constexpr std::uint32_t kFlagTexelPosition = 2u;  // curr_pos from the base texel (paper)
inline constexpr std::uint32_t kFlagAdaptiveRange = 4u;  // r from the projected range
inline constexpr std::uint32_t kFlagPaperResponse = 8u;  // bounce response of seed 000
inline constexpr std::uint32_t kFlagTextureValid = 16u;  // the texture holds a previous step

// GL bindings (render/cdt/CdtGl.cpp and the shaders' layout qualifiers).
inline constexpr int kAttribPositionTime = 0;  // vec4: position (m), collideTime (s)
inline constexpr int kAttribVelocity = 1;      // vec3: velocity (m/s)
inline constexpr int kAttribId = 2;            // uint: Particles::id
inline constexpr int kAttribAcceleration = 3;  // vec3: acceleration (m/s^2)
inline constexpr int kParamsBinding = 0;       // uniform block CdtParams
inline constexpr int kLayerUnit = 0;           // texture unit of the 2D array of layers
inline constexpr int kPeelDepthUnit = 4;       // previous layer's depth keys while peeling (raster)
inline constexpr int kPeelIndexUnit = 5;       // previous layer's index keys while peeling (raster)
// The compute-shader texture write (shaders/cdt_write.comp): image units, particle buffer, and
// invocations per work group.
inline constexpr int kImageColour = 0;         // rgba32f layer being written
inline constexpr int kImageDepthKey = 1;       // r32ui depth bits of the kept particle
inline constexpr int kImageIndexKey = 2;       // r32ui draw index of the kept particle
inline constexpr int kImagePreviousDepth = 3;  // the previous layer's keys (peeling)
inline constexpr int kImagePreviousIndex = 4;
inline constexpr int kParticleBinding = 0;  // shader storage block CdtParticles
inline constexpr int kWriteKeyBinding = 1;  // shader storage block CdtWriteKeys
// Transform feedback buffers of the collision pass: new state, diagnostics, write keys.
inline constexpr int kXfbState = 0;
inline constexpr int kXfbDiagnostics = 1;
inline constexpr int kXfbWriteKeys = 2;
inline constexpr int kWriteGroupSize = 64;

}  // namespace sph::cdt
