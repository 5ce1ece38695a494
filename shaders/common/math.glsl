// Constants shared by every pass; the same values as renderer/core/sampling.h.
const float kPi = 3.14159265358979323846;
const float kInvPi = 1.0 / kPi;

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Orthonormal basis (s, t) around the unit vector n (Duff et al. 2017), the same as renderer/core/sampling.h Frame down
// to its sign, copysign(1, n.z): the CPU draws maps around a normal or direction with Frame (VPL hemicubes, ISM tiles,
// directional lights' maps) that are read here, and a normal whose z is -0 (14 of the Cornell box's 291 VPLs) must get
// the same frame on both sides: where its x is not 0, a test of n.z >= 0 gives it the frame turned half a turn about it.
void orthonormalFrame(vec3 n, out vec3 s, out vec3 t) {
  float sgn = uintBitsToFloat((floatBitsToUint(n.z) & 0x80000000u) | 0x3f800000u);
  float a = -1.0 / (sgn + n.z);
  float b = n.x * n.y * a;
  s = vec3(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
  t = vec3(b, sgn + n.y * n.y * a, -n.y);
}
