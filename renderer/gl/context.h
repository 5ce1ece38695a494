#pragma once
// Headless OpenGL 4.5 core contexts (docs/guide.md, "Install and build"): EGL (a GPU device where one exists, else Mesa's
// surfaceless platform) and OSMesa (pure software, the CI default). The context loads the glad function table from
// its own getProcAddress, so that nothing in vplab ever calls libGL's or libOSMesa's exported gl* symbols directly
// (they belong to whichever GL library was linked first, not to the context). Rendering goes into framebuffer objects; there is no default framebuffer to draw to.

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace vplab {

enum class GlBackend {
  Auto,    ///< EGL (device, then surfaceless), then OSMesa
  Egl,     ///< EGL_EXT_platform_device with a GPU, else EGL_PLATFORM_SURFACELESS_MESA, else any EGL device
  OsMesa,  ///< OSMesaCreateContextAttribs, core profile 4.5
};

/// Parses "auto", "egl", "osmesa"; returns false on anything else.
bool parseGlBackend(const std::string& text, GlBackend& out);
const char* toString(GlBackend backend);

/// Any GL runtime failure: no context, a shader that does not compile, an incomplete framebuffer.
struct GlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class GlMessageSeverity { Notification, Low, Medium, High };

/// Receives KHR_debug messages. The default prints High and Medium (errors, undefined behaviour) as warnings on
/// stderr and drops the rest.
using GlLogCallback = std::function<void(GlMessageSeverity severity, const std::string& message)>;

/// An OpenGL 4.5 core context without a window, current on the creating thread from construction to destruction.
/// Only one context may be current per thread; glad's function table is global, so creating a second context
/// reloads it for the newer one (call makeCurrent() to switch back).
class HeadlessGlContext {
 public:
  /// Throws GlError listing every backend tried and why it failed when no GL 4.5 core context can be made.
  explicit HeadlessGlContext(GlBackend backend = GlBackend::Auto, GlLogCallback log = {});
  ~HeadlessGlContext();
  HeadlessGlContext(HeadlessGlContext&&) noexcept;
  HeadlessGlContext& operator=(HeadlessGlContext&&) noexcept;
  HeadlessGlContext(const HeadlessGlContext&) = delete;
  HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

  /// Makes this context current on the calling thread and reloads glad's function table from it.
  void makeCurrent();

  /// The backend actually in use (never Auto).
  GlBackend backend() const;
  /// e.g. "EGL device /dev/dri/renderD128", "EGL surfaceless", "OSMesa".
  const std::string& platform() const;
  const std::string& renderer() const;  ///< GL_RENDERER
  const std::string& vendor() const;    ///< GL_VENDOR
  const std::string& version() const;   ///< GL_VERSION
  int majorVersion() const;
  int minorVersion() const;
  /// One line: platform, renderer and version.
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Keeps the GL driver libraries that the EGL or GLX front end loaded at run time (Mesa's *_dri.so, libEGL_mesa,
/// libGLX_mesa) loaded until the process exits. Without it the last eglTerminate unloads the driver: the next context
/// pays for loading it again, and the allocations it keeps for the process's lifetime lose the module they came from,
/// so LeakSanitizer reports them as leaks it cannot attribute (tests/lsan-mesa.supp names Mesa's libraries).
/// Called after a display is initialised; cheap after the first call.
void keepGlDriversLoaded();

}  // namespace vplab
