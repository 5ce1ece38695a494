#version 450 core
#include "common/scene.glsl"

out vec3 vPosition;
flat out int vCaster;

void main() {
  vPosition = scenePositions[sceneTriangles[gl_VertexID / 3][gl_VertexID % 3]].xyz;
  vCaster = gl_InstanceID;
}
