// The G-buffer's colour attachments (common/fullscreen.glsl reads them), written by preview/gbuffer.frag.glsl and, for
// the indirect light's grid, by preview/indirect_grid.frag.glsl.
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outBaseColor;
layout(location = 3) out vec4 outEmission;
layout(location = 4) out uvec4 outShading;  // common/gbuffer_packing.glsl
// Shading normal and distance to the camera in one texel: the geometry-aware merges (deinterleave.frag.glsl,
// the coarse-ring interpolation of common/ssbc.glsl) test every neighbour with one fetch instead of two and no length().
layout(location = 5) out vec4 outMergeKey;
layout(location = 6) out uvec4 outSurface;  // common/gbuffer_packing.glsl
