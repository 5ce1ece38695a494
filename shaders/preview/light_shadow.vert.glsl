#version 450 core
// One face of a light's cube shadow map (renderer/gl/light_shadows.h), drawn as an indexed mesh.
layout(location = 0) in vec4 aPosition;
uniform mat4 uViewProjection;
uniform vec3 uLightPosition;
out vec3 vOffset;

void main() {
  vOffset = aPosition.xyz - uLightPosition;
  gl_Position = uViewProjection * vec4(aPosition.xyz, 1.0);
}
