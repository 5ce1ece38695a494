#include "renderer/gl/gl_scene.h"

#include <glad/gl.h>

#include <algorithm>
#include <cassert>

#include "renderer/gl/texture_units.h"

namespace vplab {

GlScene::GlScene(const Scene& scene) : triangleCount_(static_cast<int>(scene.triangles.size())) {
  assert(scene.normals.size() == scene.positions.size() && scene.uvs.size() == scene.positions.size());
  std::vector<glm::vec4> p(scene.positions.size()), n(scene.normals.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    p[i] = glm::vec4(scene.positions[i], 1.0f);
    n[i] = glm::vec4(scene.normals[i], 0.0f);
  }
  std::vector<glm::uvec4> t(scene.triangles.size());
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = glm::uvec4(scene.triangles[i], scene.triangleMaterials[i]);

  int size = 1;
  for (const Texture& tex : scene.textures) size = std::max({size, tex.width, tex.height});
  size = std::min(size, kMaxTextureSize);
  struct MaterialGpu {
    glm::vec4 baseColor, emission, params, emissiveUvRow0, emissiveUvRow1;
  };
  std::vector<MaterialGpu> m(scene.materials.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Material& mat = scene.materials[i];
    textured_ = textured_ || mat.baseColorTexture >= 0 || mat.emissiveTexture >= 0;
    const glm::mat3& uv = mat.emissiveUvTransform;  // column-major: uv[column][row]
    m[i] = {glm::vec4(mat.baseColor, static_cast<float>(mat.baseColorTexture)),
            glm::vec4(mat.emission, static_cast<float>(mat.emissiveTexture)),
            glm::vec4(mat.metallic, mat.roughness, mat.specular, 0.0f), glm::vec4(uv[0][0], uv[1][0], uv[2][0], 0.0f),
            glm::vec4(uv[0][1], uv[1][1], uv[2][1], 0.0f)};
  }
  positions_.assign(p.data(), p.size() * sizeof(glm::vec4));
  normals_.assign(n.data(), n.size() * sizeof(glm::vec4));
  uvs_.assign(scene.uvs.data(), scene.uvs.size() * sizeof(glm::vec2));
  triangles_.assign(t.data(), t.size() * sizeof(glm::uvec4));
  materials_.assign(m.data(), m.size() * sizeof(MaterialGpu));

  int layers = std::max<int>(1, static_cast<int>(scene.textures.size()));
  textures_ = GlTexture(size, size, TextureFormat::Rgba32F, 1, layers, true);
  textures_.setRepeat(true);
  std::vector<glm::vec4> texels(static_cast<std::size_t>(size) * size);
  for (std::size_t layer = 0; layer < scene.textures.size(); ++layer) {
    // GL's t = 0 is the first row uploaded, matching glTF's v = 0 at the top row of Texture::texels.
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        texels[static_cast<std::size_t>(y) * size + x] =
            glm::vec4(scene.textures[layer].sample(
                          {(x + 0.5f) / static_cast<float>(size), (y + 0.5f) / static_cast<float>(size)}),
                      1.0f);
    textures_.uploadLayerRgba(static_cast<int>(layer), texels);
  }
}

void GlScene::bind() const {
  positions_.bindStorage(binding(BufferBinding::ScenePositions));
  normals_.bindStorage(binding(BufferBinding::SceneNormals));
  uvs_.bindStorage(binding(BufferBinding::SceneUvs));
  triangles_.bindStorage(binding(BufferBinding::SceneTriangles));
  materials_.bindStorage(binding(BufferBinding::SceneMaterials));
  textures_.bind(unit(TextureUnit::SceneTextures));
}

}  // namespace vplab
