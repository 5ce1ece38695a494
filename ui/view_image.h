#pragma once
// What the editor's view shows, composed from the state as 8-bit sRGB pixels: the tonemapped preview (or its SSBC
// residual), the offline result, their split at the divider, or the difference heatmap with its legend. Pure: the
// window uploads the pixels; tests read them.

#include <cstdint>
#include <string>
#include <vector>

#include "ui/editor_state.h"

namespace vplab::ui {

struct ViewImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< width x height x 3, rows from the top; empty when there is nothing to show
  std::string note;          ///< a short line over the view ("no preview image", "SSBC is off")
  /// Non-empty when the view has nothing to show because an offline result is missing or of another size: the view
  /// shows this message with the render buttons instead of an image.
  std::string emptyState;
};

ViewImage composeView(const EditorState& state);

}  // namespace vplab::ui
