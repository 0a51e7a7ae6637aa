// A framebuffer's colour read back as a picture (RGB, row 0 at the top, as PNGs are written): the
// splat renderer's offscreen frame, and a window's back buffer for `view`'s screenshot. Needs a
// current context.
#pragma once

#include "render/frame/RenderImage.h"
#include "render/gl/GlHandle.h"

namespace sph::render::frame {

// Colour buffer `buffer` (GL_COLOR_ATTACHMENTn, GL_BACK) of `framebuffer` (0: the window's), its
// width x height pixels from the bottom-left corner, RGBA8 on the GL side. Colour only: no normals.
RenderImage readPicture(GLuint framebuffer, GLenum buffer, int width, int height);

// The current window's back buffer (what the next swap shows), width x height pixels.
RenderImage readWindow(int width, int height);

}  // namespace sph::render::frame
