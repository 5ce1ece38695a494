// Constants shared by every pass; the same values as renderer/core/sampling.h.
const float kPi = 3.14159265358979323846;
const float kInvPi = 1.0 / kPi;

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
