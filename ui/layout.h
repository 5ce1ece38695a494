#pragma once
// The editor window's fixed layout, in window pixels: the two panels beside the view, the active preset's explanation
// above it, and the margins the view keeps around the image and for the status bar. The fitted preview's size
// (EditorState::fittedPreviewSize) follows from it.

namespace vplab::ui {

inline constexpr float kLeftPanelWidth = 340.0f;
inline constexpr float kRightPanelWidth = 370.0f;
/// Height of the active preset's explanation above the view (a longer text scrolls inside it). Fixed, so that the
/// view area, and a fitted preview's size, is the same for every preset.
inline constexpr float kPresetBoxHeight = 150.0f;
/// Room the view keeps beside the image (horizontally) and for the status bar (vertically).
inline constexpr float kViewMarginX = 16.0f;
inline constexpr float kViewMarginY = 40.0f;

}  // namespace vplab::ui
