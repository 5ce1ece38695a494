#include "renderer/offline/embree_scene.h"

#include "renderer/offline/media_tracking.h"

#include "renderer/core/sampling.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplab {

namespace {

// One error callback on the device instead of checking every call (Embree tutorials); the message is kept so the
// build step can turn it into an exception.
void embreeErrorCallback(void* userPtr, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  auto* last = static_cast<std::string*>(userPtr);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
  std::fprintf(stderr, "vplab: %s\n", last->c_str());
}

}  // namespace

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string lastError;
};

EmbreeScene::EmbreeScene(const Scene& scene)
    : scene_(scene), hasMedia_(scene.hasMedia()), impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw std::runtime_error("cannot create an Embree device");
  rtcSetDeviceErrorFunction(impl_->device, embreeErrorCallback, &impl_->lastError);

  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);

  if (!scene.triangles.empty()) {
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), scene.positions.size()));
    for (std::size_t i = 0; i < scene.positions.size(); ++i) {
      vertices[3 * i + 0] = scene.positions[i].x;
      vertices[3 * i + 1] = scene.positions[i].y;
      vertices[3 * i + 2] = scene.positions[i].z;
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), scene.triangles.size()));
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
      indices[3 * i + 0] = scene.triangles[i].x;
      indices[3 * i + 1] = scene.triangles[i].y;
      indices[3 * i + 2] = scene.triangles[i].z;
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(impl_->scene);
  if (!impl_->lastError.empty()) throw std::runtime_error("building the BVH failed: " + impl_->lastError);

  // Offsets scale with the scene so that metre- and millimetre-sized scenes both avoid self-intersection.
  rayEpsilon_ = std::max(1e-6f, 1e-4f * scene.bounds.diagonal());
}

EmbreeScene::~EmbreeScene() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

std::optional<SurfaceHit> EmbreeScene::intersect(const glm::vec3& origin, const glm::vec3& direction,
                                                 float tMax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  std::memset(&rh, 0, sizeof(rh));
  rh.ray.org_x = origin.x;
  rh.ray.org_y = origin.y;
  rh.ray.org_z = origin.z;
  rh.ray.dir_x = direction.x;
  rh.ray.dir_y = direction.y;
  rh.ray.dir_z = direction.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = tMax;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  SurfaceHit hit;
  hit.distance = rh.ray.tfar;
  hit.triangle = rh.hit.primID;
  hit.material = scene_.triangleMaterials[hit.triangle];
  const glm::uvec3& tri = scene_.triangles[hit.triangle];
  float u = rh.hit.u, v = rh.hit.v, w = 1.0f - u - v;
  hit.position = origin + direction * rh.ray.tfar;
  hit.geometricNormal = scene_.geometricNormal(hit.triangle);
  glm::vec3 n = w * scene_.normals[tri.x] + u * scene_.normals[tri.y] + v * scene_.normals[tri.z];
  float len = glm::length(n);
  hit.shadingNormal = len > 0.0f ? n / len : hit.geometricNormal;
  hit.uv = w * scene_.uvs[tri.x] + u * scene_.uvs[tri.y] + v * scene_.uvs[tri.z];
  return hit;
}

bool EmbreeScene::occluded(const glm::vec3& origin, const glm::vec3& direction, float tMax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  std::memset(&ray, 0, sizeof(ray));
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = direction.x;
  ray.dir_y = direction.y;
  ray.dir_z = direction.z;
  ray.tnear = 0.0f;
  ray.tfar = tMax;
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(impl_->scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

void EmbreeScene::occludedBatch(const ShadowRay* rays, uint8_t* occludedOut, std::size_t count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  for (std::size_t base = 0; base < count; base += 8) {
    std::size_t lanes = std::min<std::size_t>(8, count - base);
    // Zero-filled packet: inactive lanes must still hold finite values (Debian's Embree has assertions on).
    alignas(32) RTCRay8 packet;
    std::memset(&packet, 0, sizeof(packet));
    alignas(32) int valid[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (std::size_t l = 0; l < lanes; ++l) {
      const ShadowRay& r = rays[base + l];
      packet.org_x[l] = r.origin.x;
      packet.org_y[l] = r.origin.y;
      packet.org_z[l] = r.origin.z;
      packet.dir_x[l] = r.direction.x;
      packet.dir_y[l] = r.direction.y;
      packet.dir_z[l] = r.direction.z;
      packet.tnear[l] = 0.0f;
      packet.tfar[l] = r.tMax;
      packet.mask[l] = 0xFFFFFFFFu;
      valid[l] = -1;
    }
    rtcOccluded8(valid, impl_->scene, &context, &packet);
    for (std::size_t l = 0; l < lanes; ++l) occludedOut[base + l] = packet.tfar[l] < 0.0f ? 1 : 0;
  }
}

glm::vec3 EmbreeScene::offsetOrigin(const glm::vec3& p, const glm::vec3& geometricNormal, const glm::vec3& dir) const {
  float side = glm::dot(geometricNormal, dir) >= 0.0f ? 1.0f : -1.0f;
  return p + geometricNormal * (side * rayEpsilon_);
}

ShadowRay EmbreeScene::shadowRayBetween(const glm::vec3& p0, const glm::vec3& n0, const glm::vec3& p1,
                                        const glm::vec3& n1) const {
  glm::vec3 d = p1 - p0;
  glm::vec3 o0 = offsetOrigin(p0, n0, d);
  glm::vec3 o1 = offsetOrigin(p1, n1, -d);
  ShadowRay ray;
  ray.origin = o0;
  glm::vec3 seg = o1 - o0;
  float len = glm::length(seg);
  if (!(len > 0.0f)) {
    ray.tMax = 0.0f;
    return ray;
  }
  ray.direction = seg / len;
  ray.tMax = len;
  return ray;
}

bool EmbreeScene::visible(const glm::vec3& p0, const glm::vec3& n0, const glm::vec3& p1, const glm::vec3& n1) const {
  ShadowRay r = shadowRayBetween(p0, n0, p1, n1);
  if (!(r.tMax > 0.0f)) return true;
  return !occluded(r.origin, r.direction, r.tMax);
}

namespace {

/// The media intervals of the ray being traced: one list per thread, so tracing allocates nothing once warm.
std::vector<MediumInterval>& intervalScratch() {
  thread_local std::vector<MediumInterval> intervals;
  return intervals;
}

}  // namespace

Segment EmbreeScene::beginSegment(const glm::vec3& origin, const glm::vec3& direction, float tMax) const {
  Segment s;
  s.hit = intersect(origin, direction, tMax);
  if (s.hit) {
    s.end = Segment::End::Surface;
    s.distance = s.hit->distance;
    s.position = s.hit->position;
  } else {
    s.distance = tMax;
  }
  s.surfaceDistance = s.distance;
  if (!hasMedia_) return s;
  std::vector<MediumInterval>& intervals = intervalScratch();
  mediumIntervals(scene_.media, origin, direction, s.distance, intervals);
  s.crossedMedium = !intervals.empty();
  return s;
}

void EmbreeScene::sampleFreeFlight(Segment& s, const glm::vec3& origin, const glm::vec3& direction,
                                   glm::vec2 u) const {
  // The intervals beginSegment() found (nothing has traced on this thread since): a free flight through them
  // (closed form in homogeneous media, delta tracking through grids), weighted by spectral MIS per segment.
  const FreeFlight flight = sampleFlight(scene_.media, intervalScratch(), origin, direction, s.distance, u);
  const float mean = (flight.p.x + flight.p.y + flight.p.z) * (1.0f / 3.0f);
  s.weight = mean > 0.0f ? flight.f / mean : glm::vec3(0.0f);
  s.spectralF = flight.f;
  s.spectralP = flight.p;
  if (!flight.scattered) return;
  s.end = Segment::End::Medium;
  s.hit.reset();
  s.distance = flight.t;
  s.position = origin + direction * flight.t;
  s.medium = flight.medium;
}

glm::vec3 EmbreeScene::transmittance(const glm::vec3& origin, const glm::vec3& direction, float tMax) const {
  if (!hasMedia_) return glm::vec3(1.0f);
  std::vector<MediumInterval>& intervals = intervalScratch();
  mediumIntervals(scene_.media, origin, direction, tMax, intervals);
  return transmittanceAlong(scene_.media, intervals, origin, direction, tMax);
}

glm::vec3 EmbreeScene::shadowTransmittance(const ShadowRay& ray, float mediumTMax) const {
  if (ray.tMax > 0.0f && occluded(ray.origin, ray.direction, ray.tMax)) return glm::vec3(0.0f);
  if (!hasMedia_) return glm::vec3(1.0f);
  return transmittance(ray.origin, ray.direction, mediumTMax >= 0.0f ? mediumTMax : ray.tMax);
}

}  // namespace vplab
