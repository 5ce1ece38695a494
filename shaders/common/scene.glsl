// The scene as the GL passes see it (renderer/gl/gl_scene.cpp uploads it): per-vertex SSBOs fetched by
// gl_VertexID, per-triangle indices with the material in w, materials with the texture layer in baseColor.w.
#include "common/units.glsl"
struct GlMaterial {
  vec4 baseColor;  // rgb factor, w: layer in uSceneTextures or -1
  vec4 emission;   // rgb emitted radiance factor, w: layer of the emissive texture or -1
  vec4 params;     // metallic, roughness, specular, 0
  // Rows of the affine map from the vertex UVs to the emissive texture's coordinates (Material::emissiveUvTransform).
  vec4 emissiveUvRow0;
  vec4 emissiveUvRow1;
};

layout(std430, binding = BINDING_SCENE_POSITIONS) readonly buffer ScenePositions { vec4 scenePositions[]; };
layout(std430, binding = BINDING_SCENE_NORMALS) readonly buffer SceneNormals { vec4 sceneNormals[]; };
layout(std430, binding = BINDING_SCENE_UVS) readonly buffer SceneUvs { vec2 sceneUvs[]; };
layout(std430, binding = BINDING_SCENE_TRIANGLES) readonly buffer SceneTriangles { uvec4 sceneTriangles[]; };
layout(std430, binding = BINDING_SCENE_MATERIALS) readonly buffer SceneMaterials { GlMaterial sceneMaterials[]; };
