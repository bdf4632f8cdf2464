// The OpenGL 3.3 core entry points the renderer uses, as a table of function pointers loaded
// through a get-proc-address callback. The same drawing code then runs on an OSMesa context
// (OSMesaGetProcAddress) and in a GLFW window (glfwGetProcAddress) without linking libGL:
// libOSMesa exports the gl* symbols itself and libGL would shadow them (docs/dependencies.md, black
// images). Nothing in ui/ calls a gl* symbol directly; everything goes through this table.
#pragma once

#include <functional>
#include <string>
#include <vector>

// glcorearb.h gives the core-profile types, enums and PFN typedefs without declaring any
// prototypes (GL_GLEXT_PROTOTYPES stays undefined), so a direct gl* call fails to compile.
#include <GL/glcorearb.h>

namespace acdr {

/// Every entry point in the table, as X(type suffix, name). Add a line here to add a function;
/// the loader and the completeness test pick it up.
#define ACDR_GL_FUNCTIONS(X)                                              \
  /* state and queries */                                                 \
  X(GETERROR, GetError)                                                   \
  X(GETSTRING, GetString)                                                 \
  X(GETINTEGERV, GetIntegerv)                                             \
  X(GETFLOATV, GetFloatv)                                                 \
  X(ENABLE, Enable)                                                       \
  X(DISABLE, Disable)                                                     \
  X(ISENABLED, IsEnabled)                                                 \
  X(VIEWPORT, Viewport)                                                   \
  X(SCISSOR, Scissor)                                                     \
  X(CLEARCOLOR, ClearColor)                                               \
  X(CLEARDEPTH, ClearDepth)                                               \
  X(CLEAR, Clear)                                                         \
  X(BLENDFUNC, BlendFunc)                                                 \
  X(BLENDFUNCSEPARATE, BlendFuncSeparate)                                 \
  X(BLENDEQUATION, BlendEquation)                                         \
  X(DEPTHMASK, DepthMask)                                                 \
  X(DEPTHFUNC, DepthFunc)                                                 \
  X(COLORMASK, ColorMask)                                                 \
  X(CULLFACE, CullFace)                                                   \
  X(FRONTFACE, FrontFace)                                                 \
  X(POLYGONMODE, PolygonMode)                                             \
  X(POLYGONOFFSET, PolygonOffset)                                         \
  X(PIXELSTOREI, PixelStorei)                                             \
  X(READPIXELS, ReadPixels)                                               \
  X(READBUFFER, ReadBuffer)                                               \
  X(DRAWBUFFER, DrawBuffer)                                               \
  X(FINISH, Finish)                                                       \
  X(FLUSH, Flush)                                                         \
  /* shaders and programs */                                              \
  X(CREATESHADER, CreateShader)                                           \
  X(SHADERSOURCE, ShaderSource)                                           \
  X(COMPILESHADER, CompileShader)                                         \
  X(GETSHADERIV, GetShaderiv)                                             \
  X(GETSHADERINFOLOG, GetShaderInfoLog)                                   \
  X(DELETESHADER, DeleteShader)                                           \
  X(CREATEPROGRAM, CreateProgram)                                         \
  X(ATTACHSHADER, AttachShader)                                           \
  X(DETACHSHADER, DetachShader)                                           \
  X(BINDATTRIBLOCATION, BindAttribLocation)                               \
  X(LINKPROGRAM, LinkProgram)                                             \
  X(GETPROGRAMIV, GetProgramiv)                                           \
  X(GETPROGRAMINFOLOG, GetProgramInfoLog)                                 \
  X(DELETEPROGRAM, DeleteProgram)                                         \
  X(USEPROGRAM, UseProgram)                                               \
  X(GETUNIFORMLOCATION, GetUniformLocation)                               \
  X(UNIFORM1I, Uniform1i)                                                 \
  X(UNIFORM1F, Uniform1f)                                                 \
  X(UNIFORM2F, Uniform2f)                                                 \
  X(UNIFORM3F, Uniform3f)                                                 \
  X(UNIFORM4F, Uniform4f)                                                 \
  X(UNIFORMMATRIX3FV, UniformMatrix3fv)                                   \
  X(UNIFORMMATRIX4FV, UniformMatrix4fv)                                   \
  /* buffers and vertex arrays */                                         \
  X(GENBUFFERS, GenBuffers)                                               \
  X(DELETEBUFFERS, DeleteBuffers)                                         \
  X(BINDBUFFER, BindBuffer)                                               \
  X(BUFFERDATA, BufferData)                                               \
  X(BUFFERSUBDATA, BufferSubData)                                         \
  X(GENVERTEXARRAYS, GenVertexArrays)                                     \
  X(DELETEVERTEXARRAYS, DeleteVertexArrays)                               \
  X(BINDVERTEXARRAY, BindVertexArray)                                     \
  X(ENABLEVERTEXATTRIBARRAY, EnableVertexAttribArray)                     \
  X(DISABLEVERTEXATTRIBARRAY, DisableVertexAttribArray)                   \
  X(VERTEXATTRIBPOINTER, VertexAttribPointer)                             \
  X(VERTEXATTRIBDIVISOR, VertexAttribDivisor)                             \
  X(DRAWARRAYS, DrawArrays)                                               \
  X(DRAWELEMENTS, DrawElements)                                           \
  X(DRAWARRAYSINSTANCED, DrawArraysInstanced)                             \
  X(DRAWELEMENTSINSTANCED, DrawElementsInstanced)                         \
  X(DRAWELEMENTSBASEVERTEX, DrawElementsBaseVertex)                       \
  /* textures */                                                          \
  X(GENTEXTURES, GenTextures)                                             \
  X(DELETETEXTURES, DeleteTextures)                                       \
  X(BINDTEXTURE, BindTexture)                                             \
  X(ACTIVETEXTURE, ActiveTexture)                                         \
  X(TEXIMAGE2D, TexImage2D)                                               \
  X(TEXPARAMETERI, TexParameteri)                                         \
  /* framebuffers (multisampled offscreen target, resolve) */             \
  X(GENFRAMEBUFFERS, GenFramebuffers)                                     \
  X(DELETEFRAMEBUFFERS, DeleteFramebuffers)                               \
  X(BINDFRAMEBUFFER, BindFramebuffer)                                     \
  X(CHECKFRAMEBUFFERSTATUS, CheckFramebufferStatus)                       \
  X(FRAMEBUFFERRENDERBUFFER, FramebufferRenderbuffer)                     \
  X(FRAMEBUFFERTEXTURE2D, FramebufferTexture2D)                           \
  X(GENRENDERBUFFERS, GenRenderbuffers)                                   \
  X(DELETERENDERBUFFERS, DeleteRenderbuffers)                             \
  X(BINDRENDERBUFFER, BindRenderbuffer)                                   \
  X(RENDERBUFFERSTORAGEMULTISAMPLE, RenderbufferStorageMultisample)       \
  X(BLITFRAMEBUFFER, BlitFramebuffer)

/// Looks up one GL entry point by name ("glClear"); returns null when it does not exist.
/// Wrap OSMesaGetProcAddress or glfwGetProcAddress in a lambda.
using GlProcLoader = std::function<void*(const char* name)>;

/// The table. Members are named after the GL function without its "gl" prefix
/// (gl.Clear(...) calls glClear). A table is plain data: copy it to each thread or object
/// that draws; it belongs to no context, but the pointers are only meaningful while a
/// context of the same implementation is current.
struct GlFunctions {
#define ACDR_GL_MEMBER(suffix, name) PFNGL##suffix##PROC name = nullptr;
  ACDR_GL_FUNCTIONS(ACDR_GL_MEMBER)
#undef ACDR_GL_MEMBER

  /// Fills every entry through `loader` (with the context current). Returns false and lists
  /// the names the loader did not know in `error` ("missing GL functions: glFoo, glBar").
  bool load(const GlProcLoader& loader, std::string* error);

  /// Names of the entries still null (empty after a successful load()).
  std::vector<std::string> missing() const;

  /// Number of entries in the table.
  static int count();

  /// The GL names of all entries, in table order ("glGetError", ...).
  static std::vector<std::string> names();
};

/// Drains glGetError. Returns "" when there was no error, else the error names joined
/// ("GL_INVALID_OPERATION") prefixed by `where`, so a caller can report which stage failed.
std::string gl_error_string(const GlFunctions& gl, const char* where);

}  // namespace acdr
