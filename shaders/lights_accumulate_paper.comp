#version 450 core
// The paper's unsynchronised imageLoad + imageStore accumulation: lights_accumulate.glsl.
#define ACCUMULATE_PAPER
#include "lights_accumulate.glsl"
