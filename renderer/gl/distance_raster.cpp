#include "renderer/gl/distance_raster.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"

namespace vplab {

namespace {

// Rows of one band: a band is one work item of draw(), and one list of triangles per chunk of the scene.
constexpr int kBandRows = 64;
// Triangles per chunk of binning (a work item of bin()); at most kMaxChunks chunks.
constexpr std::size_t kChunkTriangles = 1 << 15;
constexpr std::size_t kMaxChunks = 64;
// Triangles at most this many texels wide are rasterized by testing each texel of their bounding box.
constexpr int kNarrow = 4;

// A triangle's coverage in a view: texel (x, y) in [-1, 1]^2 is covered where edge[k].x + edge[k].y x + edge[k].z y >=
// 0 for k = 0, 1, 2.
struct Edges {
  std::array<glm::vec3, 3> edge;
  bool covers(float x, float y) const {
    for (const glm::vec3& e : edge)
      if (e.x + e.y * x + e.z * y < 0.0f) return false;
    return true;
  }
};

// The texels [first, last] within [i0, i1] of the row at y that the edges cover: the span is solved from the edges with
// a texel of margin, and its ends tested exactly, so that a texel centre on an edge shared by two triangles is covered
// by both (no cracks). Each edge function is monotonic along the row in floating point too, so the covered texels are
// one run. False when there are none.
bool coveredSpan(const Edges& edges, float y, int i0, int i1, int size, int& first, int& last) {
  float lo = -2.0f, hi = 2.0f;
  for (const glm::vec3& e : edges.edge) {
    const float base = e.x + e.z * y;
    if (e.y > 0.0f)
      lo = std::max(lo, -base / e.y);
    else if (e.y < 0.0f)
      hi = std::min(hi, -base / e.y);
    else if (base < 0.0f)
      return false;
  }
  if (!(lo <= hi)) return false;
  const float half = 0.5f * static_cast<float>(size);
  const float fl = std::clamp((lo + 1.0f) * half - 0.5f, -2.0f, static_cast<float>(size) + 2.0f);
  const float fh = std::clamp((hi + 1.0f) * half - 0.5f, -2.0f, static_cast<float>(size) + 2.0f);
  first = std::max(i0, static_cast<int>(fl + 3.0f) - 3);
  last = std::min(i1, -(static_cast<int>(3.0f - fh) - 3));
  const float step = 2.0f / static_cast<float>(size);
  auto covered = [&](int i) { return edges.covers((static_cast<float>(i) + 0.5f) * step - 1.0f, y); };
  while (first <= last && !covered(first)) ++first;
  while (last >= first && !covered(last)) --last;
  return first <= last;
}

// The texels [lo, hi] whose centres lie within [cmin, cmax] of a view's [-1, 1] coordinate (a thousandth of a texel
// wider, for rounding: the exact test is the edges'); false when there are none. Most triangles of a dense mesh cover
// no texel centre and stop here.
inline bool texelRange(float cmin, float cmax, int size, int& lo, int& hi) {
  const float half = 0.5f * static_cast<float>(size);
  const float fl = std::clamp((cmin + 1.0f) * half - 0.5f - 1e-3f, -2.0f, static_cast<float>(size) + 2.0f);
  const float fh = std::clamp((cmax + 1.0f) * half - 0.5f + 1e-3f, -2.0f, static_cast<float>(size) + 2.0f);
  // floor and ceil by truncating positive numbers (fl, fh > -3): SSE2 has no rounding instruction.
  lo = std::max(0, -(static_cast<int>(3.0f - fl) - 3));
  hi = std::min(size - 1, static_cast<int>(fh + 3.0f) - 3);
  return lo <= hi;
}

// Texels [first, last] of a cube face's row at y, covered by a triangle: along the ray r = (x, y, 1) its plane lies at
// |det| / sum times r (sum: of the edge functions, sumAtY + sumSlope.x x along the row), |r|^2 = 1 + x^2 + y^2, and
// d ln(dist) / dx = x / |r|^2 - sumSlope.x / sum (y likewise). Branch-free, so that it runs on SIMD lanes (the file is
// built without errno and traps from floating point). Without a slope bias (kBiased false: the VPLs' maps) the slope
// is not computed.
template <bool kBiased>
void faceSpan(float* row, int first, int last, float step, float y, float sumAtY, glm::vec2 sumSlope, float absDet,
              float dmax, float maxSlopeBias, float near) {
  for (int i = first; i <= last; ++i) {
    const float x = (static_cast<float>(i) + 0.5f) * step - 1.0f;
    const float sum = sumAtY + sumSlope.x * x;
    const float inverseSum = 1.0f / (sum > 1e-30f ? sum : 1e-30f);
    const float r2 = 1.0f + x * x + y * y, inverseR2 = 1.0f / r2;
    // The hit lies absDet / sum along the face's axis (r's axis component is 1).
    const float axial = absDet * inverseSum;
    const float along = axial * std::sqrt(r2);
    const float dist = along < dmax ? along : dmax;
    float value = dist;
    if constexpr (kBiased) {
      const float slope =
          step * dist *
          (std::fabs(x * inverseR2 - sumSlope.x * inverseSum) + std::fabs(y * inverseR2 - sumSlope.y * inverseSum));
      const float bound = maxSlopeBias * dist;
      value += slope < bound ? slope : bound;
    }
    row[i] = value < row[i] && axial >= near ? value : row[i];
  }
}

// Texels [first, last] of the plane's row, covered by a triangle whose distance is zAtY + slope x there (clamped to its
// corners' range), plus its bias.
void planeSpan(float* row, int first, int last, float step, float zAtY, float slope, float zmin, float zmax,
               float bias) {
  for (int i = first; i <= last; ++i) {
    const float x = (static_cast<float>(i) + 0.5f) * step - 1.0f;
    const float z = zAtY + slope * x;
    const float value = (z < zmin ? zmin : z > zmax ? zmax : z) + bias;
    row[i] = value < row[i] ? value : row[i];
  }
}

}  // namespace

void DistanceRasterizer::binCube(const Scene& scene, glm::vec3 origin, int size, int threads, float near) {
  // GL 4.6 table 8.19: face f's texel at (sc, tc) in [-1, 1]^2 looks along axis + sc s + tc t.
  static const glm::vec3 kFaces[6][3] = {{{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
                                         {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
                                         {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}}};
  perspective_ = true;
  origin_ = origin;
  size_ = size;
  near_ = near;
  views_.clear();
  for (const auto& face : kFaces) {
    View view{face[1], face[2], face[0], {}, {}, true, 0};
    // Each of s, t, axis is a signed unit axis: the local coordinates are signed components.
    for (int c = 0; c < 3; ++c) {
      const glm::vec3& unitAxis = face[(c + 1) % 3];
      for (int k = 0; k < 3; ++k)
        if (unitAxis[k] != 0.0f) view.index[c] = k, view.sign[c] = unitAxis[k];
    }
    views_.push_back(view);
  }
  bin(scene, threads);
}

void DistanceRasterizer::binPerspective(const Scene& scene, glm::vec3 origin, const std::vector<Perspective>& views,
                                        int size, int threads, float near) {
  perspective_ = true;
  origin_ = origin;
  size_ = size;
  near_ = near;
  views_.clear();
  for (const Perspective& v : views) views_.push_back({v.s, v.t, v.axis, {}, {}, false, v.firstRow});
  bin(scene, threads);
}

void DistanceRasterizer::binPlane(const Scene& scene, glm::vec3 direction, glm::vec3 centre, float radius, int size,
                                  int threads) {
  const Frame frame(direction);
  perspective_ = false;
  origin_ = centre - direction * radius;
  radius_ = radius;
  size_ = size;
  views_ = {{frame.s / radius, frame.t / radius, direction, {}, {}, false, 0}};
  bin(scene, threads);
}

void DistanceRasterizer::bin(const Scene& scene, int threads) {
  scene_ = &scene;
  bands_ = (size_ + kBandRows - 1) / kBandRows;
  const std::size_t triangleCount = scene.triangles.size();
  chunks_ =
      static_cast<int>(std::clamp<std::size_t>((triangleCount + kChunkTriangles - 1) / kChunkTriangles, 1, kMaxChunks));
  const std::size_t perChunk =
      (triangleCount + static_cast<std::size_t>(chunks_) - 1) / static_cast<std::size_t>(chunks_);
  buckets_.resize(static_cast<std::size_t>(chunks_) * views_.size() * static_cast<std::size_t>(bands_));
  for (std::vector<Entry>& b : buckets_) b.clear();

  // Which of each view's four edge planes every vertex lies beyond (x or y beyond -1 or +1, x = local x / local z in
  // a cube face), widened by a millionth of its distance so that rounding never drops a triangle on a view's edge.
  outside_.resize(scene.positions.size());
  const int64_t vertexBlocks = (static_cast<int64_t>(outside_.size()) + 65535) / 65536;
  parallelFor(vertexBlocks, threads, [&](int64_t block, int) {
    const std::size_t end = std::min(outside_.size(), static_cast<std::size_t>(block + 1) * 65536);
    for (std::size_t v = static_cast<std::size_t>(block) * 65536; v < end; ++v) {
      const glm::vec3 d = scene.positions[v] - origin_;
      const float slack = 1e-6f * (std::abs(d.x) + std::abs(d.y) + std::abs(d.z));
      uint32_t bits = 0;
      for (std::size_t f = 0; f < views_.size(); ++f) {
        const glm::vec3 l = local(views_[f], d);
        const float w = (perspective_ ? l.z : 1.0f) + slack;
        bits |= ((l.x < -w ? 1u : 0u) | (l.x > w ? 2u : 0u) | (l.y < -w ? 4u : 0u) | (l.y > w ? 8u : 0u)) << (4 * f);
      }
      outside_[v] = bits;
    }
  });

  parallelFor(chunks_, threads, [&](int64_t chunk, int) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * perChunk,
                      end = std::min(triangleCount, begin + perChunk);
    for (std::size_t tri = begin; tri < end; ++tri) {
      const glm::uvec3& v = scene.triangles[tri];
      const uint32_t common = outside_[v.x] & outside_[v.y] & outside_[v.z];
      const glm::vec3 d[3] = {scene.positions[v.x] - origin_, scene.positions[v.y] - origin_,
                              scene.positions[v.z] - origin_};
      for (std::size_t f = 0; f < views_.size(); ++f) {
        if ((common >> (4 * f)) & 15u) continue;
        const View& view = views_[f];
        const glm::vec3 l[3] = {local(view, d[0]), local(view, d[1]), local(view, d[2])};
        float xmin = 1e30f, xmax = -1e30f, ymin = 1e30f, ymax = -1e30f;
        auto extend = [&](float x, float y) {
          xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymin = std::min(ymin, y), ymax = std::max(ymax, y);
        };
        if (perspective_) {
          // The part of the triangle in front of the light (a hair in front of it): its corners' projections bound
          // the texels it can cover.
          const float nearest = 1e-6f * (std::abs(l[0].z) + std::abs(l[1].z) + std::abs(l[2].z)) + 1e-30f;
          for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = l[k], q = l[(k + 1) % 3];
            if (p.z >= nearest) {
              const float inverse = 1.0f / p.z;
              extend(p.x * inverse, p.y * inverse);
            }
            if ((p.z >= nearest) != (q.z >= nearest)) {
              const glm::vec3 c = p + (q - p) * ((nearest - p.z) / (q.z - p.z));
              extend(c.x / nearest, c.y / nearest);
            }
          }
          if (!(xmin <= xmax)) continue;
        } else {
          for (int k = 0; k < 3; ++k) extend(l[k].x, l[k].y);
        }
        int i0, i1, j0, j1;
        if (!texelRange(xmin, xmax, size_, i0, i1) || !texelRange(ymin, ymax, size_, j0, j1)) continue;
        j0 = std::max(j0, view.firstRow);
        if (j0 > j1) continue;
        const Entry entry{static_cast<uint32_t>(tri), static_cast<uint16_t>(i0), static_cast<uint16_t>(i1),
                          static_cast<uint16_t>(j0), static_cast<uint16_t>(j1)};
        for (int band = j0 / kBandRows; band <= j1 / kBandRows; ++band)
          bucket(static_cast<int>(chunk), static_cast<int>(f), band).push_back(entry);
      }
    }
  });
}

void DistanceRasterizer::draw(int view, float maxSlopeBias, int threads, float* out,
                              const std::function<void(int rowBegin, int rowEnd)>& bandDone) const {
  const Scene& scene = *scene_;
  const View& v = views_[static_cast<std::size_t>(view)];
  const int size = size_;
  const float step = 2.0f / static_cast<float>(size);
  parallelFor(bands_, threads, [&](int64_t band, int) {
    const int rowBegin = static_cast<int>(band) * kBandRows, rowEnd = std::min(size, rowBegin + kBandRows);
    std::fill(out + static_cast<std::size_t>(rowBegin) * size, out + static_cast<std::size_t>(rowEnd) * size,
              kNoOccluder);
    for (int chunk = 0; chunk < chunks_; ++chunk)
      for (const Entry& e : bucket(chunk, view, static_cast<int>(band))) {
        const glm::uvec3& tri = scene.triangles[e.triangle];
        const glm::vec3 l[3] = {local(v, scene.positions[tri.x] - origin_), local(v, scene.positions[tri.y] - origin_),
                                local(v, scene.positions[tri.z] - origin_)};
        Edges edges;
        float dmax = 0.0f, absDet = 0.0f, zmin = 0.0f, zmax = 0.0f, z0 = 0.0f;
        glm::vec2 gradient(0.0f);
        glm::vec3 edgeSum(0.0f);  // of the three edge functions' coefficients
        if (perspective_) {
          // Edge k's plane through the light and corners k, k + 1 (local coordinates: the ray through texel (x, y) is
          // r = (x, y, 1)); r passes through the triangle where r = sum l_k c_k with every l_k >= 0, l_{k+2} =
          // r.(c_k x c_{k+1}) / det. A mirrored frame flips every cross product and det alike.
          const glm::vec3 n[3] = {glm::cross(l[0], l[1]), glm::cross(l[1], l[2]), glm::cross(l[2], l[0])};
          const float det = glm::dot(l[2], n[0]);
          if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) continue;  // the triangle's plane holds the light
          const float sign = det > 0.0f ? 1.0f : -1.0f;
          for (int k = 0; k < 3; ++k)
            edges.edge[static_cast<std::size_t>(k)] = sign * glm::vec3(n[k].z, n[k].x, n[k].y);
          absDet = std::abs(det);
          dmax = std::sqrt(std::max({glm::dot(l[0], l[0]), glm::dot(l[1], l[1]), glm::dot(l[2], l[2])}));
          edgeSum = edges.edge[0] + edges.edge[1] + edges.edge[2];
        } else {
          const float area = (l[1].x - l[0].x) * (l[2].y - l[0].y) - (l[2].x - l[0].x) * (l[1].y - l[0].y);
          if (!(std::abs(area) > 0.0f) || !std::isfinite(area)) continue;  // seen edge-on
          const float sign = area > 0.0f ? 1.0f : -1.0f;
          for (int k = 0; k < 3; ++k) {
            const glm::vec3 &p = l[k], &q = l[(k + 1) % 3];
            const float du = q.x - p.x, dw = q.y - p.y;
            edges.edge[static_cast<std::size_t>(k)] = sign * glm::vec3(dw * p.x - du * p.y, -dw, du);
          }
          // The distance along the direction is linear over the map: z = z0 + gradient.(x, y).
          gradient = glm::vec2((l[1].z - l[0].z) * (l[2].y - l[0].y) - (l[2].z - l[0].z) * (l[1].y - l[0].y),
                               (l[1].x - l[0].x) * (l[2].z - l[0].z) - (l[2].x - l[0].x) * (l[1].z - l[0].z)) /
                     area;
          z0 = l[0].z - gradient.x * l[0].x - gradient.y * l[0].y;
          zmin = std::min({l[0].z, l[1].z, l[2].z}), zmax = std::max({l[0].z, l[1].z, l[2].z});
        }
        const float planeBias = std::min(step * (std::abs(gradient.x) + std::abs(gradient.y)), maxSlopeBias);
        for (int j = std::max<int>(e.j0, rowBegin); j <= std::min<int>(e.j1, rowEnd - 1); ++j) {
          const float y = (static_cast<float>(j) + 0.5f) * step - 1.0f;
          float* row = out + static_cast<std::size_t>(j) * size;
          const float sumAtY = edgeSum.x + edgeSum.z * y;
          const glm::vec2 sumSlope(edgeSum.y, edgeSum.z);
          auto span = [&](int first, int last) {
            if (perspective_ && maxSlopeBias > 0.0f)
              faceSpan<true>(row, first, last, step, y, sumAtY, sumSlope, absDet, dmax, maxSlopeBias, near_);
            else if (perspective_)
              faceSpan<false>(row, first, last, step, y, sumAtY, sumSlope, absDet, dmax, maxSlopeBias, near_);
            else
              planeSpan(row, first, last, step, z0 + gradient.y * y, gradient.x, zmin, zmax, planeBias);
          };
          if (e.i1 - e.i0 < kNarrow) {
            // A few texels (most triangles of a dense mesh): testing each costs less than solving for the span.
            for (int i = e.i0; i <= e.i1; ++i)
              if (edges.covers((static_cast<float>(i) + 0.5f) * step - 1.0f, y)) span(i, i);
            continue;
          }
          int first, last;
          if (coveredSpan(edges, y, e.i0, e.i1, size, first, last)) span(first, last);
        }
      }
    if (bandDone) bandDone(rowBegin, rowEnd);
  });
}

}  // namespace vplab
