#include "renderer/gl/context.h"

// glad first: it defines __gl_h_, so osmesa.h does not pull in the system GL/gl.h with its exported gl* symbols.
#include <glad/gl.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>

#include <dlfcn.h>
#include <link.h>

#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

namespace vplab {

namespace {

constexpr int kWantedMajor = 4;
constexpr int kWantedMinor = 5;

// OSMesa insists on a colour buffer for OSMesaMakeCurrent even though vplab only renders into FBOs.
constexpr int kOsMesaBufferSize = 4;

GlMessageSeverity severityFrom(GLenum severity) {
  switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH: return GlMessageSeverity::High;
    case GL_DEBUG_SEVERITY_MEDIUM: return GlMessageSeverity::Medium;
    case GL_DEBUG_SEVERITY_LOW: return GlMessageSeverity::Low;
    default: return GlMessageSeverity::Notification;
  }
}

void defaultLog(GlMessageSeverity severity, const std::string& message) {
  if (severity == GlMessageSeverity::High || severity == GlMessageSeverity::Medium)
    std::fprintf(stderr, "warning: GL: %s\n", message.c_str());
}

void GLAPIENTRY debugCallback(GLenum /*source*/, GLenum type, GLuint /*id*/, GLenum severity, GLsizei length,
                              const GLchar* message, const void* user) {
  const auto* log = static_cast<const GlLogCallback*>(user);
  std::string text(message, length >= 0 ? static_cast<std::size_t>(length) : std::char_traits<char>::length(message));
  if (type == GL_DEBUG_TYPE_ERROR) text = "error: " + text;
  (*log)(severityFrom(severity), text);
}

std::string glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}

// EGL displays are shared per platform and native handle: eglTerminate on one would pull the rug from under any
// other context on the same display, so terminate only when the last user goes away.
std::mutex gEglDisplayMutex;
std::vector<std::pair<EGLDisplay, int>> gEglDisplayUsers;

void retainEglDisplay(EGLDisplay display) {
  std::lock_guard<std::mutex> lock(gEglDisplayMutex);
  for (auto& [d, n] : gEglDisplayUsers)
    if (d == display) {
      ++n;
      return;
    }
  gEglDisplayUsers.emplace_back(display, 1);
}

void releaseEglDisplay(EGLDisplay display) {
  std::lock_guard<std::mutex> lock(gEglDisplayMutex);
  for (auto it = gEglDisplayUsers.begin(); it != gEglDisplayUsers.end(); ++it) {
    if (it->first != display) continue;
    if (--it->second == 0) {
      eglTerminate(display);
      gEglDisplayUsers.erase(it);
    }
    return;
  }
}

int collectGlDriver(dl_phdr_info* info, std::size_t, void* names) {
  const char* name = info->dlpi_name;
  if (name && (std::strstr(name, "_dri.so") || std::strstr(name, "libEGL_mesa") || std::strstr(name, "libGLX_mesa")))
    static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

GLADapiproc eglLoad(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }

// OSMesa is opened when a context first asks for it, not linked: libOSMesa links Mesa's LLVM, whose relocations cost
// every process that loads it about 60 ms at start (most of `vplab info`'s time, and of every command a script runs),
// and most processes never render or render through EGL. Sanitized builds link it all the same
// (renderer/CMakeLists.txt).
struct OsMesaApi {
  decltype(&OSMesaCreateContextAttribs) createContextAttribs = nullptr;
  decltype(&OSMesaMakeCurrent) makeCurrent = nullptr;
  decltype(&OSMesaDestroyContext) destroyContext = nullptr;
  decltype(&OSMesaGetProcAddress) getProcAddress = nullptr;
  std::string error;  ///< why the library or one of its functions could not be had; empty when all are there
};

const OsMesaApi& osMesa() {
  static const OsMesaApi api = [] {
    OsMesaApi a;
    void* library = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      const char* why = dlerror();
      a.error = "OSMesa: cannot open libOSMesa.so.8 (" + std::string(why ? why : "unknown reason") +
                "; Debian package libosmesa6)";
      return a;
    }
    auto load = [&](auto& function, const char* name) {
      function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(library, name));
      if (!function && a.error.empty()) a.error = std::string("OSMesa: libOSMesa.so.8 has no ") + name;
    };
    load(a.createContextAttribs, "OSMesaCreateContextAttribs");
    load(a.makeCurrent, "OSMesaMakeCurrent");
    load(a.destroyContext, "OSMesaDestroyContext");
    load(a.getProcAddress, "OSMesaGetProcAddress");
    return a;
  }();
  return api;
}

GLADapiproc osMesaLoad(const char* name) { return reinterpret_cast<GLADapiproc>(osMesa().getProcAddress(name)); }

}  // namespace

bool parseGlBackend(const std::string& text, GlBackend& out) {
  for (GlBackend b : {GlBackend::Auto, GlBackend::Egl, GlBackend::OsMesa})
    if (text == toString(b)) {
      out = b;
      return true;
    }
  return false;
}

const char* toString(GlBackend backend) {
  switch (backend) {
    case GlBackend::Auto: return "auto";
    case GlBackend::Egl: return "egl";
    case GlBackend::OsMesa: return "osmesa";
  }
  return "?";
}

struct HeadlessGlContext::Impl {
  GlBackend backend = GlBackend::Auto;
  std::string platform, renderer, vendor, version;
  int major = 0, minor = 0;
  GlLogCallback log;

  EGLDisplay eglDisplay = EGL_NO_DISPLAY;
  EGLContext eglContext = EGL_NO_CONTEXT;
  OSMesaContext osMesaContext = nullptr;
  std::vector<unsigned char> osMesaBuffer;

  ~Impl() { destroy(); }

  void destroy() {
    if (eglContext != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == eglContext) eglMakeCurrent(eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(eglDisplay, eglContext);
      eglContext = EGL_NO_CONTEXT;
    }
    if (eglDisplay != EGL_NO_DISPLAY) {
      releaseEglDisplay(eglDisplay);
      eglDisplay = EGL_NO_DISPLAY;
    }
    if (osMesaContext) {
      osMesa().destroyContext(osMesaContext);
      osMesaContext = nullptr;
    }
  }

  // Creates a 4.5 core context on an initialised display; returns an empty string on success, else why not.
  std::string createOnEglDisplay(EGLDisplay display, const std::string& name) {
    if (display == EGL_NO_DISPLAY) return name + ": no display";
    EGLint maj = 0, min = 0;
    if (!eglInitialize(display, &maj, &min)) return name + ": eglInitialize failed";
    keepGlDriversLoaded();
    retainEglDisplay(display);
    eglDisplay = display;
    if (!eglBindAPI(EGL_OPENGL_API)) return name + ": eglBindAPI(EGL_OPENGL_API) failed";
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    std::string ext = extensions ? extensions : "";
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (ext.find("EGL_KHR_no_config_context") == std::string::npos) {
      // Without no_config contexts any GL-renderable config will do: vplab draws into FBOs only.
      const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(display, attribs, &config, 1, &count) || count < 1) return name + ": no GL config";
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                     kWantedMajor,
                                     EGL_CONTEXT_MINOR_VERSION,
                                     kWantedMinor,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_CONTEXT_OPENGL_DEBUG,
                                     EGL_TRUE,
                                     EGL_NONE};
    eglContext = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (eglContext == EGL_NO_CONTEXT) return name + ": eglCreateContext(4.5 core) failed";
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, eglContext)) return name + ": eglMakeCurrent failed";
    if (!gladLoadGL(eglLoad)) return name + ": glad could not load GL";
    backend = GlBackend::Egl;
    platform = name;
    return {};
  }

  std::string tryEgl() {
    std::string why;
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!getPlatformDisplay) return "EGL: no eglGetPlatformDisplayEXT";
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto queryDeviceString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    std::vector<EGLDeviceEXT> devices;
    if (queryDevices) {
      EGLint count = 0;
      if (queryDevices(0, nullptr, &count) && count > 0) {
        devices.resize(static_cast<std::size_t>(count));
        queryDevices(count, devices.data(), &count);
        devices.resize(static_cast<std::size_t>(count));
      }
    }
    auto drmFile = [&](EGLDeviceEXT d) -> std::string {
      if (!queryDeviceString) return {};
      const char* exts = queryDeviceString(d, EGL_EXTENSIONS);
      if (!exts || std::string(exts).find("EGL_EXT_device_drm") == std::string::npos) return {};
      const char* file = queryDeviceString(d, EGL_DRM_DEVICE_FILE_EXT);
      return file ? file : "";
    };
    // 1. A device backed by a DRM node is a real GPU: the fast path where the machine has one.
    for (EGLDeviceEXT d : devices) {
      std::string file = drmFile(d);
      if (file.empty()) continue;
      std::string r = createOnEglDisplay(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, d, nullptr), "EGL device " + file);
      if (r.empty()) return {};
      why += r + "; ";
      destroy();
    }
    // 2. Mesa's surfaceless platform: no window system, no config, render into FBOs.
    {
      std::string r = createOnEglDisplay(getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                                         "EGL surfaceless");
      if (r.empty()) return {};
      why += r + "; ";
      destroy();
    }
    // 3. Any other device (a software one).
    for (EGLDeviceEXT d : devices) {
      if (!drmFile(d).empty()) continue;
      std::string r = createOnEglDisplay(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, d, nullptr), "EGL device");
      if (r.empty()) return {};
      why += r + "; ";
      destroy();
    }
    return why.empty() ? "EGL: no display" : why;
  }

  std::string tryOsMesa() {
    // A 4.6 request returns NULL on Mesa 22 (Mesa 22 tops out at 4.5): ask for exactly 4.5 core.
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           kWantedMajor,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           kWantedMinor,
                           0};
    if (!osMesa().error.empty()) return osMesa().error;
    osMesaContext = osMesa().createContextAttribs(attribs, nullptr);
    if (!osMesaContext) return "OSMesa: OSMesaCreateContextAttribs(4.5 core) returned NULL";
    osMesaBuffer.assign(kOsMesaBufferSize * kOsMesaBufferSize * 4, 0);
    if (!osMesa().makeCurrent(osMesaContext, osMesaBuffer.data(), GL_UNSIGNED_BYTE, kOsMesaBufferSize,
                              kOsMesaBufferSize))
      return "OSMesa: OSMesaMakeCurrent failed";
    if (!gladLoadGL(osMesaLoad)) return "OSMesa: glad could not load GL";
    backend = GlBackend::OsMesa;
    platform = "OSMesa";
    return {};
  }

  void finish() {
    renderer = glString(GL_RENDERER);
    vendor = glString(GL_VENDOR);
    version = glString(GL_VERSION);
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < kWantedMajor || (major == kWantedMajor && minor < kWantedMinor)) {
      std::string got = platform + " gave GL " + version;
      destroy();
      throw GlError("no OpenGL 4.5 core context: " + got);
    }
    if (GLAD_GL_KHR_debug || GLAD_GL_VERSION_4_3) {
      glEnable(GL_DEBUG_OUTPUT);
      // Synchronous output so a message is reported inside the call that caused it (and on the calling thread).
      glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
      glDebugMessageCallback(debugCallback, &log);
    }
  }
};

HeadlessGlContext::HeadlessGlContext(GlBackend backend, GlLogCallback log) : impl_(std::make_unique<Impl>()) {
  impl_->log = log ? std::move(log) : GlLogCallback(defaultLog);
  std::string why;
  bool ok = false;
  if (backend == GlBackend::Auto || backend == GlBackend::Egl) {
    std::string r = impl_->tryEgl();
    ok = r.empty();
    if (!ok) why += r;
  }
  if (!ok && (backend == GlBackend::Auto || backend == GlBackend::OsMesa)) {
    impl_->destroy();
    std::string r = impl_->tryOsMesa();
    ok = r.empty();
    if (!ok) why += (why.empty() ? "" : "; ") + r;
  }
  if (!ok) {
    impl_->destroy();
    throw GlError(std::string("could not create an OpenGL 4.5 core context (backend ") + toString(backend) +
                  "): " + why);
  }
  impl_->finish();
}

HeadlessGlContext::~HeadlessGlContext() = default;
HeadlessGlContext::HeadlessGlContext(HeadlessGlContext&&) noexcept = default;
HeadlessGlContext& HeadlessGlContext::operator=(HeadlessGlContext&&) noexcept = default;

void HeadlessGlContext::makeCurrent() {
  if (impl_->backend == GlBackend::Egl) {
    if (!eglMakeCurrent(impl_->eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->eglContext))
      throw GlError("eglMakeCurrent failed");
    gladLoadGL(eglLoad);
  } else {
    if (!osMesa().makeCurrent(impl_->osMesaContext, impl_->osMesaBuffer.data(), GL_UNSIGNED_BYTE, kOsMesaBufferSize,
                              kOsMesaBufferSize))
      throw GlError("OSMesaMakeCurrent failed");
    gladLoadGL(osMesaLoad);
  }
}

GlBackend HeadlessGlContext::backend() const { return impl_->backend; }
const std::string& HeadlessGlContext::platform() const { return impl_->platform; }
const std::string& HeadlessGlContext::renderer() const { return impl_->renderer; }
const std::string& HeadlessGlContext::vendor() const { return impl_->vendor; }
const std::string& HeadlessGlContext::version() const { return impl_->version; }
int HeadlessGlContext::majorVersion() const { return impl_->major; }
int HeadlessGlContext::minorVersion() const { return impl_->minor; }

std::string HeadlessGlContext::description() const {
  return impl_->platform + ", " + impl_->renderer + ", OpenGL " + impl_->version;
}

void keepGlDriversLoaded() {
  std::vector<std::string> drivers;
  dl_iterate_phdr(collectGlDriver, &drivers);
  // RTLD_NOLOAD only takes another reference to a library already loaded; RTLD_NODELETE keeps it for good.
  for (const std::string& path : drivers) dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

}  // namespace vplab
