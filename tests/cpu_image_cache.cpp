#include "tests/cpu_image_cache.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "renderer/core/fnv1a.h"
#include "renderer/image/image_io.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/scene/density_grid.h"
#include "renderer/scene/scene.h"
#include "renderer/settings_json.h"
#include "renderer/vpl/vpl.h"

namespace vplab::test {
namespace {

// FNV-1a over the bytes fed to it, field by field (never whole structs: their padding is not theirs to hash).
class Digest {
 public:
  void bytes(const void* data, std::size_t size) { hash_.add(data, size); }
  template <class T>
  void value(const T& v) {
    static_assert(std::has_unique_object_representations_v<T> || std::is_floating_point_v<T>);
    bytes(&v, sizeof v);
  }
  void vec(const glm::vec2& v) { bytes(&v[0], sizeof(float) * 2); }
  void vec(const glm::vec3& v) { bytes(&v[0], sizeof(float) * 3); }
  void mat(const glm::mat4& m) { bytes(&m[0][0], sizeof(float) * 16); }
  void text(const std::string& s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  template <class T>
  void array(const std::vector<T>& v) {
    value(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  void vpl(const Vpl& v) {
    vec(v.position), vec(v.normal), vec(v.geometricNormal), vec(v.incoming), vec(v.flux), vec(v.uv);
    value(v.material), value(v.bounce), value(v.radius), value(v.inMedium), value(v.medium);
  }
  std::string hex() const { return hash_.hex(); }

 private:
  Fnv1a64 hash_;
};

std::string digestOf(const std::string& text) {
  Digest d;
  d.text(text);
  return d.hex();
}

}  // namespace

std::string renderInputs(const Scene& scene, const Settings& settings, const VplSet* vpls) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::uvec3) == 3 * sizeof(uint32_t));
  Digest d;
  d.text(scene.sourcePath);
  d.array(scene.positions), d.array(scene.normals), d.array(scene.uvs), d.array(scene.triangles);
  d.array(scene.triangleMaterials);
  for (const Material& m : scene.materials) {
    d.vec(m.baseColor), d.value(m.baseColorTexture), d.value(m.metallic), d.value(m.roughness), d.value(m.specular);
    d.vec(m.emission), d.value(m.emissiveTexture), d.bytes(&m.emissiveUvTransform[0][0], sizeof(float) * 9);
  }
  for (const Texture& t : scene.textures) d.value(t.width), d.value(t.height), d.array(t.texels);
  for (const PunctualLight& p : scene.punctualLights) {
    d.value(static_cast<int>(p.type)), d.vec(p.position), d.vec(p.direction), d.vec(p.intensity);
    d.value(p.innerConeAngle), d.value(p.outerConeAngle);
  }
  for (const Medium& m : scene.media) {
    d.vec(m.sigmaA), d.vec(m.sigmaS), d.value(m.g), d.value(m.fillsSpace), d.mat(m.worldFromBox);
    d.value(m.densityScale), d.mat(m.indexFromWorld);
    if (m.density) d.array(m.density->values);
  }
  const Camera& c = scene.camera;
  d.vec(c.position), d.vec(c.forward), d.vec(c.up), d.value(c.yfov), d.value(c.znear), d.value(c.zfar);
  d.text(settingsToJson(settings));
  if (vpls) {
    d.value(vpls->vpls.size());
    for (const Vpl& v : vpls->vpls) d.vpl(v);
    d.value(vpls->vrls.size());
    for (const Vrl& r : vpls->vrls) {
      d.vec(r.start), d.vec(r.direction), d.value(r.t0), d.value(r.t1), d.vec(r.flux), d.value(r.medium);
    }
  }
  return d.hex();
}

Image imageInFolder(const std::string& folder, const std::string& key, const std::function<Image()>& render) {
  const std::string base = (std::filesystem::path(folder) / digestOf(key)).string();
  const std::string imagePath = base + ".pfm", keyPath = base + ".key";
  const int lock = ::open((base + ".lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  Image image;
  try {
    std::ifstream keyFile(keyPath);
    std::stringstream stored;
    stored << keyFile.rdbuf();
    if (keyFile && stored.str() == key) image = readPfm(imagePath);
  } catch (const std::exception&) {
    image = Image();
  }
  if (image.empty()) {
    image = render();
    // The key first, then the image by rename: a reader sees a whole image or none.
    const std::string partial = imagePath + ".partial";
    writePfm(partial, image);
    std::ofstream(keyPath) << key;
    std::filesystem::rename(partial, imagePath);
  }
  if (lock >= 0) ::close(lock);  // releases the flock
  return image;
}

const Image& cachedCpu(const std::string& what, const std::string& inputs, const std::function<Image()>& render) {
  static std::mutex mutex;
  static std::map<std::string, Image> images;
  const std::string key = what + " | " + inputs;
  std::lock_guard<std::mutex> guard(mutex);
  auto it = images.find(key);
  if (it != images.end()) return it->second;
  const char* folder = std::getenv("VPLAB_TEST_IMAGE_CACHE");
  Image image = folder && *folder ? imageInFolder(folder, key, render) : render();
  return images.emplace(key, std::move(image)).first->second;
}

const Image& cachedVplRender(const OfflineScene& l, const VplSet& vpls, Method method, const Settings& settings) {
  return cachedCpu(std::string("renderVpl ") + toString(method), renderInputs(l.scene(), settings, &vpls),
                   [&] { return renderVpl(l, vpls, method, settings).image; });
}

const Image& cachedReference(const OfflineScene& l, const Settings& settings) {
  return cachedCpu("renderReference", renderInputs(l.scene(), settings),
                   [&] { return renderReference(l, settings).image; });
}

}  // namespace vplab::test
