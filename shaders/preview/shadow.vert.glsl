#version 450 core
#include "common/scene.glsl"

// The chunk's caster drawn by instance 0 (a draw of one caster, when an update is spread over several calls).
uniform int uInstanceOffset;
out vec3 vPosition;
flat out int vCaster;

void main() {
  vPosition = scenePositions[sceneTriangles[gl_VertexID / 3][gl_VertexID % 3]].xyz;
  vCaster = gl_InstanceID + uInstanceOffset;
}
