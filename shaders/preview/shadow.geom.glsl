#version 450 core
// Layered rendering of one caster's six cube faces per instance: layer-face = 6 * caster + face.
#include "common/units.glsl"
layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;

layout(std430, binding = BINDING_SHADOW_CASTERS) readonly buffer Casters { vec4 casterPositions[]; };

uniform mat3 uFaceRotation[6];
uniform mat4 uProjection;
uniform int uFirstCaster;

in vec3 vPosition[];
flat in int vCaster[];
out vec3 gOffset;

void main() {
  int caster = vCaster[0];
  vec3 origin = casterPositions[uFirstCaster + caster].xyz;
  for (int i = 0; i < 3; ++i) {
    gOffset = vPosition[i] - origin;
    gl_Position = uProjection * vec4(uFaceRotation[gl_InvocationID] * gOffset, 1.0);
    gl_Layer = caster * 6 + gl_InvocationID;
    EmitVertex();
  }
  EndPrimitive();
}
