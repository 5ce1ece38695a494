#pragma once
// The whole world vplab renders: flattened world-space triangles, materials, lights and one camera.
// glTF node transforms are baked at load time; there is no scene graph.

#include "renderer/core/object_id.h"
#include "renderer/scene/medium.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace vplab {

/// Linear-RGB texture; texels are stored linear (sRGB base-colour textures are decoded at load time).
struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> texels;  ///< row-major, row 0 at v = 0 (glTF convention: uv (0,0) is the top-left)

  /// Bilinear lookup with repeat wrapping (glTF's default sampler).
  glm::vec3 sample(glm::vec2 uv) const;
};

/// glTF metallic-roughness material, reduced to one diffuse and one GGX lobe.
struct Material {
  std::string name;
  glm::vec3 baseColor{1.0f};  ///< linear RGB factor, multiplied by the texture when there is one
  int baseColorTexture = -1;  ///< index into Scene::textures, -1 for none
  float metallic = 0.0f;      ///< [0, 1]
  float roughness = 1.0f;     ///< perceptual roughness [0, 1]; GGX alpha = roughness^2
  float specular = 1.0f;      ///< KHR_materials_specular specularFactor [0, 1]; 0 = pure Lambert dielectric
  /// Emitted radiance (emissiveFactor * KHR_materials_emissive_strength), cd/m^2; multiplied by the emissive texture
  /// when there is one (Scene::emissionAt).
  glm::vec3 emission{0.0f};
  int emissiveTexture = -1;  ///< index into Scene::textures (decoded from sRGB like the base colour), -1 for none
  /// Maps Scene::uvs to the emissive texture's coordinates (homogeneous 2D affine map): the loader bakes the base
  /// colour's KHR_texture_transform into the UVs, so this undoes it and applies the emissive texture's own.
  glm::mat3 emissiveUvTransform{1.0f};

  bool isEmissive() const { return emission.r > 0.0f || emission.g > 0.0f || emission.b > 0.0f; }
};

/// KHR_lights_punctual light. vplab renders in photometric units throughout (emissive radiance in cd/m^2), so no
/// 683 lm/W factor is applied anywhere: point and spot intensities are in candela, a directional light's in lux, as
/// the extension defines them.
struct PunctualLight {
  /// Point and Spot sit at `position`; Directional has no position: it is a light at infinity whose parallel rays
  /// travel along `direction` (docs/methods.md, "Directional lights").
  enum class Type { Point, Spot, Directional };
  std::string name;
  Type type = Type::Point;
  glm::vec3 position{0.0f};                ///< world space; unused by Directional
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  ///< spot axis, or the direction a directional light's rays travel (unit)
  /// colour * intensity: radiant intensity in candela (Point, Spot), or for Directional the irradiance in lux that
  /// it delivers to a surface facing it (perpendicular to `direction`).
  glm::vec3 intensity{1.0f};
  float innerConeAngle = 0.0f;           ///< radians, Spot only
  float outerConeAngle = 0.7853981634f;  ///< radians (glTF default pi/4), Spot only

  bool isDirectional() const { return type == Type::Directional; }
  /// Radiant intensity toward a unit direction leaving a Point or Spot light (spot falloff as the extension defines).
  glm::vec3 intensityToward(const glm::vec3& dirFromLight) const;
  /// Integral of intensityToward() over the sphere: the flux of a Point or Spot light (lumens).
  glm::vec3 flux() const;
};

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 1.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  ///< unit view direction
  glm::vec3 up{0.0f, 1.0f, 0.0f};        ///< unit, orthogonal to forward
  float yfov = 0.6911f;                  ///< vertical field of view, radians
  float znear = 0.01f;
  float zfar = 1000.0f;
  bool fromFile = false;  ///< false when vplab framed the scene bounds itself

  glm::vec3 right() const { return glm::normalize(glm::cross(forward, up)); }
  /// World-space direction through film point ndc in [-1,1]^2 (+y up) for an image of the given aspect.
  glm::vec3 rayDirection(glm::vec2 ndc, float aspect) const;
};

struct Bounds {
  glm::vec3 lower{std::numeric_limits<float>::max()};
  glm::vec3 upper{-std::numeric_limits<float>::max()};
  void extend(const glm::vec3& p) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  bool valid() const { return lower.x <= upper.x; }
  glm::vec3 center() const { return 0.5f * (lower + upper); }
  glm::vec3 extent() const { return upper - lower; }
  float diagonal() const { return valid() ? glm::length(extent()) : 0.0f; }
};

struct Scene {
  /// Every scene made has its own (copies keep it): with its address, how a renderer tells another scene from the one
  /// it uploaded, also when a new scene takes the place of the old one in the same variable. Edits in place keep it
  /// (the renderers' invalidate calls say so).
  std::uint64_t id = newObjectId();
  std::string sourcePath;

  // Per-vertex, world space.
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  ///< unit; face normals where the file had none
  std::vector<glm::vec2> uvs;      ///< TEXCOORD_0, zero where the file had none

  // Per triangle.
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> triangleMaterials;  ///< index into materials

  std::vector<Material> materials;
  std::vector<Texture> textures;

  std::vector<uint32_t> emissiveTriangles;  ///< triangles whose material emits: the area lights
  std::vector<PunctualLight> punctualLights;
  /// Homogeneous participating media (glTF extension VPLAB_participating_media, docs/scenes.md): disjoint boxes, or
  /// one medium filling all space. Empty for a scene without media, whose images are exactly those of a scene that
  /// never heard of them.
  std::vector<Medium> media;

  Camera camera;
  /// Triangles plus the positions of Point and Spot lights: what shadow-map ranges and ray offsets must cover.
  Bounds bounds;
  /// Triangles only: what the automatic camera frames and a directional light's emission disk covers.
  Bounds geometryBounds;

  std::vector<std::string> warnings;      ///< non-fatal problems found while loading
  /// What staging added (renderer/scene/staging.h), one line; empty when the scene is as the file describes it.
  std::string staging;
  /// Numeric members of the file's asset.extras: facts a generated scene records for its tests (e.g. the furnace's
  /// "albedo" and "expectedRadiance").
  std::map<std::string, double> assetExtras;
  std::size_t degenerateTrianglesDropped = 0;

  bool hasLights() const { return !emissiveTriangles.empty() || !punctualLights.empty(); }
  /// True when some medium absorbs or scatters: the passes then trace rays through media.
  bool hasMedia() const;
  const Material& materialOf(uint32_t triangle) const { return materials[triangleMaterials[triangle]]; }
  /// Unit normal from the winding order (loaders make it agree with the vertex normals). Cached by finalize().
  glm::vec3 geometricNormal(uint32_t triangle) const {
    return triangle < faceNormals_.size() ? faceNormals_[triangle] : computeGeometricNormal(triangle);
  }
  /// Cached by finalize().
  float triangleArea(uint32_t triangle) const {
    return triangle < faceAreas_.size() ? faceAreas_[triangle] : computeTriangleArea(triangle);
  }
  /// Base colour at a surface point (factor times texture).
  glm::vec3 baseColorAt(uint32_t material, glm::vec2 uv) const;
  /// Emitted radiance at a surface point (factor times emissive texture), cd/m^2.
  glm::vec3 emissionAt(uint32_t material, glm::vec2 uv) const;
  /// Mean emitted radiance over a triangle (emissionAt averaged over its area): its power is pi x area x this.
  /// The texture's mean over the triangle's UV footprint is cached by finalize().
  glm::vec3 meanEmission(uint32_t triangle) const {
    const glm::vec3& factor = materialOf(triangle).emission;
    return triangle < emissionTextureMeans_.size() ? factor * emissionTextureMeans_[triangle] : factor;
  }
  /// Texture coordinates at barycentrics b (weight b.x on corner x, b.y on y, 1 - b.x - b.y on z).
  glm::vec2 uvAt(uint32_t triangle, glm::vec2 b) const {
    const glm::uvec3& t = triangles[triangle];
    return b.x * uvs[t.x] + b.y * uvs[t.y] + (1.0f - b.x - b.y) * uvs[t.z];
  }

  /// Recomputes bounds (geometryBounds and the punctual lights' positions) after a punctual light moved: what
  /// finalize() would change then, without its passes over the triangles.
  void updateBounds();
  /// Recomputes bounds, geometryBounds, emissiveTriangles and the per-triangle normal, area and emissive-texture mean
  /// caches from the geometry and materials.
  /// Loaders and builders call it last, and so does anything that edits positions afterwards.
  void finalize();

 private:
  glm::vec3 computeGeometricNormal(uint32_t triangle) const;
  float computeTriangleArea(uint32_t triangle) const;
  glm::vec3 computeEmissionTextureMean(uint32_t triangle) const;
  // Hit points, light samples and pdfs ask for these per ray: recomputing the cross product showed up in profiles.
  std::vector<glm::vec3> faceNormals_;
  std::vector<float> faceAreas_;
  /// Per triangle, the mean of its material's emissive texture over the triangle (1 without a texture); empty when no
  /// emissive material has a texture.
  std::vector<glm::vec3> emissionTextureMeans_;
};

}  // namespace vplab
