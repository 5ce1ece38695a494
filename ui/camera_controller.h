#pragma once
// Mouse and keyboard camera for the editor: orbit around a target, pan in the view plane, zoom toward the target,
// fly with WASD. Pure math over vplab::Camera (no window types), so the tests drive it directly.

#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

namespace vplab::ui {

class CameraController {
 public:
  CameraController() = default;
  /// Starts from a scene camera; the orbit target is placed along its view direction, `targetDistance` away
  /// (typically the distance to the scene centre).
  CameraController(const Camera& camera, float targetDistance, float sceneDiagonal);

  /// The current camera (position, forward, up; yfov and clip planes kept from the start camera).
  Camera camera() const;

  /// Rotates around the target: dx, dy in radians of yaw (about world +y) and pitch. Pitch stays within +-89 deg.
  void orbit(float dx, float dy);
  /// Moves camera and target in the view plane by (dx, dy) fractions of the distance to the target.
  void pan(float dx, float dy);
  /// Moves toward the target by a factor 0.9^steps of the distance (negative steps move away).
  void zoom(float steps);
  /// Moves camera and target together: forward, right and up in units of the scene diagonal.
  void fly(float forward, float right, float up);

  glm::vec3 target() const { return target_; }
  float distance() const { return distance_; }

 private:
  Camera base_;
  glm::vec3 target_{0.0f};
  float yaw_ = 0.0f;    // radians about +y, 0 looks toward -z
  float pitch_ = 0.0f;  // radians, positive looks up
  float distance_ = 1.0f;
  float sceneScale_ = 1.0f;
};

}  // namespace vplab::ui
