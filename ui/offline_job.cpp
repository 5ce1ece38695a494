#include "ui/offline_job.h"

#include "renderer/offline/offline_scene.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vpl_renderer.h"

#include <chrono>

namespace vplab::ui {

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Method exactCounterpartOf(const Settings& s) {
  if (s.vslRadius > 0.0f) return Method::Vsl;
  if (s.ssbcSteps > 0 && s.clampBound < kInfinity) return Method::VplKK;
  return Method::Vpl;
}

double estimateSecondsLeft(double elapsedSeconds, float progress) {
  if (!(progress >= 0.02f) || !(elapsedSeconds >= 0.25)) return -1.0;
  return elapsedSeconds * (1.0 - static_cast<double>(progress)) / static_cast<double>(progress);
}

double OfflineTimeEstimate::work(Method method, const Settings& s, std::size_t vplCount) {
  const double samples = static_cast<double>(s.width) * s.height * s.samplesPerPixel;
  if (method == Method::Reference) return samples;
  return samples * static_cast<double>(vplCount) * (method == Method::Vsl ? s.vslSamples : 1);
}

void OfflineTimeEstimate::record(Method method, const Settings& settings, std::size_t vplCount, double seconds) {
  const double units = work(method, settings, vplCount);
  if (units > 0.0 && seconds > 0.0) secondsPerUnit_[static_cast<int>(method)] = seconds / units;
}

double OfflineTimeEstimate::estimate(Method method, const Settings& settings, std::size_t vplCount) const {
  const double perUnit = secondsPerUnit_[static_cast<int>(method)];
  return perUnit < 0.0 ? -1.0 : perUnit * work(method, settings, vplCount);
}

OfflineJob::~OfflineJob() {
  control_.cancel = true;
  join();
}

void OfflineJob::join() {
  if (thread_.joinable()) thread_.join();
}

void OfflineJob::cancel() { control_.cancel = true; }

double OfflineJob::seconds() const { return running_ ? now() - startTime_ : seconds_.load(); }

double OfflineJob::secondsLeft() const { return running_ ? estimateSecondsLeft(seconds(), progress_.load()) : -1.0; }

std::string OfflineJob::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void OfflineJob::start(const Scene& scene, const Camera& camera, const VplSet& vpls, const Settings& settings,
                       Method method) {
  cancel();
  join();
  control_.cancel = false;
  control_.onProgress = [this](float f) { progress_ = f; };
  running_ = true;
  finished_ = false;
  progress_ = 0.0f;
  method_ = method;
  cancelled_ = false;
  samples_ = 0;
  nonFiniteSamples_ = 0;
  clampEnergyRemoved_ = 0.0;
  startTime_ = now();
  {
    std::lock_guard lock(mutex_);
    error_.clear();
  }
  // Copies: the worker must not see the editor's later edits (a moved light, a new scene) half-way through.
  Scene sceneCopy = scene;
  sceneCopy.camera = camera;
  VplSet vplCopy = method == Method::Reference ? VplSet{} : vpls;
  thread_ = std::thread([this, sceneCopy = std::move(sceneCopy), vplCopy = std::move(vplCopy),
                         settings = offlineRenderSettings(settings, method), method] {
    auto onPass = [this](const Image& mean, int) {
      std::lock_guard lock(mutex_);
      image_ = mean;
      imageChanged_ = true;
    };
    try {
      OfflineScene offline(sceneCopy);
      ProgressiveResult result;
      if (method == Method::Reference) {
        result = renderReference(offline, settings, &control_, onPass);
      } else {
        VplRenderResult vr = renderVpl(offline, vplCopy, method, settings, &control_, onPass);
        clampEnergyRemoved_ = vr.clampEnergyRemoved;
        result = std::move(vr);
      }
      cancelled_ = result.cancelled;
      samples_ = result.samplesPerPixel;
      nonFiniteSamples_ = result.nonFiniteSamples;
      std::lock_guard lock(mutex_);
      image_ = std::move(result.image);
      imageChanged_ = true;
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      error_ = e.what();
    }
    seconds_ = now() - startTime_;
    progress_ = 1.0f;
    running_ = false;
    finished_ = true;
  });
}

std::optional<Image> OfflineJob::takeImage() {
  if (!imageChanged_.exchange(false)) return std::nullopt;
  std::lock_guard lock(mutex_);
  return image_;
}

bool OfflineJob::takeFinished() { return finished_.exchange(false); }

}  // namespace vplab::ui
