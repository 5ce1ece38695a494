#pragma once
// The editor's offline pass: any row of the render-method table (renderer/offline/render_methods.h): the Embree
// reference, the exact VPL render of the same scene, camera, settings and VPLs, or a media method (approximate
// compensation, virtual ray lights, progressive virtual beam lights, whose running mean arrives pass by pass), on a
// worker thread with progress, cancellation and the running mean, while the UI stays
// responsive. The job owns copies of everything it reads, so the editor may edit its own scene meanwhile.

#include "renderer/core/parallel.h"
#include "renderer/image/image.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

#include <atomic>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace vplab::ui {

/// The exact CPU counterpart of what the preview shows: VSLs when r > 0, Kollig-Keller compensation when the
/// preview compensates the bound (SSBC), else the clamped VPL render.
Method exactCounterpartOf(const Settings& settings);

/// Seconds an offline render still needs, extrapolated from its progress: elapsed (1 - p) / p. Negative while too
/// little is done to tell (the first 2 %, or under a quarter of a second).
double estimateSecondsLeft(double elapsedSeconds, float progress);

/// Estimates how long an offline render will take before it starts, from the throughput of the last completed
/// render of the same method on this machine: its seconds per unit of work, where a unit is one pixel sample of the
/// reference (pixels x spp), or one VPL evaluation of an exact render (pixels x spp x VPLs, x VSL or VRL samples;
/// progressive virtual beams: x vplCount x beamPasses).
class OfflineTimeEstimate {
 public:
  /// A render of `method` with these settings (offlineRenderSettings) and `vplCount` VPLs took `seconds`.
  void record(Method method, const Settings& settings, std::size_t vplCount, double seconds);
  /// Seconds the render would take; negative until a render of the same method was recorded.
  double estimate(Method method, const Settings& settings, std::size_t vplCount) const;

  /// Units of work of a render (see the class comment).
  static double work(Method method, const Settings& settings, std::size_t vplCount);

 private:
  std::map<Method, double> secondsPerUnit_;
};

class OfflineJob {
 public:
  OfflineJob() = default;
  ~OfflineJob();
  OfflineJob(const OfflineJob&) = delete;
  OfflineJob& operator=(const OfflineJob&) = delete;

  /// Starts a render of `scene` seen from `camera`; a running job is cancelled first. `vpls` is ignored by the
  /// methods that do not use VPLs (the reference, vbl, which makes a set per pass).
  void start(const Scene& scene, const Camera& camera, const VplSet& vpls, const Settings& settings, Method method);
  void cancel();
  bool running() const { return running_.load(); }
  float progress() const { return progress_.load(); }
  /// Seconds since start (while running) or of the whole render (when done).
  double seconds() const;
  /// estimateSecondsLeft() of the running render; negative when unknown or not running.
  double secondsLeft() const;
  Method method() const { return method_; }

  /// The running mean (or the final image) when it changed since the last call.
  std::optional<Image> takeImage();
  /// True once after a job finished (completed or cancelled); then result details are valid.
  bool takeFinished();
  bool cancelled() const { return cancelled_; }
  int samplesPerPixel() const { return samples_; }
  /// Samples that were NaN or infinite, left out of the image (ProgressiveResult::nonFiniteSamples).
  uint64_t nonFiniteSamples() const { return nonFiniteSamples_; }
  /// Energy removed by the clamp, measured by the exact VPL render (0 for the reference).
  double clampEnergyRemoved() const { return clampEnergyRemoved_; }
  /// The message of an exception thrown by the render, empty when none.
  std::string error() const;
  /// Lightcuts: the finished render's per-pixel cut size (VplRenderResult::cutSize); empty otherwise.
  Image cutSize() const;

 private:
  void join();

  std::thread thread_;
  RenderControl control_;
  std::atomic<bool> running_{false};
  std::atomic<float> progress_{0.0f};
  std::atomic<bool> imageChanged_{false};
  std::atomic<bool> finished_{false};
  mutable std::mutex mutex_;
  Image image_, cutSize_;
  std::string error_;
  Method method_ = Method::Reference;
  double startTime_ = 0.0;
  std::atomic<double> seconds_{0.0};
  bool cancelled_ = false;
  int samples_ = 0;
  uint64_t nonFiniteSamples_ = 0;
  double clampEnergyRemoved_ = 0.0;
};

}  // namespace vplab::ui
