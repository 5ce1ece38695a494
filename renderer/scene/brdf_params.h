#pragma once
// The bridge from scene materials to the one BRDF: factors multiplied by textures at a surface point.

#include "renderer/core/brdf.h"
#include "renderer/scene/scene.h"

namespace vplab {

inline BrdfParams brdfParamsAt(const Scene& scene, uint32_t material, glm::vec2 uv) {
  const Material& m = scene.materials[material];
  BrdfParams p;
  p.baseColor = scene.baseColorAt(material, uv);
  p.metallic = m.metallic;
  p.roughness = m.roughness;
  p.specular = m.specular;
  return p;
}

}  // namespace vplab
