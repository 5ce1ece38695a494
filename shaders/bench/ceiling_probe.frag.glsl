#version 450 core
// Fragment-shading ceiling of the VPL gather on this GL implementation (bench/gl_bench.cpp; docs/benchmarks.md): per pixel and light exactly 2 uniform-buffer reads, 1 sampler2DArrayShadow fetch and ~40 flops of a point
// light's clamped geometry term, with no branch and no G-buffer read, so that nothing but that work is timed. The
// light index is uniform across the draw, as in the gather's deinterleaved layout. The sum is written out, so the
// compiler cannot drop any of it.

const int kProbeLights = 1024;    // lights in the table; light j reads entry j mod kProbeLights
const int kProbeCubes = 16;       // shadow cubes; light j fetches cube j mod kProbeCubes
layout(std140, binding = 1) uniform ProbeLights { vec4 uLights[2 * kProbeLights]; };
layout(binding = 6) uniform sampler2DArrayShadow uShadowMaps;
uniform int uLightCount;
uniform vec2 uInvSize;

layout(location = 0) out vec4 outColor;

void main() {
  // A receiver that varies per pixel, like the G-buffer point of the gather.
  vec2 uv = gl_FragCoord.xy * uInvSize;
  vec3 x1 = vec3(uv * 2.0 - 1.0, -1.0);
  vec3 n1 = normalize(vec3(0.2 * uv.x, 0.2 * uv.y, 1.0));
  vec3 sum = vec3(0.0);
  for (int j = 0; j < uLightCount; ++j) {
    vec4 a = uLights[2 * (j % kProbeLights)];      // xyz position, w clamp bound
    vec4 b = uLights[2 * (j % kProbeLights) + 1];  // xyz normal, w flux
    vec3 d = a.xyz - x1;                                     // 3
    float dist2 = dot(d, d);                                 // 5
    float inv = inversesqrt(dist2);                          // 1
    vec3 w = d * inv;                                        // 3
    float cos1 = max(dot(n1, w), 0.0);                       // 6
    float cos2 = max(-dot(b.xyz, w), 0.0);                   // 7
    float g = min(cos1 * cos2 / dist2, a.w);                 // 3
    // Cube face and its coordinates, as common/shadow.glsl (major axis), without the branch.
    vec3 m = abs(w);                                         // 3
    float major = max(m.x, max(m.y, m.z));                   // 2
    vec2 st = (m.x >= major ? w.yz : m.y >= major ? w.xz : w.xy) / major * 0.5 + 0.5;  // 6
    float face = m.x >= major ? 0.0 : m.y >= major ? 2.0 : 4.0;
    float layer = float(6 * (j % kProbeCubes)) + face;
    float v = texture(uShadowMaps, vec4(st, layer, dist2 * 0.01));
    sum += vec3(g * v * b.w) * vec3(1.0, 0.9, 0.8);          // 6
  }
  outColor = vec4(sum, 1.0);
}
