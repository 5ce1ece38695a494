#version 450 core
// Stores the radial distance to the light (one value works for every face and for the filter taps, which cross
// faces), pushed away from the light by how fast it changes across a texel (a slope-scaled bias, at most
// uMaxSlopeBias x distance: grazing triangles would push it without bound). The depth test uses the ordinary depth.
// A directional light's map stores the distance along its direction from a plane behind the scene instead.
uniform float uMaxSlopeBias;
uniform bool uAlongDirection;
uniform vec3 uDirection;
in vec3 vOffset;
layout(location = 0) out float outDistance;

void main() {
  float d = uAlongDirection ? dot(vOffset, uDirection) : length(vOffset);
  outDistance = d + min(fwidth(d), uMaxSlopeBias * (uAlongDirection ? 1.0 : d));
}
