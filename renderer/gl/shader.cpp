#include "renderer/gl/shader.h"

#include <glad/gl.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace vplab {

namespace {

struct StageInfo {
  const char* suffix;
  GLenum type;
};
constexpr StageInfo kStages[] = {{".vert.glsl", GL_VERTEX_SHADER},
                                 {".frag.glsl", GL_FRAGMENT_SHADER},
                                 {".geom.glsl", GL_GEOMETRY_SHADER},
                                 {".comp.glsl", GL_COMPUTE_SHADER}};

// Mesa 22 attributes some errors after a `#line L S` to the wrong source string S, so the file index is encoded in
// the line number instead (line = index * kLineStride + line) with source string 0; the log is decoded below.
constexpr int kLineStride = 100000;

std::string lineDirective(int index, int line) { return "#line " + std::to_string(index * kLineStride + line) + "\n"; }

bool endsWith(const std::string& s, const char* suffix) {
  std::string x(suffix);
  return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

GLenum stageOf(const std::string& file) {
  for (const StageInfo& s : kStages)
    if (endsWith(file, s.suffix)) return s.type;
  throw ShaderError(file + ": shader file names must end in .vert/.frag/.geom/.comp.glsl", file, 0);
}

bool readFile(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  out = s.str();
  return true;
}

// `#include <path>` in a shader names a header of a system include directory (VPLAB_SHADER_SYSTEM_INCLUDE_DIR):
// NanoVDB's PNanoVDB.h, read where the distribution installed it rather than copied (docs/methods.md "Smoke in the
// preview"). Such a header's own `#include <...>` lines are C-only (inside its #if blocks) and stay as they are.
void expand(const std::string& dir, const std::string& file, std::vector<std::string>& names,
            std::set<std::string>& included, std::ostringstream& out, const std::string& from, int fromLine) {
  std::string text;
  const bool systemHeader = dir == VPLAB_SHADER_SYSTEM_INCLUDE_DIR;
  if (!readFile(dir + "/" + file, text)) {
    std::string where = from.empty() ? file : from + ":" + std::to_string(fromLine);
    throw ShaderError(where + ": cannot read shader file '" + dir + "/" + file + "'", from.empty() ? file : from,
                      fromLine);
  }
  int index = static_cast<int>(names.size());
  names.push_back(systemHeader ? "<" + file + ">" : file);
  static const std::regex includeRe(R"(^\s*#\s*include\s+\"([^\"]+)\"\s*$)");
  static const std::regex systemIncludeRe(R"(^\s*#\s*include\s+<([^>]+)>\s*$)");
  static const std::regex versionRe(R"(^\s*#\s*version\b.*$)");
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  bool first = from.empty();
  if (!first) out << lineDirective(index, 1);
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::smatch m;
    if (std::regex_match(line, m, includeRe)) {
      std::string child = m[1].str();
      if (included.insert(child).second) expand(dir, child, names, included, out, file, lineNo);
      out << lineDirective(index, lineNo + 1);
      continue;
    }
    if (!systemHeader && std::regex_match(line, m, systemIncludeRe)) {
      std::string child = m[1].str();
      if (included.insert("<" + child + ">").second)
        expand(VPLAB_SHADER_SYSTEM_INCLUDE_DIR, child, names, included, out, file, lineNo);
      out << lineDirective(index, lineNo + 1);
      continue;
    }
    out << line << "\n";
    // After #version the defines marker goes in, then numbering resumes at the next line of this file.
    if (first && std::regex_match(line, versionRe)) {
      out << "//@DEFINES@\n" << lineDirective(index, lineNo + 1);
      first = false;
    }
  }
}

// Mesa writes "0:12(5): error: ...", NVIDIA "0(12) : error ...": decode the encoded line into file name and line.
std::string rewriteLog(const std::string& log, const std::vector<std::string>& names, std::string& firstFile,
                       int& firstLine) {
  static const std::regex mesaRe(R"(^(\d+):(\d+)\((\d+)\):\s*(.*)$)");
  static const std::regex nvRe(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
  std::istringstream in(log);
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::smatch m;
    int source = -1, lineNo = 0;
    std::string rest;
    if (std::regex_match(line, m, mesaRe)) {
      lineNo = std::stoi(m[2]);
      rest = m[4];
      source = lineNo / kLineStride;
    } else if (std::regex_match(line, m, nvRe)) {
      lineNo = std::stoi(m[2]);
      rest = m[3];
      source = lineNo / kLineStride;
    }
    lineNo %= kLineStride;
    if (source >= 0 && source < static_cast<int>(names.size())) {
      if (firstFile.empty()) {
        firstFile = names[static_cast<std::size_t>(source)];
        firstLine = lineNo;
      }
      out << names[static_cast<std::size_t>(source)] << ":" << lineNo << ": " << rest << "\n";
    } else {
      out << line << "\n";
    }
  }
  return out.str();
}

}  // namespace

std::string defaultShaderDir() {
  // VPLAB_SHADER_DIR in the environment: shaders edited in a copy are tried without rebuilding.
  const char* fromEnvironment = std::getenv("VPLAB_SHADER_DIR");
  return fromEnvironment && *fromEnvironment ? fromEnvironment : VPLAB_SHADER_DIR;
}

std::string preprocessShader(const std::string& shaderDir, const std::string& file,
                             std::vector<std::string>& fileNames) {
  std::ostringstream out;
  std::set<std::string> included;
  expand(shaderDir, file, fileNames, included, out, {}, 0);
  return out.str();
}

ShaderProgram::ShaderProgram(std::vector<std::string> files, std::vector<std::string> defines, std::string shaderDir)
    : files_(std::move(files)), defines_(std::move(defines)), shaderDir_(std::move(shaderDir)) {
  if (shaderDir_.empty()) shaderDir_ = defaultShaderDir();
  id_ = build();
}

ShaderProgram::~ShaderProgram() {
  if (id_) glDeleteProgram(id_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept { *this = std::move(other); }

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this == &other) return *this;
  if (id_) glDeleteProgram(id_);
  id_ = other.id_;
  other.id_ = 0;
  files_ = std::move(other.files_);
  defines_ = std::move(other.defines_);
  shaderDir_ = std::move(other.shaderDir_);
  locations_ = std::move(other.locations_);
  return *this;
}

uint32_t ShaderProgram::build() const {
  std::string defineBlock;
  for (const std::string& d : defines_) defineBlock += "#define " + d + "\n";
  std::vector<GLuint> shaders;
  auto cleanup = [&] {
    for (GLuint s : shaders) glDeleteShader(s);
  };
  for (const std::string& file : files_) {
    GLenum type = stageOf(file);
    std::vector<std::string> names;
    std::string source = preprocessShader(shaderDir_, file, names);
    std::size_t marker = source.find("//@DEFINES@\n");
    if (marker == std::string::npos) {
      cleanup();
      throw ShaderError(file + ":1: missing #version directive", file, 1);
    }
    source.replace(marker, 12, defineBlock);
    GLuint shader = glCreateShader(type);
    shaders.push_back(shader);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    // A system header's warnings (PNanoVDB.h's implicit int -> uint conversions on Mesa) are not ours to fix: the
    // compiler's debug messages stay off while a shader that includes one compiles. Errors still fail it below.
    const bool quiet = std::any_of(names.begin(), names.end(), [](const std::string& n) { return n[0] == '<'; });
    if (quiet) glDebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
    glCompileShader(shader);
    if (quiet) glDebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      GLint length = 0;
      glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
      std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
      glGetShaderInfoLog(shader, length, nullptr, log.data());
      log.resize(std::char_traits<char>::length(log.c_str()));
      std::string firstFile;
      int firstLine = 0;
      std::string message = rewriteLog(log, names, firstFile, firstLine);
      cleanup();
      throw ShaderError("shader compile error in " + file + ":\n" + message, firstFile.empty() ? file : firstFile,
                        firstLine);
    }
  }
  GLuint program = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(program, s);
  glLinkProgram(program);
  for (GLuint s : shaders) glDetachShader(program, s);
  cleanup();
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(std::char_traits<char>::length(log.c_str()));
    glDeleteProgram(program);
    std::string all;
    for (const std::string& f : files_) all += (all.empty() ? "" : " + ") + f;
    throw ShaderError("shader link error in " + all + ":\n" + log, files_.empty() ? "" : files_.front(), 0);
  }
  return program;
}

bool ShaderProgram::reload(std::string* error) {
  try {
    GLuint fresh = build();
    if (id_) glDeleteProgram(id_);
    id_ = fresh;
    locations_.clear();
    return true;
  } catch (const GlError& e) {
    if (error) *error = e.what();
    return false;
  }
}

void ShaderProgram::use() const { glUseProgram(id_); }

int ShaderProgram::location(const char* name) {
  auto it = locations_.find(name);
  if (it != locations_.end()) return it->second;
  int loc = glGetUniformLocation(id_, name);
  locations_.emplace(name, loc);
  return loc;
}

void ShaderProgram::set(const char* name, int value) { glProgramUniform1i(id_, location(name), value); }
void ShaderProgram::set(const char* name, uint32_t value) { glProgramUniform1ui(id_, location(name), value); }
void ShaderProgram::set(const char* name, float value) { glProgramUniform1f(id_, location(name), value); }
void ShaderProgram::set(const char* name, glm::vec2 v) { glProgramUniform2f(id_, location(name), v.x, v.y); }
void ShaderProgram::set(const char* name, glm::vec3 v) { glProgramUniform3f(id_, location(name), v.x, v.y, v.z); }
void ShaderProgram::set(const char* name, glm::vec4 v) {
  glProgramUniform4f(id_, location(name), v.x, v.y, v.z, v.w);
}
void ShaderProgram::set(const char* name, glm::ivec2 v) { glProgramUniform2i(id_, location(name), v.x, v.y); }
void ShaderProgram::set(const char* name, const glm::mat4& m) {
  glProgramUniformMatrix4fv(id_, location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::set(const char* name, const glm::mat3& m) {
  glProgramUniformMatrix3fv(id_, location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::setArray(const char* name, const int* values, int count) {
  glProgramUniform1iv(id_, location(name), count, values);
}
void ShaderProgram::setArray(const char* name, const glm::vec2* values, int count) {
  glProgramUniform2fv(id_, location(name), count, glm::value_ptr(values[0]));
}
void ShaderProgram::setArray(const char* name, const glm::vec3* values, int count) {
  glProgramUniform3fv(id_, location(name), count, glm::value_ptr(values[0]));
}
void ShaderProgram::setArray(const char* name, const glm::vec4* values, int count) {
  glProgramUniform4fv(id_, location(name), count, glm::value_ptr(values[0]));
}

}  // namespace vplab
