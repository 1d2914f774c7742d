#include "pipeline/reference/mesa_peer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"

#if TEXSIM_HAVE_MESA
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>
#endif

namespace texsim {

const char* to_string(MesaDriver d) { return d == MesaDriver::Softpipe ? "softpipe" : "llvmpipe"; }

Rgba MesaImage::at(int x, int y) const {
  const size_t i =
      (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 4;
  constexpr float k = 1.0f / 255.0f;
  return {static_cast<float>(rgba[i]) * k, static_cast<float>(rgba[i + 1]) * k,
          static_cast<float>(rgba[i + 2]) * k, static_cast<float>(rgba[i + 3]) * k};
}

MesaView mesa_view(const Scene& scene, const TextureSet& textures,
                   const std::vector<AddressMode>& address) {
  MesaView v;
  v.camera = scene.camera;
  v.background = scene.background;
  for (const ScenePrimitive& p : scene.primitives) {
    if (PlaneProjection(scene, p).culled()) continue;
    MesaPrimitive m;
    const SceneMaterial& mat = scene.materials[static_cast<size_t>(p.material)];
    if (mat.texture < 0 || mat.texture >= textures.size())
      throw InputError("Mesa peer", "material " + mat.name + " has no texture in the set");
    m.texture = &textures[mat.texture];
    m.address = address[static_cast<size_t>(p.material)];
    const bool tri = p.shape == ScenePrimitive::Shape::Triangle;
    const std::vector<std::pair<double, double>> ab =
        tri ? std::vector<std::pair<double, double>>{{0, 0}, {1, 0}, {0, 1}}
            : std::vector<std::pair<double, double>>{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& [a, b] : ab) {
      m.corners.push_back(p.origin + a * p.edge_u + b * p.edge_v);
      m.uvs.push_back(p.uv_origin + a * p.uv_edge_u + b * p.uv_edge_v);
    }
    v.primitives.push_back(std::move(m));
  }
  return v;
}

#if TEXSIM_HAVE_MESA

namespace {

// Mesa's surfaceless display is one per process: the driver it was started with, the context,
// and a lock, shared by every peer.
struct Session {
  std::mutex lock;
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::optional<MesaDriver> driver;  // the driver the display runs, if started
  std::string renderer;

  void stop() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
    context = EGL_NO_CONTEXT;
    display = EGL_NO_DISPLAY;
    driver.reset();
    renderer.clear();
  }
  // Starts the display on `d`; returns why not (empty: running).
  std::string start(MesaDriver d);
};

Session& session() {
  static Session s;
  return s;
}

// Sets an environment variable for the scope, restoring its previous value.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    const char* old = std::getenv(name);
    if (old) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

std::string egl_error(const char* what) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s failed (EGL error 0x%04x)", what,
                static_cast<unsigned>(eglGetError()));
  return buf;
}

std::string Session::start(MesaDriver d) {
  if (std::getenv("TEXSIM_NO_MESA")) return "TEXSIM_NO_MESA is set";
  if (driver == d) return "";
  stop();
  const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!ext || std::string(ext).find("EGL_MESA_platform_surfaceless") == std::string::npos)
    return "EGL has no EGL_MESA_platform_surfaceless (libegl-mesa0 not installed?)";
  const auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_display) return "EGL has no eglGetPlatformDisplayEXT";
  {
    const ScopedEnv soft("LIBGL_ALWAYS_SOFTWARE", "1");
    const ScopedEnv gallium("GALLIUM_DRIVER", to_string(d));
    display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) return egl_error("eglGetPlatformDisplayEXT(surfaceless)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
      const std::string e = egl_error("eglInitialize");
      display = EGL_NO_DISPLAY;
      return e + " (libgl1-mesa-dri not installed?)";
    }
  }
  if (!eglBindAPI(EGL_OPENGL_API)) return egl_error("eglBindAPI(OpenGL)");
  const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION,
                          3,
                          EGL_CONTEXT_MINOR_VERSION,
                          3,
                          EGL_CONTEXT_OPENGL_PROFILE_MASK,
                          EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                          EGL_NONE};
  context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
  if (context == EGL_NO_CONTEXT) return egl_error("eglCreateContext(OpenGL 3.3 core)");
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
    return egl_error("eglMakeCurrent");
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const std::string rs = r ? r : "";
  renderer = rs + ", " + (v ? v : "");
  // Mesa falls back to another driver when the one asked for is not built in.
  if (!rs.starts_with(to_string(d)))
    return "asked for " + std::string(to_string(d)) + ", got " + renderer;
  driver = d;
  return "";
}

const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec4 clip;
layout(location = 1) in vec2 uv;
out vec2 t;
void main() { gl_Position = clip; t = uv; }
)";
const char* const kFragmentShader = R"(#version 330 core
uniform sampler2D tex;
in vec2 t;
out vec4 colour;
void main() { colour = texture(tex, t); }
)";

GLuint compile(GLenum kind, const char* src) {
  const GLuint s = glCreateShader(kind);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw InputError("Mesa peer", std::string("shader does not compile: ") + log);
  }
  return s;
}

// Throws with the step that OpenGL refused.
void check(const std::string& step) {
  const GLenum err = glGetError();
  if (err == GL_NO_ERROR) return;
  char buf[32];
  std::snprintf(buf, sizeof buf, "OpenGL error 0x%04x", static_cast<unsigned>(err));
  throw InputError("Mesa peer", std::string(buf) + " in " + step);
}

GLint gl_wrap(AddressMode m) {
  switch (m) {
    case AddressMode::Wrap:
      return GL_REPEAT;
    case AddressMode::Clamp:
      return GL_CLAMP_TO_EDGE;
    case AddressMode::Mirror:
      return GL_MIRRORED_REPEAT;
    case AddressMode::Border:
      return GL_CLAMP_TO_BORDER;  // GL's default border colour: transparent black
    case AddressMode::MirrorClamp:
      return 0x8743;  // GL_MIRROR_CLAMP_TO_EDGE (ARB_texture_mirror_clamp_to_edge, GL 4.4)
  }
  return GL_REPEAT;
}

// The texture's mip pyramid, level by level, and its sampler state.
GLuint upload(const Texture& tex, AddressMode address, const MesaView& view) {
  GLuint name = 0;
  glGenTextures(1, &name);
  glBindTexture(GL_TEXTURE_2D, name);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const bool u8 = tex.format() == TexelFormat::Rgba8;
  for (int l = 0; l < tex.levels(); ++l) {
    const Texture::Level& lv = tex.level(l);
    glTexImage2D(GL_TEXTURE_2D, l, u8 ? GL_RGBA8 : GL_RGBA32F, lv.width, lv.height, 0, GL_RGBA,
                 u8 ? GL_UNSIGNED_BYTE : GL_FLOAT,
                 u8 ? static_cast<const void*>(tex.rgba8(l)) : tex.rgba32f(l));
    check("glTexImage2D of " + tex.name() + " level " + std::to_string(l) + " (" +
          std::to_string(lv.width) + "x" + std::to_string(lv.height) + ")");
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, tex.levels() - 1);
  glTexParameteri(
      GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
      view.filter == MesaFilter::Bilinear ? GL_LINEAR_MIPMAP_NEAREST : GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, gl_wrap(address));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, gl_wrap(address));
  glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY,
                  view.filter == MesaFilter::Anisotropic ? view.max_aniso : 1.0f);
  return name;
}

// Clip coordinates of every corner, computed in double from the camera as texsim's plane
// projection sees it (x right, y up, w = depth along the view direction), then one
// (clip, uv) vertex list of triangles per primitive.
struct Vertices {
  std::vector<float> data;                  // x y z w u v per vertex
  std::vector<std::pair<int, int>> ranges;  // first vertex, count per primitive
};

Vertices clip_vertices(const MesaView& view) {
  const Camera& cam = view.camera;
  const glm::dvec3 f = glm::normalize(cam.look_at - cam.position);
  const glm::dvec3 r = glm::normalize(glm::cross(f, cam.up));
  const glm::dvec3 up = glm::cross(r, f);
  const double th =
      static_cast<double>(cam.orthographic ? cam.ortho_half_height : cam.tan_half_fov_y);
  const double aspect = static_cast<double>(cam.width) / cam.height;
  double far = cam.near * 2;
  for (const MesaPrimitive& p : view.primitives) {
    for (const glm::dvec3& c : p.corners)
      far = std::max(far, 2 * glm::dot(c - cam.position, f) + 1);
  }
  const double n = cam.near;
  Vertices out;
  for (const MesaPrimitive& p : view.primitives) {
    const int first = static_cast<int>(out.data.size() / 6);
    const std::vector<int> order =
        p.corners.size() == 4 ? std::vector<int>{0, 1, 2, 0, 2, 3} : std::vector<int>{0, 1, 2};
    for (int i : order) {
      const glm::dvec3 d = p.corners[static_cast<size_t>(i)] - cam.position;
      const double x = glm::dot(d, r), y = glm::dot(d, up), z = glm::dot(d, f);
      const double w = cam.orthographic ? 1.0 : z;
      const double zc = cam.orthographic ? 2 * (z - n) / (far - n) - 1
                                         : ((far + n) * z - 2 * far * n) / (far - n);
      const glm::dvec2 uv = p.uvs[static_cast<size_t>(i)];
      for (double c : {x / (th * aspect), y / th, zc, w, uv.x, uv.y})
        out.data.push_back(static_cast<float>(c));
    }
    out.ranges.emplace_back(first, static_cast<int>(order.size()));
  }
  return out;
}

// The GL objects of one render, deleted on every exit.
struct GlObjects {
  GLuint fbo = 0, colour = 0, depth = 0, program = 0, vao = 0, vbo = 0;
  std::vector<GLuint> textures;
  GlObjects() = default;
  GlObjects(const GlObjects&) = delete;
  GlObjects& operator=(const GlObjects&) = delete;
  ~GlObjects() {
    if (!textures.empty()) glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
    glDeleteBuffers(1, &vbo);
    glDeleteVertexArrays(1, &vao);
    if (program) glDeleteProgram(program);
    glDeleteRenderbuffers(1, &depth);
    glDeleteRenderbuffers(1, &colour);
    glDeleteFramebuffers(1, &fbo);
  }
};

void make_target(GlObjects& g, int w, int h) {
  glGenFramebuffers(1, &g.fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
  glGenRenderbuffers(1, &g.colour);
  glBindRenderbuffer(GL_RENDERBUFFER, g.colour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.colour);
  glGenRenderbuffers(1, &g.depth);
  glBindRenderbuffer(GL_RENDERBUFFER, g.depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.depth);
  check("the " + std::to_string(w) + "x" + std::to_string(h) + " framebuffer object");
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw InputError("Mesa peer", "the RGBA8 + depth framebuffer object is incomplete");
}

void make_program(GlObjects& g) {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  g.program = glCreateProgram();
  glAttachShader(g.program, vs);
  glAttachShader(g.program, fs);
  glLinkProgram(g.program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(g.program, GL_LINK_STATUS, &ok);
  if (!ok) throw InputError("Mesa peer", "the shader program does not link");
}

// Vertices and textures of the view in GL objects: one texture per (texture, address mode).
struct Prepared {
  Vertices vx;
  std::vector<GLuint> texture_of;  // per primitive
};

Prepared prepare(GlObjects& g, const MesaView& view) {
  Prepared pr{clip_vertices(view), {}};
  glGenVertexArrays(1, &g.vao);
  glBindVertexArray(g.vao);
  glGenBuffers(1, &g.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(pr.vx.data.size() * sizeof(float)),
               pr.vx.data.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        // NOLINTNEXTLINE(performance-no-int-to-ptr): OpenGL's buffer offset
                        reinterpret_cast<const void*>(4 * sizeof(float)));
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glUseProgram(g.program);
  glUniform1i(glGetUniformLocation(g.program, "tex"), 0);
  glActiveTexture(GL_TEXTURE0);
  std::map<std::pair<const Texture*, AddressMode>, GLuint> uploaded;
  for (const MesaPrimitive& p : view.primitives) {
    GLuint& t = uploaded[{p.texture, p.address}];
    if (!t) {
      t = upload(*p.texture, p.address, view);
      g.textures.push_back(t);
    }
    pr.texture_of.push_back(t);
  }
  return pr;
}

void draw(const Prepared& pr) {
  for (size_t i = 0; i < pr.texture_of.size(); ++i) {
    glBindTexture(GL_TEXTURE_2D, pr.texture_of[i]);
    glDrawArrays(GL_TRIANGLES, pr.vx.ranges[i].first, pr.vx.ranges[i].second);
    check("drawing primitive " + std::to_string(i));
  }
}

// The framebuffer, program and state of one render, cleared to the background.
void begin(GlObjects& g, const MesaView& view, bool depth_test) {
  while (glGetError() != GL_NO_ERROR) {
  }
  const int w = view.camera.width, h = view.camera.height;
  make_target(g, w, h);
  make_program(g);
  glViewport(0, 0, w, h);
  glDisable(GL_BLEND);
  if (depth_test) {
    glEnable(GL_DEPTH_TEST);
  } else {
    glDisable(GL_DEPTH_TEST);
  }
  glDepthFunc(GL_LESS);
  glClearColor(static_cast<float>(view.background.x), static_cast<float>(view.background.y),
               static_cast<float>(view.background.z), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

}  // namespace

MesaPeer::MesaPeer(MesaDriver driver) : driver_(driver) {
  Session& s = session();
  const std::lock_guard<std::mutex> hold(s.lock);
  const std::string e = s.start(driver);
  if (!e.empty()) {
    why_not_ = "Mesa not available: " + e;
    s.stop();
    return;
  }
  renderer_ = s.renderer;
}

MesaImage MesaPeer::render(const MesaView& view) const {
  if (!available()) throw InputError("Mesa peer", why_not_);
  Session& s = session();
  const std::lock_guard<std::mutex> hold(s.lock);
  const std::string e = s.start(driver_);
  if (!e.empty()) throw InputError("Mesa peer", "Mesa not available: " + e);
  eglMakeCurrent(s.display, EGL_NO_SURFACE, EGL_NO_SURFACE, s.context);
  const int w = view.camera.width, h = view.camera.height;
  MesaImage img{w, h, std::vector<uint8_t>(static_cast<size_t>(w) * static_cast<size_t>(h) * 4)};
  {
    GlObjects g;
    begin(g, view, true);
    draw(prepare(g, view));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    std::vector<uint8_t> rows(img.rgba.size());
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    check("reading the image back");
    // OpenGL's row 0 is the bottom one.
    const size_t stride = static_cast<size_t>(w) * 4;
    for (int y = 0; y < h; ++y) {
      std::copy_n(
          rows.begin() + static_cast<std::ptrdiff_t>(stride * static_cast<size_t>(h - 1 - y)),
          stride, img.rgba.begin() + static_cast<std::ptrdiff_t>(stride * static_cast<size_t>(y)));
    }
  }
  return img;
}

double MesaPeer::time_draws(const MesaView& view, int draws) const {
  if (!available()) throw InputError("Mesa peer", why_not_);
  Session& s = session();
  const std::lock_guard<std::mutex> hold(s.lock);
  const std::string e = s.start(driver_);
  if (!e.empty()) throw InputError("Mesa peer", "Mesa not available: " + e);
  eglMakeCurrent(s.display, EGL_NO_SURFACE, EGL_NO_SURFACE, s.context);
  GlObjects g;
  begin(g, view, false);
  const Prepared pr = prepare(g, view);
  draw(pr);
  glFinish();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < draws; ++i) draw(pr);
  glFinish();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

namespace {
// A 2-D texture object bound for the duration of a codec call.
struct ScopedTexture {
  GLuint id = 0;
  ScopedTexture() {
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
  }
  ~ScopedTexture() { glDeleteTextures(1, &id); }
  ScopedTexture(const ScopedTexture&) = delete;
  ScopedTexture& operator=(const ScopedTexture&) = delete;
};
}  // namespace

MesaImage MesaPeer::decode_blocks(uint32_t gl_format, int width, int height,
                                  const std::vector<uint8_t>& blocks, uint32_t gl_type) const {
  if (width <= 0 || height <= 0 || width % 4 != 0 || height % 4 != 0)
    throw InputError("Mesa peer", "compressed texture size must be positive multiples of 4");
  return {width, height, decode_compressed(gl_format, width, height, blocks, GL_RGBA, gl_type, 4)};
}

std::vector<uint8_t> MesaPeer::encode_blocks(uint32_t gl_format, const MesaImage& image) const {
  if (!available()) throw InputError("Mesa peer", why_not_);
  Session& s = session();
  const std::lock_guard<std::mutex> hold(s.lock);
  const std::string e = s.start(driver_);
  if (!e.empty()) throw InputError("Mesa peer", "Mesa not available: " + e);
  eglMakeCurrent(s.display, EGL_NO_SURFACE, EGL_NO_SURFACE, s.context);
  const ScopedTexture tex;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(gl_format), image.width, image.height, 0,
               GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  check("compressing the image");
  GLint size = 0;
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_COMPRESSED_IMAGE_SIZE, &size);
  std::vector<uint8_t> blocks(static_cast<size_t>(std::max(size, 0)));
  glGetCompressedTexImage(GL_TEXTURE_2D, 0, blocks.data());
  check("reading the compressed blocks back");
  return blocks;
}

std::vector<uint8_t> MesaPeer::decode_compressed(uint32_t gl_format, int width, int height,
                                                 std::span<const uint8_t> data,
                                                 uint32_t read_format, uint32_t read_type,
                                                 size_t texel_bytes) const {
  if (!available()) throw InputError("Mesa peer", why_not_);
  Session& s = session();
  const std::lock_guard<std::mutex> hold(s.lock);
  const std::string e = s.start(driver_);
  if (!e.empty()) throw InputError("Mesa peer", "Mesa not available: " + e);
  eglMakeCurrent(s.display, EGL_NO_SURFACE, EGL_NO_SURFACE, s.context);
  while (glGetError() != GL_NO_ERROR) {
  }
  GlObjects g;
  g.textures.push_back(0);
  glGenTextures(1, g.textures.data());
  glBindTexture(GL_TEXTURE_2D, g.textures[0]);
  glCompressedTexImage2D(GL_TEXTURE_2D, 0, gl_format, width, height, 0,
                         static_cast<GLsizei>(data.size()), data.data());
  check("glCompressedTexImage2D");
  std::vector<uint8_t> out(static_cast<size_t>(width) * static_cast<size_t>(height) * texel_bytes);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTexImage(GL_TEXTURE_2D, 0, read_format, read_type, out.data());
  check("glGetTexImage of the compressed image");
  return out;
}

#else  // built without EGL/OpenGL

MesaPeer::MesaPeer(MesaDriver driver)
    : driver_(driver),
      why_not_(
          "Mesa not available: texsim was built without EGL and OpenGL (libegl-dev, "
          "libgl-dev)") {}

MesaImage MesaPeer::render(const MesaView&) const { throw InputError("Mesa peer", why_not_); }

double MesaPeer::time_draws(const MesaView&, int) const { throw InputError("Mesa peer", why_not_); }

std::vector<uint8_t> MesaPeer::decode_compressed(uint32_t, int, int, std::span<const uint8_t>,
                                                 uint32_t, uint32_t, size_t) const {
  throw InputError("Mesa peer", why_not_);
}

MesaImage MesaPeer::decode_blocks(uint32_t, int, int, const std::vector<uint8_t>&, uint32_t) const {
  throw InputError("Mesa peer", why_not_);
}

std::vector<uint8_t> MesaPeer::encode_blocks(uint32_t, const MesaImage&) const {
  throw InputError("Mesa peer", why_not_);
}

#endif

}  // namespace texsim
