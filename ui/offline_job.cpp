#include "ui/offline_job.h"

#include "renderer/offline/offline_scene.h"
#include "renderer/offline/render_methods.h"

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
  // Progressive virtual beams make their own light paths, vplCount per pass, beamPasses passes.
  if (method == Method::Vbl) return samples * s.vplCount * s.beamPasses;
  const int perLight = method == Method::Vsl ? s.vslSamples : method == Method::Vrl ? s.vrlSamples : 1;
  return samples * static_cast<double>(vplCount) * perLight;
}

void OfflineTimeEstimate::record(Method method, const Settings& settings, std::size_t vplCount, double seconds) {
  const double units = work(method, settings, vplCount);
  if (units > 0.0 && seconds > 0.0) secondsPerUnit_[method] = seconds / units;
}

double OfflineTimeEstimate::estimate(Method method, const Settings& settings, std::size_t vplCount) const {
  auto it = secondsPerUnit_.find(method);
  return it == secondsPerUnit_.end() ? -1.0 : it->second * work(method, settings, vplCount);
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
    cutSize_ = Image();
  }
  // Copies: the worker must not see the editor's later edits (a moved light, a new scene) half-way through.
  Scene sceneCopy = scene;
  sceneCopy.camera = camera;
  VplSet vplCopy = renderMethod(method).usesVpls ? vpls : VplSet{};
  thread_ = std::thread([this, sceneCopy = std::move(sceneCopy), vplCopy = std::move(vplCopy),
                         settings = offlineRenderSettings(settings, method), method] {
    auto onPass = [this](const Image& mean, int) {
      std::lock_guard lock(mutex_);
      image_ = mean;
      imageChanged_ = true;
    };
    try {
      OfflineScene offline(sceneCopy);
      VplRenderResult result = renderMethod(method).render(offline, vplCopy, settings, &control_, onPass);
      clampEnergyRemoved_ = result.clampEnergyRemoved;
      cancelled_ = result.cancelled;
      samples_ = result.samplesPerPixel;
      nonFiniteSamples_ = result.nonFiniteSamples;
      std::lock_guard lock(mutex_);
      image_ = std::move(result.image);
      cutSize_ = std::move(result.cutSize);
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

Image OfflineJob::cutSize() const {
  std::lock_guard lock(mutex_);
  return cutSize_;
}

}  // namespace vplab::ui
