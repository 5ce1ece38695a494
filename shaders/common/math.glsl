// Constants shared by every pass; the same values as renderer/core/sampling.h.
const float kPi = 3.14159265358979323846;
const float kInvPi = 1.0 / kPi;

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Orthonormal basis (s, t) around the unit vector n (Duff et al. 2017); the same as renderer/core/sampling.h Frame, and
// as renderer/gl/shadow_maps.cpp's hemicube frame, which the VPL maps are drawn with.
void orthonormalFrame(vec3 n, out vec3 s, out vec3 t) {
  float sgn = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (sgn + n.z);
  float b = n.x * n.y * a;
  s = vec3(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
  t = vec3(b, sgn + n.y * n.y * a, -n.y);
}
