#pragma once
// GLSL programs built from files under shaders/ (`shaders/<pass>.<stage>.glsl`, shared code in
// shaders/common/*.glsl). A small preprocessor resolves `#include "common/x.glsl"` (each file once per stage) and
// emits #line directives, so compiler messages are rewritten to name the real file and line.
// Needs a current GL context; headers stay free of GL types so that callers do not need the loader.

#include "renderer/gl/context.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace vplab {

/// A shader compile or link failure. what() reads "<file>:<line>: <message>" for every message the driver gave.
struct ShaderError : GlError {
  ShaderError(const std::string& message, std::string file, int line)
      : GlError(message), file(std::move(file)), line(line) {}
  std::string file;  ///< first file named by the driver's log (or the file that failed to load)
  int line = 0;      ///< its line, 0 when unknown
};

/// The shaders/ folder: $VPLAB_SHADER_DIR when set, else the source tree's (compile definition VPLAB_SHADER_DIR).
std::string defaultShaderDir();

/// Reads `file` (relative to shaderDir) and resolves its #include directives. fileNames[i] receives the file whose
/// lines the emitted #line directives number i * 100000 + line. Throws ShaderError for a missing file.
std::string preprocessShader(const std::string& shaderDir, const std::string& file,
                             std::vector<std::string>& fileNames);

class ShaderProgram {
 public:
  ShaderProgram() = default;
  /// Builds a program from stage files named `<pass>.<stage>.glsl` with stage vert, frag, geom or comp, relative to
  /// shaderDir (empty = defaultShaderDir()). `defines` lines ("NAME VALUE") are inserted after #version.
  /// Throws ShaderError naming the file and line on a compile or link error.
  explicit ShaderProgram(std::vector<std::string> files, std::vector<std::string> defines = {},
                         std::string shaderDir = {});
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  /// Rebuilds from the same files. On failure keeps the last working program and returns false with the message
  /// in *error (the editor's reload key relies on this).
  bool reload(std::string* error = nullptr);

  bool valid() const { return id_ != 0; }
  uint32_t id() const { return id_; }
  const std::vector<std::string>& files() const { return files_; }
  void use() const;

  // Uniform setters (glProgramUniform*: no need to bind the program first). Unknown names are ignored, as GL does
  // for uniforms the compiler removed.
  void set(const char* name, int value);
  void set(const char* name, uint32_t value);
  void set(const char* name, float value);
  void set(const char* name, glm::vec2 value);
  void set(const char* name, glm::vec3 value);
  void set(const char* name, glm::vec4 value);
  void set(const char* name, glm::ivec2 value);
  void set(const char* name, const glm::mat4& value);
  void set(const char* name, const glm::mat3& value);
  void setArray(const char* name, const int* values, int count);
  void setArray(const char* name, const glm::vec2* values, int count);
  void setArray(const char* name, const glm::vec3* values, int count);
  void setArray(const char* name, const glm::vec4* values, int count);
  int location(const char* name);

 private:
  uint32_t build() const;  // returns a linked program or throws ShaderError

  uint32_t id_ = 0;
  std::vector<std::string> files_;
  std::vector<std::string> defines_;
  std::string shaderDir_;
  std::unordered_map<std::string, int> locations_;
};

/// A program built when it is first used, not when its pass is made: a run that never draws it (the compensation's
/// programs without SSBC, the full-resolution composition when the indirect light has a grid of its own) neither
/// compiles it nor loads it from Mesa's shader cache (milliseconds each, warm; tens of them with an empty cache).
/// Compile errors surface at that first use.
class DeferredProgram {
 public:
  explicit DeferredProgram(std::vector<std::string> files, std::vector<std::string> defines = {})
      : files_(std::move(files)), defines_(std::move(defines)) {}
  ShaderProgram& get() {
    if (!program_) program_.emplace(files_, defines_);
    return *program_;
  }
  ShaderProgram* operator->() { return &get(); }

 private:
  std::vector<std::string> files_, defines_;
  std::optional<ShaderProgram> program_;
};

}  // namespace vplab
