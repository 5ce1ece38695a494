// Visibility of a light from a shading point through its cube shadow map of radial distances
// (renderer/gl/light_shadows.h; docs/methods.md "Direct light in the preview"): a point or spot light's filtered over
// about a texel, an area emitter's per sample (AreaShadow below).
// Every tap compares against the distance to the receiver's own plane along the tap's direction (receiver-plane depth
// bias), so a tap away from the receiver's own direction on a tilted receiver does not shadow the receiver by itself.
#include "common/light_maps.glsl"

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

// Visibility of a point or spot light at lightPos from x: percentage-closer filtering over a disc of about one texel.
float pointLightVisibility(int cube, vec3 lightPos, vec3 x, vec3 ng, float rotation) {
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
  float lit = 0.0;
  vec2 angle = vogelStart(rotation);
  for (int i = 0; i < kSharpShadowTaps; ++i, angle = vogelNext(angle)) {
    vec2 o = vogelTap(i, kSharpShadowTaps, angle) * uLightShadowTexel;
    vec3 u = normalize(w + o.x * s + o.y * t);
    lit += lightShadowDistance(u, float(cube)) >= tapReference(u, ng, planeOffset, wn, dist) ? 1.0 : 0.0;
  }
  return lit / float(kSharpShadowTaps);
}

// Soft shadows of an area emitter from the cube maps of its cells (renderer/gl/light_shadows.h), per area-light sample y
// (percentage-closer soft shadows, Fernando 2005, with the emitter's own samples as the filter). A blocker at point b
// blocks the segment from y to the receiver x where that segment is as far from the cell's centre c along c->x as b
// is: the map is read in the direction of that point, so each sample's shadow test follows the emitter's real shape and
// orientation as seen from x. A disc of the emitter's radius around c->x instead (the textbook filter) reached behind
// the emitter's plane for receivers near its horizon and found the ceiling the emitter hangs under: walls of the
// Cornell box got half their light there, and a large emitter darkened the whole room (docs/methods.md "Direct light
// in the preview").
// The blocker search runs once per emitter, not once per cell: its taps are spread over all the emitter's samples,
// each read from its own cell's map, and it keeps the mean blocker as a point, which each cell measures from its own
// centre. Nothing behind the emitter's plane can block light it emits, so directions within two texels of that plane
// are not tested (a texel's ray there may hit the ceiling).
struct AreaShadow {
  int cube;
  vec3 centre;
  vec3 receiver;  // x, offset along its normal (acne)
  vec3 w;         // unit, from the centre to the receiver
  float dist;
  vec3 ng;
  float planeOffset, wn;  // the receiver's plane, for tapReference
};

// A cell's view of the receiver x (geometric normal ng) from its map at `centre`.
AreaShadow areaShadowCell(int cube, vec3 centre, vec3 x, vec3 ng) {
  AreaShadow a;
  a.cube = cube;
  a.centre = centre;
  vec3 d0 = x - centre;
  // A quarter texel's footprint along the normal: the 1.5 of the point lights put a receiver between an engine's
  // cooling fins, a texel or two apart under its studio light, into the next fin's shadow.
  vec3 d = d0 + ng * (0.25 * uAreaShadowTexel * length(d0));
  a.receiver = centre + d;
  a.dist = length(d);
  a.w = d / a.dist;
  a.ng = ng;
  a.planeOffset = dot(d, ng);
  a.wn = dot(a.w, ng);
  return a;
}

// Whether the point `reach` from the centre in direction u (in front of the emitter) lies behind an occluder seen
// from the centre, and before the receiver's plane. Testing against the receiver's plane alone (the textbook test)
// counted any geometry along u before the plane, far from the segment the tap stands for: the ground under the
// engine's studio light was shadowed by the engine in directions that did not reach it (7 % too dark).
bool areaShadowOccluded(AreaShadow a, vec3 u, float reach, vec3 emitterNormal, out float stored) {
  stored = lightShadowDistance(u, float(a.cube));
  return dot(u, emitterNormal) > 2.0 * uAreaShadowTexel &&
         stored < min(reach, tapReference(u, a.ng, a.planeOffset, a.wn, a.dist));
}

// The blocker search's mean blocker point, accumulated over taps.
struct BlockerSearch {
  vec3 pointSum;
  int blockers;
};

BlockerSearch blockerSearchBegin() { return BlockerSearch(vec3(0.0), 0); }

// One tap of the blocker search (preview/blocker_search.frag.glsl): the point a fraction t of the way from emitter
// sample y to the receiver, read from the map of y's cell a. Occluders up to half as far again count (a blocker's
// surface seen from the centre lies before the segment's crossing). A tap from a pixel that sees no surface
// (receiverSeen false) counts nothing.
void blockerSearchTap(inout BlockerSearch search, AreaShadow a, vec3 y, vec3 emitterNormal, float t,
                      bool receiverSeen) {
  vec3 p = mix(y, a.receiver, t) - a.centre;
  float reach = length(p);
  vec3 u = p / reach;
  float stored;
  bool blocked = receiverSeen && areaShadowOccluded(a, u, 1.5 * reach, emitterNormal, stored);
  search.pointSum += blocked ? a.centre + stored * u : vec3(0.0);
  search.blockers += blocked ? 1 : 0;
}

// 1 when the segment from emitter sample y (normal emitterNormal) of cell a to the receiver is clear, 0 when blocked:
// the map is read toward the segment's point as far from the centre along c->x as the mean blocker, and an occluder
// there (within a quarter again) blocks it. The factors 1.5 and 1.25 and the receiver's normal offset of a quarter
// texel are those that kept every case of vplab_bench_direct_bench within about 1 % (docs/benchmarks.md "Direct light
// in the preview").
float areaSampleVisibility(BlockerSearch search, AreaShadow a, vec3 y, vec3 emitterNormal) {
  vec3 blocker = search.pointSum / float(max(search.blockers, 1));
  float blockerDepth = dot(blocker - a.centre, a.w);
  vec3 yc = y - a.centre;
  float along = dot(yc, a.w);
  float t = clamp((blockerDepth - along) / max(a.dist - along, 1e-6 * a.dist), 0.0, 1.0);
  vec3 p = mix(yc, a.receiver - a.centre, t);
  float reach = length(p);
  float stored;
  return search.blockers > 0 && areaShadowOccluded(a, p / reach, 1.25 * reach, emitterNormal, stored) ? 0.0 : 1.0;
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
