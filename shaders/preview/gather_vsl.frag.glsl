#version 450 core
// VPL gather for sets with virtual spherical lights (radius > 0); handles point VPLs too (common/gather.glsl).
#define GATHER_VSL 1
#include "common/gather.glsl"
