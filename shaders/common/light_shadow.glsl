// Visibility of a light from a shading point through its cube shadow map of radial distances
// (renderer/gl/light_shadows.h; docs/methods.md "Direct light in the preview").
//  - emitterRadius = 0 (punctual light): percentage-closer filtering over a disc of about one texel (kSharpShadowTaps).
//  - emitterRadius R > 0 (area emitter around the map's centre): percentage-closer soft shadows (Fernando 2005). The
//    blocker search averages the distances of occluders within the cone the emitter subtends; with their mean z_b the
//    penumbra seen from the centre has the angular radius R (d - z_b) / (z_b d); the filter's fraction of lit taps is
//    the visible fraction of the emitter.
// Every tap compares against the distance to the receiver's own plane along the tap's direction (receiver-plane depth
// bias), so a wide filter on a tilted receiver does not shadow the receiver by itself.
layout(binding = UNIT_LIGHT_SHADOWS) uniform samplerCubeArray uLightShadows;
// Directional lights: an orthographic map each (layer of a 2D array) over the disc of radius uSceneRadius around
// uSceneCentre perpendicular to the light's direction, storing the distance along the direction from the plane
// uSceneRadius behind the centre.
layout(binding = UNIT_DIRECTIONAL_SHADOWS) uniform sampler2DArray uDirectionalShadows;
uniform vec3 uSceneCentre;
uniform float uSceneRadius;
uniform float uDirectionalShadowTexel;  // 2 uSceneRadius / map size, metres
uniform float uLightShadowTexel;  // angle of a texel at a face's centre, 2 / faceSize

// Taps of the soft shadows' blocker search and filter (area emitters).
const int kLightShadowTaps = 16;
// Taps of the filter over about one texel (punctual and directional lights): with 8 instead of 16 a point light's
// direct light is 3 % further from the reference (relMSE 0.0180 against 0.0175 on the 10k-triangle dense scene at
// 256^2), at half the cost, which is most of the direct pass (a point light: 13 of its 21 ms at 640x480).
const int kSharpShadowTaps = 8;

// A Vogel spiral of `taps` taps over the unit disc, rotated by `rotation`: tap i at radius sqrt((i + 0.5) / taps) and
// angle rotation + i times the golden angle. The angle advances by a complex multiplication (vogelNext) instead of a sin
// and cos per tap: llvmpipe evaluates those as polynomials, and 32 of them per pixel cost more than the shadow lookups.
const vec2 kGoldenTurn = vec2(-0.7373688, 0.6754903);  // cos, sin of the golden angle 2.39996323
vec2 vogelStart(float rotation) { return vec2(cos(rotation), sin(rotation)); }
vec2 vogelTap(int i, int taps, vec2 angle) { return sqrt((float(i) + 0.5) / float(taps)) * angle; }
vec2 vogelNext(vec2 angle) { return vec2(angle.x * kGoldenTurn.x - angle.y * kGoldenTurn.y, angle.x * kGoldenTurn.y + angle.y * kGoldenTurn.x); }

// The receiver's distance along tap direction u: to its own plane (planeOffset = (x - light).n, wn = w.n for the
// central direction w), clamped where the plane turns away from the light.
float tapReference(vec3 u, vec3 ng, float planeOffset, float wn, float dist) {
  float un = dot(u, ng);
  return abs(un) > 0.05 * abs(wn) && un * wn > 0.0 ? clamp(planeOffset / un, 0.5 * dist, 2.0 * dist) : dist;
}

float lightVisibility(int cube, vec3 lightPos, float emitterRadius, vec3 x, vec3 ng, float rotation) {
  vec3 d0 = x - lightPos;
  float dist0 = length(d0);
  // Normal offset by about 1.5 texels' footprint at this distance (acne on grazing receivers).
  vec3 d = d0 + ng * (1.5 * uLightShadowTexel * dist0);
  float dist = length(d);
  vec3 w = d / dist;
  vec3 s = normalize(abs(w.x) > 0.5 ? cross(w, vec3(0.0, 1.0, 0.0)) : cross(w, vec3(1.0, 0.0, 0.0)));
  vec3 t = cross(w, s);
  float planeOffset = dot(d, ng);
  float wn = dot(w, ng);

  float filterAngle = 1.0 * uLightShadowTexel;
  if (emitterRadius > 0.0) {
    float searchAngle = clamp(emitterRadius / dist, uLightShadowTexel, 0.7);
    float blockerSum = 0.0;
    int blockers = 0;
    vec2 angle = vogelStart(rotation);
    for (int i = 0; i < kLightShadowTaps; ++i, angle = vogelNext(angle)) {
      vec2 o = vogelTap(i, kLightShadowTaps, angle) * searchAngle;
      vec3 u = normalize(w + o.x * s + o.y * t);
      float stored = texture(uLightShadows, vec4(u, float(cube))).r;
      if (stored < tapReference(u, ng, planeOffset, wn, dist)) {
        blockerSum += stored;
        ++blockers;
      }
    }
    if (blockers == 0) return 1.0;
    float zb = blockerSum / float(blockers);
    filterAngle = clamp(emitterRadius * (dist - zb) / (zb * dist), uLightShadowTexel, 0.7);
  }
  // emitterRadius is a constant 0 where a punctual light's map is filtered, so the count is a constant too.
  int filterTaps = emitterRadius > 0.0 ? kLightShadowTaps : kSharpShadowTaps;
  float lit = 0.0;
  vec2 angle = vogelStart(rotation);
  for (int i = 0; i < filterTaps; ++i, angle = vogelNext(angle)) {
    vec2 o = vogelTap(i, filterTaps, angle) * filterAngle;
    vec3 u = normalize(w + o.x * s + o.y * t);
    lit += texture(uLightShadows, vec4(u, float(cube))).r >= tapReference(u, ng, planeOffset, wn, dist) ? 1.0 : 0.0;
  }
  return lit / float(filterTaps);
}

// Visibility of a directional light (rays travelling along `direction`) from x: percentage-closer filtering over a
// disc of about one texel, each tap compared with the receiver's plane at the tap's position.
float directionalVisibility(int map, vec3 direction, vec3 x, vec3 ng, float rotation) {
  vec3 s, t;
  orthonormalFrame(direction, s, t);
  vec3 p = x + ng * (1.5 * uDirectionalShadowTexel) - uSceneCentre;
  vec2 uv = vec2(dot(p, s), dot(p, t)) / (2.0 * uSceneRadius) + 0.5;
  float depth = dot(p, direction) + uSceneRadius;
  // How the receiver's plane moves along the direction per metre across the map: -(ng.s, ng.t) / (ng.direction).
  float nd = dot(ng, direction);
  vec2 slope = abs(nd) > 0.05 ? -vec2(dot(ng, s), dot(ng, t)) / nd : vec2(0.0);
  float lit = 0.0;
  vec2 angle = vogelStart(rotation);
  for (int i = 0; i < kSharpShadowTaps; ++i, angle = vogelNext(angle)) {
    vec2 o = vogelTap(i, kSharpShadowTaps, angle) * uDirectionalShadowTexel;
    float ref = depth + clamp(dot(slope, o), -4.0 * uDirectionalShadowTexel, 4.0 * uDirectionalShadowTexel);
    float stored = texture(uDirectionalShadows, vec3(uv + o / (2.0 * uSceneRadius), float(map))).r;
    lit += stored >= ref ? 1.0 : 0.0;
  }
  return lit / float(kSharpShadowTaps);
}
