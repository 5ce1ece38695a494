#version 450 core
#include "common/scene.glsl"

uniform mat4 uViewProj;

out vec3 vPosition;
out vec3 vNormal;
out vec2 vUv;
flat out vec3 vGeoNormal;
flat out uint vMaterial;

void main() {
  uvec4 tri = sceneTriangles[gl_VertexID / 3];
  uint index = tri[gl_VertexID % 3];
  vec3 p0 = scenePositions[tri.x].xyz, p1 = scenePositions[tri.y].xyz, p2 = scenePositions[tri.z].xyz;
  vPosition = scenePositions[index].xyz;
  vNormal = sceneNormals[index].xyz;
  vUv = sceneUvs[index];
  vGeoNormal = normalize(cross(p1 - p0, p2 - p0));
  vMaterial = tri.w;
  gl_Position = uViewProj * vec4(vPosition, 1.0);
}
