// Participating media in the preview (docs/theory.md §16-§17, §22; renderer/scene/medium.h): transmittance
// exp(-optical depth) over the parts of a segment inside the media (a ray-box slab test per medium). For a homogeneous
// box the optical depth is sigma_t length in closed form. The renderer compiles a pass with PREVIEW_MEDIA set to the
// number of the scene's media and binds their table (renderer/gl/media_pass.h): a count known to the compiler unrolls
// the loops over the media and makes their reads constant (llvmpipe: half the cost of a loop to a count read from the
// table). With PREVIEW_MEDIA 0 (no media) the transmittance is 1 and costs nothing, so the surface passes include this
// file unconditionally.
// PREVIEW_MEDIA_GRIDS, when defined, is the number of media with a density grid (smoke), and
// PREVIEW_MEDIA_GRID_MEDIA their table indices (grid g is medium mediaGridMedium[g]): their coefficients are per unit
// density, sigma(x) = densityScale d(x) sigma, d the grid's trilinear interpolation, read from a 3D texture per grid
// whose linear filtering is that interpolation, or, for the grids whose bit is set in PREVIEW_MEDIA_GRID_NANOVDB, from
// a NanoVDB grid in a storage buffer (renderer/gl/density_grids_gpu.h), interpolated here. Their optical depth is
// ray-marched (gridDensityIntegral), one march per grid the segment crosses; the other media take the closed form as
// without a grid, so a scene without one compiles the code it always had. The grid count, the indices and the storage
// are compile-time constants: the loops over the grids unroll, and with the loops over the media every grid's lookup
// folds to its own texture and its own medium's coefficients.
#ifndef PREVIEW_MEDIA
#define PREVIEW_MEDIA 0
#endif

#if PREVIEW_MEDIA
#include "common/units.glsl"

// The most media a scene may hold in the preview (renderer/gl/media_pass.h kPreviewMaxMedia).
#define MEDIA_MAX 8

// The most media with a density grid (renderer/gl/media_pass.h kPreviewMaxDensityGrids).
#define MEDIA_GRID_MAX 4

struct GlMedium {
  vec4 sigmaT;        // rgb sigma_a + sigma_s, w: 1 when the medium fills all space
  vec4 sigmaS;        // rgb sigma_s, w: Henyey-Greenstein g
  mat4 boxFromWorld;  // maps the medium's box onto the cube [-1, 1]^3
  vec4 compensation;  // rgb: the approximate bias compensation's factor C for the bound b (renderer/gl/media_pass.h)
};
// A grid medium's density texture or NanoVDB grid (unused without PREVIEW_MEDIA_GRIDS).
struct GlMediumGrid {
  mat4 textureFromWorld;  // world -> texture coordinates: index point p at (p - origin + 0.5) / size, a texel centre
  vec4 size;              // xyz: texels along x, y, z (the grid's stored voxels, zero margin included); w: densityScale
  uvec4 bufferOffset;     // x: the byte offset of its NanoVDB grid in the storage buffer (PREVIEW_MEDIA_GRID_NANOVDB)
};
layout(std140, binding = BINDING_MEDIA) uniform Media {
  GlMedium media[MEDIA_MAX];
  GlMediumGrid mediaGrids[MEDIA_GRID_MAX];
};

#ifdef PREVIEW_MEDIA_GRIDS
// The table index of grid g's medium.
const int mediaGridMedium[PREVIEW_MEDIA_GRIDS] = int[](PREVIEW_MEDIA_GRID_MEDIA);

// The grid of medium m, or -1 (a constant where m is: the loops over the media unroll).
int gridOfMedium(int m) {
  int found = -1;
  for (int g = 0; g < PREVIEW_MEDIA_GRIDS; ++g)
    if (mediaGridMedium[g] == m) found = g;
  return found;
}

#ifndef PREVIEW_MEDIA_GRID_NANOVDB
#define PREVIEW_MEDIA_GRID_NANOVDB 0
#endif
// Grid g is read from the NanoVDB buffer (else from its 3D texture).
bool gridInBuffer(int g) { return (PREVIEW_MEDIA_GRID_NANOVDB >> g & 1) != 0; }

#if PREVIEW_MEDIA_GRID_NANOVDB
// The NanoVDB grids at their byte offsets in one storage buffer (renderer/gl/density_grids_gpu.h), read through
// NanoVDB's own GLSL reader; their mediaGrids[g].textureFromWorld then maps world to index coordinates and
// mediaGrids[g].size.xyz is 1, so that the march below counts voxels alike for both storages.
layout(std430, binding = BINDING_MEDIA_DENSITY_GRID) readonly buffer MediaDensityGrid { uint pnanovdb_buf_data[]; };
#define PNANOVDB_GLSL
#include <nanovdb/PNanoVDB.h>

// The trilinear interpolation of the voxel values at integer index points of the NanoVDB grid at byte `offset`, as
// DensityGrid::lookup (a voxel the grid leaves out reads its background, 0). Corner c is voxel i + (c & 1, c >> 1 & 1,
// c >> 2).
float nanoVdbDensityAt(uint offset, vec3 index) {
  pnanovdb_buf_t buf;  // GLSL's reader names the storage block itself; the handle is a placeholder
  buf.unused = 0u;
  pnanovdb_grid_handle_t grid;
  grid.address.byte_offset = offset;
  pnanovdb_readaccessor_t acc;
  pnanovdb_readaccessor_init(acc, pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, grid)));
  vec3 f0 = floor(index), f = index - f0;
  ivec3 i = ivec3(f0);
  uint level;
  pnanovdb_address_t first =
      pnanovdb_readaccessor_get_value_address_and_level(PNANOVDB_GRID_TYPE_FLOAT, buf, acc, i, level);
  // Where all eight corners lie in the 8^3 leaf of the first (7 in 8 cells along each axis), their values follow its
  // in the leaf's table at (x << 6) + (y << 3) + z: one walk down the tree instead of eight (llvmpipe runs the
  // accessor's branches for every lane).
  float v[8];
  if (level == 0u && all(lessThan(i & 7, ivec3(7)))) {
    for (int c = 0; c < 8; ++c) {
      uint entry = uint((c & 1) * 64 + (c >> 1 & 1) * 8 + (c >> 2));
      v[c] = pnanovdb_read_float(buf, pnanovdb_address_offset(first, entry * 4u));
    }
  } else {
    for (int c = 0; c < 8; ++c) {
      ivec3 corner = i + ivec3(c & 1, c >> 1 & 1, c >> 2);
      v[c] = pnanovdb_read_float(
          buf, pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, buf, acc, corner));
    }
  }
  float y0 = mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
  float y1 = mix(mix(v[4], v[5], f.x), mix(v[6], v[7], f.x), f.y);
  return mix(y0, y1, f.z);
}
#endif

// R32F, linear filtering, clamped to the edge: outside the stored box each reads its zero margin, as the CPU's lookup.
// Grid g's texture is on unit UNIT_MEDIA_DENSITY + g (a grid in the buffer leaves its unit unused). One sampler each,
// not an array: llvmpipe (LLVM 15) crashed compiling the direct pass with an array indexed by the grid.
layout(binding = UNIT_MEDIA_DENSITY) uniform sampler3D uMediaDensity0;
#if PREVIEW_MEDIA_GRIDS > 1
layout(binding = UNIT_MEDIA_DENSITY + 1) uniform sampler3D uMediaDensity1;
#endif
#if PREVIEW_MEDIA_GRIDS > 2
layout(binding = UNIT_MEDIA_DENSITY + 2) uniform sampler3D uMediaDensity2;
#endif
#if PREVIEW_MEDIA_GRIDS > 3
layout(binding = UNIT_MEDIA_DENSITY + 3) uniform sampler3D uMediaDensity3;
#endif

// Grid g's texel at texture coordinates uvw (explicit level: the callers sample in non-uniform control flow).
float gridTexel(int g, vec3 uvw) {
#if PREVIEW_MEDIA_GRIDS > 3
  if (g == 3) return textureLod(uMediaDensity3, uvw, 0.0).r;
#endif
#if PREVIEW_MEDIA_GRIDS > 2
  if (g == 2) return textureLod(uMediaDensity2, uvw, 0.0).r;
#endif
#if PREVIEW_MEDIA_GRIDS > 1
  if (g == 1) return textureLod(uMediaDensity1, uvw, 0.0).r;
#endif
  return textureLod(uMediaDensity0, uvw, 0.0).r;
}

// densityScale d of grid g at its texture (or index) coordinates p.
float gridDensityAt(int g, vec3 p) {
#if PREVIEW_MEDIA_GRID_NANOVDB
  if (gridInBuffer(g)) return mediaGrids[g].size.w * nanoVdbDensityAt(mediaGrids[g].bufferOffset.x, p);
#endif
  return mediaGrids[g].size.w * gridTexel(g, p);
}

// The most steps of one ray march through a grid. A march takes one step per voxel the segment crosses (its length
// in index coordinates), so a segment longer than this many voxels is marched with longer steps. One step per voxel
// keeps the optical depth within 1.3 % of a fine quadrature on cornell-smoke (tests/gl_smoke_test.cpp); four steps
// per voxel give 0.1 % at four times the cost, and no visible change in its images.
#define MEDIA_GRID_MAX_STEPS 256

// densityScale d(x) of grid g at the world point x.
float gridDensity(int g, vec3 x) { return gridDensityAt(g, (mediaGrids[g].textureFromWorld * vec4(x, 1.0)).xyz); }

// The integral of grid g's densityScale d over the points o + t d, t in [t0, t1] (d need not be unit: the integral is
// over world length), by the midpoint rule with one step per voxel crossed, at most MEDIA_GRID_MAX_STEPS. 0 when
// t0 >= t1.
float gridDensityIntegral(int g, vec3 o, vec3 d, float t0, float t1) {
  if (!(t1 > t0)) return 0.0;
  vec3 a = (mediaGrids[g].textureFromWorld * vec4(o + d * t0, 1.0)).xyz;
  vec3 b = (mediaGrids[g].textureFromWorld * vec4(o + d * t1, 1.0)).xyz;
  int steps = clamp(int(ceil(length((b - a) * mediaGrids[g].size.xyz))), 1, MEDIA_GRID_MAX_STEPS);
  vec3 stride = (b - a) / float(steps);
  float sum = 0.0;
  for (int i = 0; i < steps; ++i) sum += gridDensityAt(g, a + stride * (float(i) + 0.5));
  return sum * ((t1 - t0) * length(d) / float(steps));
}
#endif

// sigma_s of medium m at x, a point inside it (m may differ between lanes: each grid's test reads its own texture).
vec3 mediumSigmaS(int m, vec3 x) {
#ifdef PREVIEW_MEDIA_GRIDS
  for (int g = 0; g < PREVIEW_MEDIA_GRIDS; ++g)
    if (m == mediaGridMedium[g]) return media[m].sigmaS.rgb * gridDensity(g, x);
#endif
  return media[m].sigmaS.rgb;
}

// The parameter range [t0, t1] of o + t d inside medium m (empty when t0 >= t1); d need not be unit.
vec2 mediumRange(int m, vec3 o, vec3 d) {
  if (media[m].sigmaT.w > 0.5) return vec2(-1e30, 1e30);
  vec3 ob = (media[m].boxFromWorld * vec4(o, 1.0)).xyz;
  vec3 db = mat3(media[m].boxFromWorld) * d;
  // A zero component becomes a tiny one of either sign: the slab is then [-inf, inf] or empty, as it should be.
  vec3 inv = 1.0 / mix(db, vec3(1e-30), lessThan(abs(db), vec3(1e-30)));
  vec3 ta = (-1.0 - ob) * inv, tb = (1.0 - ob) * inv;
  vec3 lo = min(ta, tb), hi = max(ta, tb);
  return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}

// Optical depth per channel of o + t d for t in [tMin, tMax]. Where `needed` is false the grids' part is left out
// unmarched (the caller discards the result there): llvmpipe runs a march as long as its longest active lane, so a
// march skipped where a term is zero anyway (a back-facing or shadowed VPL or light) saves its steps. The closed forms
// are taken either way.
vec3 opticalDepth(vec3 o, vec3 d, float tMin, float tMax, bool needed) {
  vec3 depth = vec3(0.0);
  float len = length(d);
  for (int m = 0; m < PREVIEW_MEDIA; ++m) {
    vec2 r = mediumRange(m, o, d);
#ifdef PREVIEW_MEDIA_GRIDS
    int g = gridOfMedium(m);
    if (g >= 0) {
      depth += media[m].sigmaT.rgb * gridDensityIntegral(g, o, d, max(r.x, tMin), needed ? min(r.y, tMax) : tMin);
      continue;
    }
#endif
    depth += media[m].sigmaT.rgb * (max(0.0, min(r.y, tMax) - max(r.x, tMin)) * len);
  }
  return depth;
}

// Transmittance between two points (meaningless where `needed` is false, see opticalDepth).
vec3 mediaTransmittance(vec3 a, vec3 b, bool needed) { return exp(-opticalDepth(a, b - a, 0.0, 1.0, needed)); }

#else
vec3 mediaTransmittance(vec3 a, vec3 b, bool needed) { return vec3(1.0); }
#endif

// The transmittance between x and a light of the direct pass's table (preview/direct.frag.glsl): position.w 3 is a
// directional light arriving from -axis, anything else a point at position.xyz. Meaningless where `needed` is false.
vec3 mediaLightTransmittance(vec4 position, vec3 axis, vec3 x, bool needed) {
#if PREVIEW_MEDIA
  // One segment either way (a select of two would evaluate both).
  bool directional = position.w == 3.0;
  return exp(-opticalDepth(x, directional ? -axis : position.xyz - x, 0.0, directional ? 1e30 : 1.0, needed));
#else
  return vec3(1.0);
#endif
}
