// VPL visibility from imperfect shadow maps (Ritschel et al. 2008; renderer/gl/ism.h, vpl_visibility.h IsmVisibility):
// one paraboloid depth tile per VPL around its geometric normal, tiles in an atlas (layers of a 2D array), depth =
// distance / far. A texel holds the depth of a nearby point's tangent plane along the texel's centre direction
// (renderer/gl/ism.cpp), so a receiver on that surface meets its own depth up to the slope across a texel: the lookup
// offsets the receiver along its normal by half a rim texel's footprint and biases the comparison by one (larger than
// cube maps need; measured against light leaks through a 1 cm wall and self-shadowing, docs/methods.md).
layout(binding = UNIT_VISIBILITY) uniform sampler2DArrayShadow uVisibilityMaps;
uniform float uShadowFar;
uniform float uShadowBias;
uniform int uIsmTileSize;
uniform int uIsmTilesPerRow;
uniform int uIsmTilesPerLayer;

float vplVisibility(int caster, vec3 casterPos, vec3 casterNormal, vec3 x, float distance, vec3 geoNormal) {
  float tileSize = float(uIsmTileSize);
  // Angle of a texel at the tile's rim, where the paraboloid's texels are largest (2 / T of the uv range, times 2).
  float texelAngle = 4.0 / tileSize;
  vec3 d = x + geoNormal * (0.5 * texelAngle * distance) - casterPos;
  float r = length(d);
  // The frame of renderer/core/sampling.h Frame (Duff et al. 2017) around the caster's normal.
  vec3 s, t;
  orthonormalFrame(casterNormal, s, t);
  vec3 local = vec3(dot(d, s), dot(d, t), dot(d, casterNormal));
  // Behind the caster's plane it sends no light; the gather's cosines already give 0 there.
  vec2 uv = local.xy / max(r + local.z, 1e-20);
  vec2 texel = clamp((uv + 1.0) * (0.5 * tileSize), vec2(0.5), vec2(tileSize - 0.5));
  // The tile's layer, row and column in float arithmetic (exact below 2^24 tiles): llvmpipe has no vector integer
  // division and would divide lane by lane for every fragment and VPL.
  float perLayer = float(uIsmTilesPerLayer), perRow = float(uIsmTilesPerRow);
  float layer = floor((float(caster) + 0.5) / perLayer);
  float inLayer = float(caster) - layer * perLayer;
  float row = floor((inLayer + 0.5) / perRow);
  vec2 origin = vec2(inLayer - row * perRow, row) * tileSize;
  float atlasSize = tileSize * perRow;
  float reference = (r - uShadowBias - texelAngle * r) / uShadowFar;
  return texture(uVisibilityMaps, vec4((origin + texel) / atlasSize, layer, reference));
}
