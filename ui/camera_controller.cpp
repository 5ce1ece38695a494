#include "ui/camera_controller.h"

#include <algorithm>
#include <cmath>

namespace vplab::ui {

namespace {

constexpr float kMaxPitch = 1.5533f;  // 89 degrees: keeps forward away from the world up axis

glm::vec3 directionFrom(float yaw, float pitch) {
  return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
}

}  // namespace

CameraController::CameraController(const Camera& camera, float targetDistance, float sceneDiagonal)
    : base_(camera),
      distance_(std::max(targetDistance, 1e-3f)),
      sceneScale_(sceneDiagonal > 0.0f ? sceneDiagonal : 1.0f) {
  glm::vec3 f = glm::normalize(camera.forward);
  pitch_ = std::asin(std::clamp(f.y, -1.0f, 1.0f));
  pitch_ = std::clamp(pitch_, -kMaxPitch, kMaxPitch);
  yaw_ = std::atan2(f.x, -f.z);
  target_ = camera.position + distance_ * f;
}

Camera CameraController::camera() const {
  Camera c = base_;
  c.forward = glm::normalize(directionFrom(yaw_, pitch_));
  c.position = target_ - distance_ * c.forward;
  // Up stays in the plane of forward and world +y, so the horizon never rolls.
  glm::vec3 right = glm::normalize(glm::cross(c.forward, glm::vec3(0.0f, 1.0f, 0.0f)));
  c.up = glm::normalize(glm::cross(right, c.forward));
  return c;
}

void CameraController::orbit(float dx, float dy) {
  yaw_ += dx;
  pitch_ = std::clamp(pitch_ + dy, -kMaxPitch, kMaxPitch);
}

void CameraController::pan(float dx, float dy) {
  Camera c = camera();
  target_ += distance_ * (dx * c.right() + dy * c.up);
}

void CameraController::zoom(float steps) {
  distance_ = std::clamp(distance_ * std::pow(0.9f, steps), 1e-3f * sceneScale_, 100.0f * sceneScale_);
}

void CameraController::fly(float forward, float right, float up) {
  Camera c = camera();
  target_ += sceneScale_ * (forward * c.forward + right * c.right() + up * glm::vec3(0.0f, 1.0f, 0.0f));
}

}  // namespace vplab::ui
