// Loading of the GL function table through a caller-supplied get-proc-address.
#include "ui/gl_functions.hpp"

namespace acdr {

bool GlFunctions::load(const GlProcLoader& loader, std::string* error) {
  // Each entry is looked up by its full GL name and cast to its own PFN type; a null result
  // leaves the entry null so missing() can name it.
#define ACDR_GL_LOAD(suffix, name) \
  name = reinterpret_cast<PFNGL##suffix##PROC>(loader("gl" #name));
  ACDR_GL_FUNCTIONS(ACDR_GL_LOAD)
#undef ACDR_GL_LOAD
  const std::vector<std::string> absent = missing();
  if (absent.empty()) return true;
  if (error) {
    std::string message = "missing GL functions:";
    for (std::size_t i = 0; i < absent.size(); ++i) message += (i ? ", " : " ") + absent[i];
    *error = message;
  }
  return false;
}

std::vector<std::string> GlFunctions::missing() const {
  std::vector<std::string> absent;
#define ACDR_GL_CHECK(suffix, name) \
  if (name == nullptr) absent.push_back("gl" #name);
  ACDR_GL_FUNCTIONS(ACDR_GL_CHECK)
#undef ACDR_GL_CHECK
  return absent;
}

int GlFunctions::count() {
  int n = 0;
#define ACDR_GL_COUNT(suffix, name) ++n;
  ACDR_GL_FUNCTIONS(ACDR_GL_COUNT)
#undef ACDR_GL_COUNT
  return n;
}

std::vector<std::string> GlFunctions::names() {
  std::vector<std::string> all;
#define ACDR_GL_NAME(suffix, name) all.push_back("gl" #name);
  ACDR_GL_FUNCTIONS(ACDR_GL_NAME)
#undef ACDR_GL_NAME
  return all;
}

namespace {
const char* gl_error_name(GLenum code) {
  switch (code) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "GL error (unknown code)";
  }
}
}  // namespace

std::string gl_error_string(const GlFunctions& gl, const char* where) {
  std::string errors;
  // glGetError returns one flag per call; a bounded loop guards against a context that keeps
  // reporting (e.g. a lost context returns GL_CONTEXT_LOST forever).
  for (int i = 0; i < 16; ++i) {
    const GLenum code = gl.GetError();
    if (code == GL_NO_ERROR) break;
    errors += errors.empty() ? "" : ", ";
    errors += gl_error_name(code);
  }
  if (errors.empty()) return errors;
  return std::string(where) + ": " + errors;
}

}  // namespace acdr
