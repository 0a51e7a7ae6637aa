#version 450 core
// The race-free accumulation (fixed-point integer atomics): lights_accumulate.glsl.
#include "lights_accumulate.glsl"
