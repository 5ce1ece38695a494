#pragma once
// The pixels an image comparison leaves out of its means: those where the camera sees an emitter, and their edges.

#include "renderer/image/metrics.h"
#include "renderer/offline/embree_scene.h"

namespace vplab {

/// Pixels of a width x height image of the scene's camera where any of 4x4 primary rays spread over the pixel hits a
/// triangle of emissive material (an area light, seen from either side), dilated by `edge` pixels. The rays cover the
/// pixel's whole footprint, so a pixel an emitter only partly covers is excluded too; the dilation takes the pixels
/// a filter or a downscaled render mixes with the emitter. Compute it at the size of the images compared (after
/// downscaling, not before).
PixelMask emitterMask(const EmbreeScene& embree, int width, int height, int edge = 1);

}  // namespace vplab
