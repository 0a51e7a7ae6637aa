// Setting a GL program's uniforms by name (glProgramUniform*: no program has to be bound). A name
// the program does not use (location -1) is ignored, as GL does, so one lighting setter serves
// programs that use only part of it. Shared by the splat, solid and rain renderers.
#pragma once

#include "render/gl/GlHandle.h"
#include "sim/Types.h"

namespace sph::render::frame {

inline void setVec3(GLuint program, const char* name, const Vec3& v) {
  glProgramUniform3f(program, glGetUniformLocation(program, name), v.x(), v.y(), v.z());
}
inline void setFloat(GLuint program, const char* name, float v) {
  glProgramUniform1f(program, glGetUniformLocation(program, name), v);
}
inline void setInt(GLuint program, const char* name, int v) {
  glProgramUniform1i(program, glGetUniformLocation(program, name), v);
}

}  // namespace sph::render::frame
