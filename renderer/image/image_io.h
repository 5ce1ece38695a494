#pragma once
// Reading and writing images by file extension: OpenEXR (.exr, 32-bit float), PFM (.pfm) and PNG (.png, 8-bit sRGB).
// EXR and PFM keep linear radiance exactly; PNG is a display format, so writing tonemaps (exposure, clamp, sRGB) and
// reading decodes sRGB back to linear. Failures throw ImageIoError whose message starts with the file name.
// Every write is atomic (renderer/core/atomic_file.h): the image is encoded in memory, written beside the target and
// renamed into place, so a failed write leaves the old file and a "wrote" is only ever printed for a whole file.

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/image/image.h"
#include "renderer/image/tonemap.h"

namespace vplab {

struct ImageIoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// An image (or its sidecar) that could not be written: the disk, the folder or the target, not the image data.
struct ImageWriteError : ImageIoError {
  using ImageIoError::ImageIoError;
};

enum class ImageFormat { Exr, Pfm, Png };

/// The format named by the extension (case-insensitive); throws ImageIoError for anything else.
ImageFormat imageFormatFromPath(const std::string& path);
/// True for EXR and PFM, which hold radiance; false for PNG, which holds a tonemapped display image.
bool isLinearFormat(ImageFormat format);

/// What an image holds, written with it so that a comparison can tell an indirect-only reference from a full render.
/// Keys vplab writes: "components" (all|direct|indirect), "method" (reference, vpl, vpl-kk, vsl, gl-preview),
/// "spp", "settings" (the whole Settings as JSON). Stored as OpenEXR string attributes "vplab.<key>"; a PFM, which
/// has no room for them, gets a sidecar "<file>.json"; a PNG records none.
using ImageInfo = std::map<std::string, std::string>;

/// The ImageInfo recorded with an image; empty when there is none (PNG, files from elsewhere).
ImageInfo readImageInfo(const std::string& path);
/// The sidecar a PFM's ImageInfo is written to.
std::string pfmSidecarPath(const std::string& path);

/// Reads an EXR (RGB or RGBA float/half channels; alpha dropped), PFM (colour "PF" or grey "Pf", either
/// byte order) or PNG (8 or 16 bits, grey or colour, sRGB decoded to linear) into a linear image.
Image readImage(const std::string& path);

/// Writes by extension. exposure is in stops and only affects PNG (EXR and PFM store the radiance unchanged);
/// NaN/Inf pixels become magenta in a PNG and are stored as they are in EXR/PFM.
void writeImage(const std::string& path, const Image& image, float exposure = 0.0f, const ImageInfo& info = {});

Image readExr(const std::string& path);
Image readPfm(const std::string& path);
Image readPng(const std::string& path);
void writeExr(const std::string& path, const Image& image, const ImageInfo& info = {});
/// Little-endian PFM (scale -1), rows stored bottom-up as the format requires; a non-empty info goes to the sidecar.
void writePfm(const std::string& path, const Image& image, const ImageInfo& info = {});
void writePng(const std::string& path, const Image& image, float exposure);
/// Writes already display-encoded 8-bit RGB rows (top row first), e.g. a heatmap.
void writePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace vplab
