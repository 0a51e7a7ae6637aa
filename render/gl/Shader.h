// The one function that turns GLSL files into a program (STYLE.md rule 11): it resolves
// `#include "file"` lines against a ShaderLibrary, numbering every file with `#line L N` so the
// driver's log can be mapped back, compiles each stage, links, and throws a ShaderError whose
// first words are the file and line of the first error ("shaders/cdt_collide.vert:42: ...").
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"

namespace sph::render::gl {

enum class ShaderStage { Vertex, Geometry, Fragment, Compute };

struct ShaderStageFile {
  ShaderStage stage;
  std::string name;  // file under the library ("cdt_collide.vert")
};

// Source text after include expansion, and where each of its lines came from: line k (from 1)
// of `text` is line `origin[k - 1].second` of file `files[origin[k - 1].first]` (0 = the stage
// file). No #line directives: Mesa attributes some errors to the wrong source-string number, but
// always counts lines right, so the mapping is done here.
struct ExpandedShader {
  std::string text;
  std::vector<std::string> files;
  std::vector<std::pair<int, int>> origin;
};

// Replaces each `#include "name"` line (nested includes allowed) by the named file's text.
// Throws ShaderError for a missing file (naming the including file and line) or an include cycle.
ExpandedShader expandIncludes(const ShaderLibrary& library, const std::string& name);

// Rewrites a driver's info log so each "N:LINE(COL): error: ..." (Mesa), "N(LINE) : error ..."
// (NVIDIA) or "ERROR: N:LINE: ..." (AMD) names the original FILE:LINE. Lines it does not
// recognise are kept.
std::string mapShaderLog(const std::string& log, const ExpandedShader& source);

// Compiles and links the stages into a program; `label` names the program in messages.
// `defines` ("NAME" or "NAME VALUE") become `#define` lines right after each stage's #version.
Program buildProgram(const ShaderLibrary& library, const std::vector<ShaderStageFile>& stages,
                     const std::string& label, const std::vector<std::string>& defines = {});

}  // namespace sph::render::gl
