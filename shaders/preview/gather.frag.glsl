#version 450 core
// VPL gather for point VPLs only (common/gather.glsl).
#define GATHER_VSL 0
#include "common/gather.glsl"
