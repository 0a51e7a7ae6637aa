#include "render/gl/Shader.h"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "render/gl/GlError.h"

namespace sph::render::gl {
namespace {

// A small cursor over one line, for the few fixed shapes we parse (no std::regex: GCC 12 warns
// inside it under the sanitizer build).
struct Cursor {
  const std::string& s;
  std::size_t at = 0;
  bool done() const { return at >= s.size(); }
  void spaces() {
    while (!done() && (s[at] == ' ' || s[at] == '\t' || s[at] == '\r')) ++at;
  }
  bool literal(const char* text) {
    const std::size_t n = std::strlen(text);
    if (s.compare(at, n, text) != 0) return false;
    at += n;
    return true;
  }
  bool number(std::string& out) {
    const std::size_t start = at;
    while (!done() && s[at] >= '0' && s[at] <= '9') ++at;
    out = s.substr(start, at - start);
    return at > start;
  }
  std::string rest() const { return s.substr(std::min(at, s.size())); }
};

// `#include "name"` with optional spaces: the name, or "" for any other line.
std::string includedName(const std::string& line) {
  Cursor c{line};
  c.spaces();
  if (!c.literal("#")) return "";
  c.spaces();
  if (!c.literal("include")) return "";
  c.spaces();
  if (!c.literal("\"")) return "";
  const std::size_t close = line.find('"', c.at);
  if (close == std::string::npos || close == c.at) return "";
  const std::string name = line.substr(c.at, close - c.at);
  c.at = close + 1;
  c.spaces();
  return c.done() ? name : "";
}

// One log line as (line, column or "", message), if it has one of the drivers' shapes:
// "N:LINE(COL): msg" (Mesa), "N(LINE) : msg" (NVIDIA), "ERROR: N:LINE: msg" (AMD).
bool parseLogLine(const std::string& text, std::string& line, std::string& column,
                  std::string& message) {
  std::string source;
  {
    Cursor c{text};
    if (c.number(source) && c.literal(":") && c.number(line) && c.literal("(") &&
        c.number(column) && c.literal("): ")) {
      message = c.rest();
      return true;
    }
  }
  {
    Cursor c{text};
    if (c.number(source) && c.literal("(") && c.number(line) && c.literal(") : ")) {
      column.clear();
      message = c.rest();
      return true;
    }
  }
  for (const char* kind : {"ERROR", "WARNING"}) {
    Cursor c{text};
    if (c.literal(kind) && c.literal(": ") && c.number(source) && c.literal(":") &&
        c.number(line) && c.literal(": ")) {
      column.clear();
      message = std::string(kind[0] == 'E' ? "error" : "warning") + ": " + c.rest();
      return true;
    }
  }
  return false;
}

void expandInto(const ShaderLibrary& library, const std::string& name,
                std::vector<std::string>& stack, ExpandedShader& out) {
  const ShaderSource source = library.load(name);
  const int number = static_cast<int>(out.files.size());
  out.files.push_back(source.name);
  std::istringstream in(source.text);
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string child = includedName(line);
    if (child.empty()) {
      out.text += line + "\n";
      out.origin.emplace_back(number, lineNumber);
      continue;
    }
    if (std::find(stack.begin(), stack.end(), child) != stack.end()) {
      throw ShaderError(source.name + ":" + std::to_string(lineNumber) +
                        ": include cycle through \"" + child + "\"");
    }
    stack.push_back(child);
    try {
      expandInto(library, child, stack, out);
    } catch (const ShaderError& e) {
      if (std::string(e.what()).rfind(source.name + ":", 0) == 0) throw;  // already located
      throw ShaderError(source.name + ":" + std::to_string(lineNumber) + ": cannot include \"" +
                        child + "\": " + e.what());
    }
    stack.pop_back();
  }
}

GLenum glStage(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return GL_VERTEX_SHADER;
    case ShaderStage::Geometry:
      return GL_GEOMETRY_SHADER;
    case ShaderStage::Fragment:
      return GL_FRAGMENT_SHADER;
    case ShaderStage::Compute:
      return GL_COMPUTE_SHADER;
  }
  return GL_VERTEX_SHADER;
}

std::string firstError(const std::string& mappedLog) {
  std::istringstream in(mappedLog);
  std::string line, first, any;
  int count = 0;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    ++count;
    if (any.empty()) any = line;
    if (first.empty() && line.find("error") != std::string::npos) first = line;
  }
  std::string result = first.empty() ? any : first;
  while (!result.empty() && (result.back() == '\r' || result.back() == ' ')) result.pop_back();
  if (count > 1)
    result += " (and " + std::to_string(count - 1) + " more line" + (count > 2 ? "s" : "") +
              " in the log)";
  return result;
}

std::string infoLog(GLuint object, bool program) {
  GLint length = 0;
  if (program)
    glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
  else
    glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  if (program)
    glGetProgramInfoLog(object, length, nullptr, log.data());
  else
    glGetShaderInfoLog(object, length, nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
}

}  // namespace

ExpandedShader expandIncludes(const ShaderLibrary& library, const std::string& name) {
  ExpandedShader out;
  std::vector<std::string> stack{name};
  expandInto(library, name, stack, out);
  return out;
}

std::string mapShaderLog(const std::string& log, const ExpandedShader& source) {
  // The expanded line number decides the file; the driver's source-string number is ignored.
  auto place = [&](const std::string& line) {
    const std::size_t k = std::stoul(line);
    if (k >= 1 && k <= source.origin.size()) {
      const auto& [file, original] = source.origin[k - 1];
      return source.files[static_cast<std::size_t>(file)] + ":" + std::to_string(original);
    }
    return (source.files.empty() ? std::string("shader") : source.files[0]) + ":" + line;
  };
  std::istringstream in(log);
  std::string text, out;
  while (std::getline(in, text)) {
    std::string line, column, message;
    if (parseLogLine(text, line, column, message)) {
      out += place(line) + (column.empty() ? "" : ":" + column) + ": " + message + "\n";
    } else {
      out += text + "\n";
    }
  }
  return out;
}

Program buildProgram(const ShaderLibrary& library, const std::vector<ShaderStageFile>& stages,
                     const std::string& label, const std::vector<std::string>& defines) {
  Program program = Program::create();
  std::vector<Shader> shaders;
  for (const ShaderStageFile& stage : stages) {
    ExpandedShader source = expandIncludes(library, stage.name);
    if (!defines.empty()) {
      // After the #version line; the log maps their lines to it.
      std::string lines;
      for (const std::string& d : defines) lines += "#define " + d + "\n";
      source.text.insert(source.text.find('\n') + 1, lines);
      if (!source.origin.empty())
        source.origin.insert(source.origin.begin() + 1, defines.size(), source.origin.front());
    }
    Shader shader = Shader::create(glStage(stage.stage));
    const char* text = source.text.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
      const std::string log = mapShaderLog(infoLog(shader.id(), false), source);
      throw ShaderError(firstError(log) + " [program " + label + "]");
    }
    glAttachShader(program.id(), shader.id());
    shaders.push_back(std::move(shader));
  }
  glLinkProgram(program.id());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  for (const Shader& s : shaders) glDetachShader(program.id(), s.id());
  if (!ok) {
    std::string names;
    for (const ShaderStageFile& s : stages)
      names += (names.empty() ? "shaders/" : ", shaders/") + s.name;
    throw ShaderError(names + ": link failed: " + firstError(infoLog(program.id(), true)) +
                      " [program " + label + "]");
  }
  return program;
}

}  // namespace sph::render::gl
