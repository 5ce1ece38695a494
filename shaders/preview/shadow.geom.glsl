#version 450 core
// Layered rendering of one caster's map per instance (renderer/gl/shadow_maps.h): the six faces of a whole cube, or
// the five of a hemicube, whose four side faces keep their upper half (clip distances) and share two layers.
#include "common/units.glsl"
#include "common/math.glsl"
layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;

struct ShadowCaster {
  vec4 position;  // w: first layer in the chunk
  vec4 normal;    // xyz: a hemicube's normal; w: 1 for a hemicube
};
layout(std430, binding = BINDING_SHADOW_CASTERS) readonly buffer Casters { ShadowCaster casters[]; };

uniform mat3 uFaceRotation[6];
uniform mat4 uProjection;
uniform int uFirstCaster;

in vec3 vPosition[];
flat in int vCaster[];
out vec3 gOffset;
out gl_PerVertex {
  vec4 gl_Position;
  float gl_ClipDistance[2];
};

void main() {
  ShadowCaster caster = casters[uFirstCaster + vCaster[0]];
  int face = gl_InvocationID;
  bool hemicube = caster.normal.w > 0.5;
  if (hemicube && face == 5) return;
  mat3 view = uFaceRotation[face];
  int layer = int(caster.position.w) + face;
  // A side face of a hemicube: only its upper half, y_clip in [0, w_clip], drawn into the upper (+s, +t) or lower
  // (-s, -t) half of its layer (common/shadow.glsl hemicubeVisibilityAt reads it back).
  bool halfFace = hemicube && face > 0;
  float lower = 0.0;
  if (hemicube) {
    vec3 n = caster.normal.xyz, s, t;
    orthonormalFrame(n, s, t);
    // Rows of the view: face 0 looks along n (x = s, y = t); faces 1-4 along +s, -s, +t, -t with n up.
    float sgn = (face == 1 || face == 3) ? 1.0 : -1.0;
    vec3 along = face <= 2 ? s : t, across = face <= 2 ? t : s;
    view = face == 0 ? transpose(mat3(s, t, -n)) : transpose(mat3(across, n, -sgn * along));
    layer = int(caster.position.w) + (face == 0 ? 0 : face <= 2 ? 1 : 2);
    lower = halfFace && sgn < 0.0 ? 1.0 : 0.0;
  }
  vec3 origin = caster.position.xyz;
  vec4 clip[3];
  for (int i = 0; i < 3; ++i) clip[i] = uProjection * vec4(view * (vPosition[i] - origin), 1.0);
  // A triangle wholly outside one side of the face's frustum (or below a half face's horizon) is not emitted: most
  // triangles lie in one or two of a caster's faces, and the rasteriser's clipping and setup of the others cost more
  // than these comparisons.
  // Each test is one clip-space half-space (linear in the vertices), so all three vertices outside it put the whole
  // triangle outside.
  bvec4 allOut = bvec4(true);
  bool allBeforeNear = true, allBelow = true;
  for (int i = 0; i < 3; ++i) {
    vec4 c = clip[i];
    allOut = bvec4(allOut.x && c.x > c.w, allOut.y && c.x < -c.w, allOut.z && c.y > c.w, allOut.w && c.y < -c.w);
    allBeforeNear = allBeforeNear && c.z < -c.w;
    allBelow = allBelow && c.y < 0.0;
  }
  if (any(allOut) || allBeforeNear || (halfFace && allBelow)) return;
  for (int i = 0; i < 3; ++i) {
    gOffset = vPosition[i] - origin;
    vec4 c = clip[i];
    gl_ClipDistance[0] = halfFace ? c.y : 1.0;
    gl_ClipDistance[1] = halfFace ? c.w - c.y : 1.0;
    c.y -= lower * c.w;
    gl_Position = c;
    gl_Layer = layer;
    EmitVertex();
  }
  EndPrimitive();
}
