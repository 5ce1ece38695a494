#include "renderer/gl/screen_pass.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace vplab {

Target::Target(int w, int h) : texture(w, h, TextureFormat::Rgba32F) {
  framebuffer.attachColor(0, texture);
  framebuffer.finalize(1);
}

void drawFullscreen(ShaderProgram& program, const GlVertexArray& vao) {
  program.use();
  vao.bind();
  drawProceduralTriangles(3);
}

namespace {
std::vector<std::string> withDefine(std::vector<std::string> defines, std::string define) {
  defines.push_back(std::move(define));
  return defines;
}
}  // namespace

BrdfVariants::BrdfVariants(const std::string& fragmentShader, std::vector<std::string> defines)
    : general_({"preview/fullscreen.vert.glsl", fragmentShader}, defines),
      lambertOnly_({"preview/fullscreen.vert.glsl", fragmentShader}, withDefine(defines, "BRDF_LAMBERT_ONLY 1")) {}

void BandCost::measured(int rows, double ms) {
  // Two bands of clearly different heights give both parts (a time that did not grow with the rows is all fixed cost);
  // heights closer than 3 : 2 would turn timing noise into either part, so such a band, like the first, keeps the
  // fixed part and gives the rest of its time to the rows.
  if (lastRows_ > 0 && 2 * std::max(rows, lastRows_) >= 3 * std::min(rows, lastRows_)) {
    const double slope = (ms - lastMs_) / (rows - lastRows_);
    if (slope > 0.0) {
      msPerRow_ = slope;
      fixedMs_ = std::clamp(ms - slope * rows, 0.0, ms);
    } else {
      fixedMs_ = std::min(ms, lastMs_);
      msPerRow_ = std::max(ms - fixedMs_, 0.0) / rows;
    }
  } else {
    fixedMs_ = std::min(fixedMs_, ms);
    msPerRow_ = (ms - fixedMs_) / rows;
  }
  lastRows_ = rows;
  lastMs_ = ms;
}

int BandCost::nextBand(int rowsLeft, int rows, double sliceMs) const {
  if (lastRows_ == 0) return std::min(rowsLeft, std::max(1, rows / 8));
  if (fixedMs_ >= 0.5 * sliceMs || msPerRow_ <= 0.0) return rowsLeft;
  const double band = std::clamp((sliceMs - fixedMs_) / msPerRow_, 1.0, static_cast<double>(rows));
  return std::min(rowsLeft, static_cast<int>(band));
}

void PassSlices::begin(std::function<bool()> outOfTime) {
  outOfTime_ = std::move(outOfTime);
  seen_ = 0;
  stopped_ = false;
}

bool PassSlices::stopAfterSlice() {
  if (outOfTime_ && outOfTime_()) stopped_ = true;
  return stopped_;
}

void PassSlices::step(const std::function<void()>& work) {
  const int index = seen_++;
  if (stopped_ || index < done_) return;
  work();
  done_ = index + 1;
  stopAfterSlice();
}

void PassSlices::bands(glm::ivec4 rect, const std::function<void()>& draw) {
  const int index = seen_++;
  if (stopped_ || index < done_) return;
  const int rows = rect.w;
  if (!outOfTime_ || rows <= 1) {
    // Unbudgeted, or nothing to split: whatever rows are left in one draw (all of them unless a budgeted call began).
    if (bandRow_ > 0) {
      glEnable(GL_SCISSOR_TEST);
      glScissor(rect.x, rect.y + bandRow_, rect.z, rows - bandRow_);
    }
    draw();
    glDisable(GL_SCISSOR_TEST);
    bandRow_ = 0;
    done_ = index + 1;
    stopAfterSlice();
    return;
  }
  if (bandCosts_.size() <= static_cast<std::size_t>(index)) bandCosts_.resize(static_cast<std::size_t>(index) + 1);
  BandCost& cost = bandCosts_[static_cast<std::size_t>(index)];
  while (bandRow_ < rows) {
    const int height = cost.nextBand(rows - bandRow_, rows, kSliceMs);
    const auto start = std::chrono::steady_clock::now();
    glEnable(GL_SCISSOR_TEST);
    glScissor(rect.x, rect.y + bandRow_, rect.z, height);
    draw();
    glDisable(GL_SCISSOR_TEST);
    bandRow_ += height;
    if (bandRow_ == rows) {
      bandRow_ = 0;
      done_ = index + 1;
    }
    // outOfTime waits for the GPU, so the time to its answer is the band's.
    const bool stop = stopAfterSlice();
    cost.measured(height, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    if (stop || done_ == index + 1) return;
  }
}

bool PassSlices::end() {
  outOfTime_ = nullptr;
  if (done_ < seen_ || bandRow_ > 0) return false;
  done_ = 0;
  return true;
}

void PassSlices::restart() {
  done_ = bandRow_ = 0;
}

}  // namespace vplab
