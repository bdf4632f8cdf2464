// The scene renderer: shaders, buffer management and the draw order of a frame.
#include "ui/scene_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "ui/mesh_normals.hpp"
#include "ui/render_camera.hpp"

namespace acdr {

namespace {

// Lighting shared by every fragment shader. Two directional lights fixed to the camera (a warm
// key from the upper left, a cool fill from the right) keep every view readable while the user
// orbits; a hemisphere ambient (sky above, dark ground below, by the world's +z) tells up from
// down. Colours are taken as sRGB, lit in linear space and encoded back, as the framebuffer
// (OSMesa's RGBA8 or a window's) holds sRGB-looking values; gamma 2 (square, square root)
// stands in for sRGB's 2.2 because pow() is costly per pixel on a software rasteriser.
const char* kLightingGlsl = R"(
uniform vec3 u_key_dir;   // towards the key light, view space, unit
uniform vec3 u_fill_dir;  // towards the fill light, view space, unit
uniform vec3 u_up_dir;    // world +z in view space, unit
const vec3 kKeyColor = vec3(1.00, 0.96, 0.90) * 0.95;
const vec3 kFillColor = vec3(0.60, 0.68, 0.85) * 0.35;
const vec3 kSkyAmbient = vec3(0.26, 0.28, 0.32);
const vec3 kGroundAmbient = vec3(0.07, 0.065, 0.06);

// Key-light shadows: the depth map seen from the light, and the matrix taking a view-space
// position to its coordinates there (0..1 in x, y and depth).
uniform sampler2DShadow u_shadow_map;
uniform mat4 u_view_to_shadow;
uniform float u_shadow_on;         // 0 or 1
uniform float u_shadow_offset;     // along the normal, m: keeps surfaces out of their own shadow
uniform float u_shadow_bias;       // in map depth units

// 1 where the key light reaches the point, 0 in shadow; the comparison sampler's linear filter
// blends the four nearest map texels (a 2 x 2 percentage-closer filter).
float key_visibility(vec3 pos_view, vec3 n) {
  if (u_shadow_on < 0.5) return 1.0;
  vec4 s = u_view_to_shadow * vec4(pos_view + u_shadow_offset * n, 1.0);
  if (any(lessThan(s.xyz, vec3(0.0))) || any(greaterThan(s.xyz, vec3(1.0)))) return 1.0;
  return texture(u_shadow_map, vec3(s.xy, s.z - u_shadow_bias));
}

vec3 to_linear(vec3 srgb) { return srgb * srgb; }

// `base` is the surface colour in linear space (to_linear of an sRGB colour).
vec3 shade_linear(vec3 base, vec3 n, vec3 pos_view, float specular) {
  vec3 v = normalize(-pos_view);
  float hemi = 0.5 + 0.5 * dot(n, u_up_dir);
  vec3 color = base * mix(kGroundAmbient, kSkyAmbient, hemi);
  float key = max(dot(n, u_key_dir), 0.0);
  if (key > 0.0) key *= key_visibility(pos_view, n);
  color += base * kKeyColor * key;
  color += base * kFillColor * max(dot(n, u_fill_dir), 0.0);
  // Blinn-Phong highlight of the key light only, and only on the lit side.
  vec3 h = normalize(u_key_dir + v);
  float shininess = mix(16.0, 80.0, specular);
  color += kKeyColor * specular * pow(max(dot(n, h), 0.0), shininess) * step(0.0001, key);
  return sqrt(clamp(color, 0.0, 1.0));
}

vec3 shade(vec3 base_srgb, vec3 n, vec3 pos_view, float specular) {
  return shade_linear(to_linear(clamp(base_srgb, 0.0, 1.0)), n, pos_view, specular);
}
)";

const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform mat3 u_normal_matrix;
out vec3 v_pos_view;
out vec3 v_normal_view;
out vec3 v_pos_world;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  vec4 p = u_view * world;
  v_pos_world = world.xyz;
  v_pos_view = p.xyz;
  v_normal_view = u_normal_matrix * a_normal;
  gl_Position = u_proj * p;
}
)";

// Tissue finishes (RenderMesh::finish): 0 plain, 1 wet gel, 2 fibrous annulus, 3 cartilage.
const char* kMeshFragment = R"(
in vec3 v_pos_view;
in vec3 v_normal_view;
in vec3 v_pos_world;
uniform vec4 u_rgba;
uniform float u_specular;
uniform int u_finish;
uniform vec3 u_pattern_origin;  // world, m
uniform vec3 u_pattern_axis;    // world, unit
out vec4 out_color;

// Soft tissue: light wraps past the terminator (`wrap`, 0..1: scattering inside a translucent
// material), highlights from both lights (a wet surface glints more than once), and a Fresnel
// rim reflecting the sky at grazing angles (`rim`).
vec3 shade_tissue(vec3 base, vec3 n, vec3 pos_view, float specular, float wrap, float shininess,
                  float rim) {
  vec3 v = normalize(-pos_view);
  float hemi = 0.5 + 0.5 * dot(n, u_up_dir);
  vec3 color = base * mix(kGroundAmbient, kSkyAmbient, hemi);
  float ndl = dot(n, u_key_dir);
  float visible = key_visibility(pos_view, n);
  float key = max((ndl + wrap) / (1.0 + wrap), 0.0);
  // Scattered light also softens the cast shadow a little.
  color += base * kKeyColor * key * mix(visible, 1.0, 0.3 * wrap);
  color += base * kFillColor * max((dot(n, u_fill_dir) + wrap) / (1.0 + wrap), 0.0);
  vec3 h = normalize(u_key_dir + v);
  color += kKeyColor * specular * pow(max(dot(n, h), 0.0), shininess) * visible * step(0.0, ndl);
  vec3 hf = normalize(u_fill_dir + v);
  color += 2.0 * kFillColor * specular * pow(max(dot(n, hf), 0.0), shininess);
  float fresnel = pow(1.0 - max(dot(n, v), 0.0), 5.0);
  color += rim * fresnel * kSkyAmbient * 2.0;
  return sqrt(clamp(color, 0.0, 1.0));
}

// 0..1 stripes with `coord` cycles, faded to their mean where a cycle gets narrower than about
// two pixels, so fine fibres never alias into moire.
float stripes(float coord) {
  float cycles_per_pixel = fwidth(coord);
  float s = 0.5 + 0.5 * cos(6.2831853 * coord);
  return mix(s, 0.5, clamp(2.5 * cycles_per_pixel - 0.25, 0.0, 1.0));
}

// Annulus: lamellae as concentric rings about the disc's axis (about 0.6 mm apart), each of
// fibre bundles at about 30 degrees to the disc's plane, the angle alternating from one to the
// next (drawn 0.25 mm apart: real fibres are finer than a pixel at any useful zoom).
vec3 fibrous_base(vec3 base) {
  vec3 a = normalize(u_pattern_axis);
  vec3 rel = v_pos_world - u_pattern_origin;
  float along = dot(rel, a);
  vec3 radial = rel - along * a;
  float rho = length(radial);
  // Angle about the axis, 0 at the front (the seam of atan lies at the back).
  vec3 e1 = normalize(abs(a.x) < 0.9 ? cross(vec3(1.0, 0.0, 0.0), a) : cross(vec3(0.0, 0.0, 1.0), a));
  vec3 e2 = cross(a, e1);
  float theta = atan(dot(radial, e2), dot(radial, e1));
  float lamella = rho / 0.6e-3;
  float side = mod(floor(lamella), 2.0) < 1.0 ? 1.0 : -1.0;
  float fibre = (0.5 * rho * theta - side * 0.866 * along) / 0.25e-3;
  float tone = 0.80 + 0.10 * stripes(lamella) + 0.14 * stripes(fibre);
  // A pearly, slightly yellow tint between lamellae.
  return base * tone * mix(vec3(1.0, 0.97, 0.90), vec3(1.0), stripes(lamella));
}

void main() {
  vec3 n = normalize(v_normal_view);
  if (!gl_FrontFacing) n = -n;  // the inside of an open or clipped mesh is lit as well
  float alpha = u_rgba.a;
  if (alpha < 1.0) {
    // Translucent shapes (danger zones) grow more opaque towards their silhouette, so their
    // outline reads even when the fill is faint.
    float rim = pow(1.0 - abs(dot(n, normalize(-v_pos_view))), 3.0);
    alpha = mix(alpha, min(1.0, 2.0 * alpha + 0.25), rim);
  }
  vec3 base = to_linear(clamp(u_rgba.rgb, 0.0, 1.0));
  vec3 color;
  if (u_finish == 1) {
    color = shade_tissue(base, n, v_pos_view, u_specular, 0.5, 140.0, 0.6);
  } else if (u_finish == 2) {
    color = shade_tissue(fibrous_base(base), n, v_pos_view, u_specular, 0.15, 24.0, 0.15);
  } else if (u_finish == 3) {
    color = shade_tissue(base, n, v_pos_view, u_specular, 0.3, 45.0, 0.35);
  } else {
    color = shade_linear(base, n, v_pos_view, u_specular);
  }
  out_color = vec4(color, alpha);
}
)";

// Particles are ray-cast sphere impostors: each covers a small screen square, and the fragment
// shader intersects the pixel's view ray with the sphere for the exact surface, normal and depth.
// That is far cheaper than tessellated spheres on a software rasteriser (llvmpipe runs vertex
// shaders on one thread) and round at any size. The square is a point sprite (one vertex per
// particle) while the nearest sphere fits the implementation's point size limit, else an
// instanced camera-facing quad (four vertices per particle).
const char* kParticlePointVertex = R"(#version 330 core
layout(location = 1) in vec3 a_center;   // world, m
layout(location = 2) in vec4 a_color;    // sRGB, alpha ignored
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_radius;
uniform vec4 u_viewport;  // x, y, width, height in pixels
flat out vec3 v_center_view;
flat out vec3 v_color;
void main() {
  vec3 c = (u_view * vec4(a_center, 1.0)).xyz;
  v_center_view = c;
  v_color = a_color.rgb * a_color.rgb;  // linear, once per particle instead of per pixel
  float depth = -c.z;
  float d = length(c);
  // The sprite sits at the centre's pixel with the depth of the sphere's nearest plane
  // (z = c.z + r), a lower bound of every depth the fragment shader writes; that lets the
  // rasteriser reject hidden sprites early (conservative depth, in the fragment shader).
  vec4 clip = u_proj * vec4(c, 1.0);
  vec4 front = u_proj * vec4(c + vec3(0.0, 0.0, u_radius), 1.0);
  gl_Position = vec4(clip.xy, front.z / front.w * clip.w, clip.w);
  if (depth <= u_radius || d <= 1.01 * u_radius) {  // behind or around the eye: drop it
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    return;
  }
  // The outline of a sphere at depth z and angle t off the view axis reaches r * P11 * h / (2 z)
  // pixels from its centre's pixel across the radial direction and 1 / cos(t) times that along
  // it (to first order in r / d); a pixel more absorbs rounding of the sprite size.
  float cos_off_axis = max(depth / d, 0.3);
  float radius_px = u_radius * u_proj[1][1] * 0.5 * u_viewport.w / depth;
  gl_PointSize = 2.0 * radius_px / cos_off_axis + 1.0;
}
)";

const char* kParticleQuadVertex = R"(#version 330 core
layout(location = 0) in vec2 a_corner;   // -1..1
layout(location = 1) in vec3 i_center;   // world, m
layout(location = 2) in vec4 i_color;    // sRGB, alpha ignored
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_radius;
flat out vec3 v_center_view;
flat out vec3 v_color;
void main() {
  vec3 c = (u_view * vec4(i_center, 1.0)).xyz;
  float d = length(c);
  v_center_view = c;
  v_color = i_color.rgb * i_color.rgb;  // linear
  if (d <= 1.01 * u_radius) {  // camera inside the sphere: drop it
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  // The quad lies in the sphere's nearest plane (z = c.z + r), so its depth is a lower bound of
  // the sphere's (conservative depth). Seen from distance d the outline cone crosses that plane
  // within (d - r) r / sqrt(d^2 - r^2) of the axis; 15 % more covers off-axis stretch.
  float grow = 1.15 * (d - u_radius) / sqrt(d * d - u_radius * u_radius);
  gl_Position = u_proj * vec4(c + vec3(a_corner * (u_radius * grow), u_radius), 1.0);
}
)";

// Declares that written depths are never nearer than the rasterised one (see the vertex
// shaders), so early depth rejection stays valid although the shader writes gl_FragDepth.
const char* kParticleFragmentPrelude = R"(
#extension GL_ARB_conservative_depth : enable
#ifdef GL_ARB_conservative_depth
layout(depth_greater) out float gl_FragDepth;
#endif
)";

const char* kParticleFragment = R"(
flat in vec3 v_center_view;
flat in vec3 v_color;
uniform mat4 u_proj;
uniform float u_radius;
uniform vec4 u_viewport;  // x, y, width, height in pixels
out vec4 out_color;
void main() {
  // The view ray through this pixel (perspective projection: x_ndc = P00 x / -z).
  vec2 ndc = 2.0 * (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw - 1.0;
  vec3 dir = normalize(vec3(ndc.x / u_proj[0][0], ndc.y / u_proj[1][1], -1.0));
  float b = dot(dir, v_center_view);
  // Squared distance of the ray from the centre, taken from the perpendicular offset rather
  // than |c|^2 - b^2, which would cancel badly at millimetre radii and decimetre distances.
  vec3 q = v_center_view - b * dir;
  float disc = u_radius * u_radius - dot(q, q);
  if (disc < 0.0) discard;
  vec3 p = dir * (b - sqrt(disc));
  vec3 n = (p - v_center_view) / u_radius;
  // Window depth of p: clip z = P22 z + P32, clip w = -z.
  gl_FragDepth = 0.5 * (u_proj[2][2] * p.z + u_proj[3][2]) / -p.z + 0.5;
  out_color = vec4(shade_linear(v_color, n, p, 0.2), 1.0);
}
)";

// Shadow pass: depth as seen from the key light (orthographic). Meshes as they are; particles
// as discs facing the light with the depth of the sphere's surface, so they shade each other.
const char* kShadowMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_vp;
uniform mat4 u_model;
void main() { gl_Position = u_light_vp * (u_model * vec4(a_position, 1.0)); }
)";

const char* kShadowMeshFragment = R"(#version 330 core
void main() {}
)";

const char* kShadowParticleVertex = R"(#version 330 core
layout(location = 1) in vec3 a_center;
uniform mat4 u_light_vp;
uniform float u_point_scale;  // map pixels per metre
uniform float u_radius;
void main() {
  gl_Position = u_light_vp * vec4(a_center, 1.0);
  gl_PointSize = 2.0 * u_radius * u_point_scale + 1.0;
}
)";

const char* kShadowParticleFragment = R"(#version 330 core
uniform float u_radius;
uniform float u_depth_per_m;  // map depth units per metre along the light
void main() {
  vec2 d = 2.0 * gl_PointCoord - 1.0;
  float rr = dot(d, d);
  if (rr > 1.0) discard;
  // The sphere's near surface is r * sqrt(1 - rr) closer to the light than its centre.
  gl_FragDepth = gl_FragCoord.z - u_radius * sqrt(1.0 - rr) * u_depth_per_m;
}
)";

// The ground: a square in the plane z = h; a grid whose lines keep one pixel's width at any
// distance (screen-space derivatives) and a fade to the background with distance.
const char* kGroundVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;  // world, m
uniform mat4 u_view;
uniform mat4 u_proj;
out vec3 v_world;
out vec3 v_pos_view;
void main() {
  v_world = a_position;
  vec4 p = u_view * vec4(a_position, 1.0);
  v_pos_view = p.xyz;
  gl_Position = u_proj * p;
}
)";

const char* kGroundFragment = R"(
in vec3 v_world;
in vec3 v_pos_view;
uniform vec3 u_ground_rgb;
uniform vec2 u_ground_center;
uniform float u_fade_radius;
uniform float u_grid_spacing;
out vec4 out_color;
void main() {
  vec3 base = u_ground_rgb;
  if (u_grid_spacing > 0.0) {
    vec2 coord = v_world.xy / u_grid_spacing;
    vec2 dist = abs(fract(coord - 0.5) - 0.5) / max(fwidth(coord), vec2(1e-6));
    float line = 1.0 - min(min(dist.x, dist.y), 1.0);
    base *= 1.0 - 0.25 * line;
  }
  vec3 n = u_up_dir;
  if (!gl_FrontFacing) n = -n;
  float r = length(v_world.xy - u_ground_center) / u_fade_radius;
  float alpha = 1.0 - smoothstep(0.45, 1.0, r);
  out_color = vec4(shade(base, n, v_pos_view, 0.0), alpha);
}
)";

// Directions towards the lights in view space (x right, y up, z towards the viewer).
const Eigen::Vector3f kKeyDirView = Eigen::Vector3f(-0.45f, 0.70f, 0.55f).normalized();
const Eigen::Vector3f kFillDirView = Eigen::Vector3f(0.70f, -0.15f, 0.60f).normalized();

// The texture unit of the shadow map (unit 0 stays free for ImGui and other overlays).
constexpr int kShadowTextureUnit = 1;

// Packed particle instance: centre (3 floats, m) + colour (4 unsigned bytes).
constexpr std::size_t kInstanceBytes = 16;

std::uint8_t to_byte(float c) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

Eigen::Vector3f key_light_direction(const RenderCamera& camera) {
  return (view_matrix(camera).block<3, 3>(0, 0).transpose() * kKeyDirView).normalized();
}

std::unique_ptr<SceneRenderer> SceneRenderer::create(const GlFunctions& gl, std::string* error) {
  const std::vector<std::string> absent = gl.missing();
  if (!absent.empty()) {
    if (error) *error = "SceneRenderer: GL table not loaded (first missing: " + absent[0] + ")";
    return nullptr;
  }
  std::unique_ptr<SceneRenderer> renderer(new SceneRenderer(gl));
  if (!renderer->init(error)) return nullptr;
  return renderer;
}

bool SceneRenderer::build_program(Program& program, const char* vertex_src,
                                  const char* fragment_src, const char* name,
                                  std::string* error, const char* fragment_prelude) {
  // Fragment shaders share the lighting code, inserted after the version line and any
  // extension directives (which must come first); complete shaders (starting with their own
  // #version, as in the shadow pass) are taken as they are.
  const bool complete = std::string(fragment_src).rfind("#version", 0) == 0;
  const std::string fragment =
      complete ? std::string(fragment_src)
               : std::string("#version 330 core\n") + fragment_prelude + kLightingGlsl +
                     fragment_src;
  const char* sources[2] = {vertex_src, fragment.c_str()};
  const GLenum kinds[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  GLuint shaders[2] = {0, 0};
  bool ok = true;
  for (int i = 0; i < 2 && ok; ++i) {
    shaders[i] = gl_.CreateShader(kinds[i]);
    gl_.ShaderSource(shaders[i], 1, &sources[i], nullptr);
    gl_.CompileShader(shaders[i]);
    GLint status = GL_FALSE;
    gl_.GetShaderiv(shaders[i], GL_COMPILE_STATUS, &status);
    if (status != GL_TRUE) {
      char log[4096] = {0};
      gl_.GetShaderInfoLog(shaders[i], sizeof(log), nullptr, log);
      if (error) {
        *error = std::string("SceneRenderer: ") + name + (i == 0 ? " vertex" : " fragment") +
                 " shader does not compile: " + log;
      }
      ok = false;
    }
  }
  if (ok) {
    program.id = gl_.CreateProgram();
    gl_.AttachShader(program.id, shaders[0]);
    gl_.AttachShader(program.id, shaders[1]);
    gl_.LinkProgram(program.id);
    GLint status = GL_FALSE;
    gl_.GetProgramiv(program.id, GL_LINK_STATUS, &status);
    if (status != GL_TRUE) {
      char log[4096] = {0};
      gl_.GetProgramInfoLog(program.id, sizeof(log), nullptr, log);
      if (error) *error = std::string("SceneRenderer: ") + name + " program does not link: " + log;
      ok = false;
    }
    gl_.DetachShader(program.id, shaders[0]);
    gl_.DetachShader(program.id, shaders[1]);
  }
  for (GLuint shader : shaders) {
    if (shader) gl_.DeleteShader(shader);
  }
  if (!ok) return false;

  const GLuint id = program.id;
  program.model = gl_.GetUniformLocation(id, "u_model");
  program.view = gl_.GetUniformLocation(id, "u_view");
  program.proj = gl_.GetUniformLocation(id, "u_proj");
  program.normal_matrix = gl_.GetUniformLocation(id, "u_normal_matrix");
  program.rgba = gl_.GetUniformLocation(id, "u_rgba");
  program.specular = gl_.GetUniformLocation(id, "u_specular");
  program.key_dir = gl_.GetUniformLocation(id, "u_key_dir");
  program.fill_dir = gl_.GetUniformLocation(id, "u_fill_dir");
  program.up_dir = gl_.GetUniformLocation(id, "u_up_dir");
  program.radius = gl_.GetUniformLocation(id, "u_radius");
  program.ground_center = gl_.GetUniformLocation(id, "u_ground_center");
  program.fade_radius = gl_.GetUniformLocation(id, "u_fade_radius");
  program.ground_rgb = gl_.GetUniformLocation(id, "u_ground_rgb");
  program.grid_spacing = gl_.GetUniformLocation(id, "u_grid_spacing");
  program.viewport = gl_.GetUniformLocation(id, "u_viewport");
  program.shadow_map = gl_.GetUniformLocation(id, "u_shadow_map");
  program.view_to_shadow = gl_.GetUniformLocation(id, "u_view_to_shadow");
  program.shadow_on = gl_.GetUniformLocation(id, "u_shadow_on");
  program.shadow_offset = gl_.GetUniformLocation(id, "u_shadow_offset");
  program.shadow_bias = gl_.GetUniformLocation(id, "u_shadow_bias");
  program.light_vp = gl_.GetUniformLocation(id, "u_light_vp");
  program.point_scale = gl_.GetUniformLocation(id, "u_point_scale");
  program.depth_per_m = gl_.GetUniformLocation(id, "u_depth_per_m");
  program.finish = gl_.GetUniformLocation(id, "u_finish");
  program.pattern_origin = gl_.GetUniformLocation(id, "u_pattern_origin");
  program.pattern_axis = gl_.GetUniformLocation(id, "u_pattern_axis");
  return true;
}

bool SceneRenderer::init(std::string* error) {
  if (!build_program(mesh_program_, kMeshVertex, kMeshFragment, "mesh", error)) return false;
  if (!build_program(particle_point_program_, kParticlePointVertex, kParticleFragment,
                     "particle (points)", error, kParticleFragmentPrelude) ||
      !build_program(particle_quad_program_, kParticleQuadVertex, kParticleFragment,
                     "particle (quads)", error, kParticleFragmentPrelude)) {
    return false;
  }
  if (!build_program(ground_program_, kGroundVertex, kGroundFragment, "ground", error) ||
      !build_program(shadow_mesh_program_, kShadowMeshVertex, kShadowMeshFragment,
                     "shadow (meshes)", error) ||
      !build_program(shadow_particle_program_, kShadowParticleVertex, kShadowParticleFragment,
                     "shadow (particles)", error)) {
    return false;
  }
  float point_range[2] = {1.0f, 1.0f};
  gl_.GetFloatv(GL_POINT_SIZE_RANGE, point_range);
  max_point_size_px_ = point_range[1];

  // One stream of packed instances feeds both particle paths.
  gl_.GenBuffers(1, &particle_instance_vbo_);
  gl_.GenBuffers(1, &particle_corner_vbo_);
  // Points: one vertex per particle.
  gl_.GenVertexArrays(1, &particle_point_vao_);
  gl_.BindVertexArray(particle_point_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, particle_instance_vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, kInstanceBytes, nullptr, GL_STREAM_DRAW);
  gl_.EnableVertexAttribArray(1);
  gl_.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, kInstanceBytes, nullptr);
  gl_.EnableVertexAttribArray(2);
  gl_.VertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, kInstanceBytes,
                          reinterpret_cast<const void*>(3 * sizeof(float)));
  // Quads: a triangle strip of four corners, instanced per particle.
  const float corners[8] = {-1.0f, -1.0f, 1.0f, -1.0f, -1.0f, 1.0f, 1.0f, 1.0f};
  gl_.GenVertexArrays(1, &particle_quad_vao_);
  gl_.BindVertexArray(particle_quad_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, particle_corner_vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, sizeof(corners), corners, GL_STATIC_DRAW);
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
  gl_.BindBuffer(GL_ARRAY_BUFFER, particle_instance_vbo_);
  gl_.EnableVertexAttribArray(1);
  gl_.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, kInstanceBytes, nullptr);
  gl_.VertexAttribDivisor(1, 1);
  gl_.EnableVertexAttribArray(2);
  gl_.VertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, kInstanceBytes,
                          reinterpret_cast<const void*>(3 * sizeof(float)));
  gl_.VertexAttribDivisor(2, 1);

  // Ground: four corners rewritten every frame.
  gl_.GenVertexArrays(1, &ground_vao_);
  gl_.BindVertexArray(ground_vao_);
  gl_.GenBuffers(1, &ground_vbo_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, ground_vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, 12 * sizeof(float), nullptr, GL_STREAM_DRAW);
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);

  gl_.BindVertexArray(0);
  gl_.BindBuffer(GL_ARRAY_BUFFER, 0);
  const std::string gl_error = gl_error_string(gl_, "SceneRenderer::create");
  if (!gl_error.empty()) {
    if (error) *error = gl_error;
    return false;
  }
  return true;
}

SceneRenderer::~SceneRenderer() {
  clear_geometry_cache();
  for (GpuMesh& mesh : stream_) destroy_mesh(mesh);
  const GLuint buffers[3] = {particle_corner_vbo_, particle_instance_vbo_, ground_vbo_};
  gl_.DeleteBuffers(3, buffers);
  const GLuint arrays[3] = {particle_point_vao_, particle_quad_vao_, ground_vao_};
  gl_.DeleteVertexArrays(3, arrays);
  for (const Program* p : {&mesh_program_, &particle_point_program_, &particle_quad_program_,
                           &ground_program_, &shadow_mesh_program_, &shadow_particle_program_}) {
    if (p->id) gl_.DeleteProgram(p->id);
  }
  destroy_shadow_map();
}

void SceneRenderer::destroy_mesh(GpuMesh& mesh) {
  if (mesh.vao) gl_.DeleteVertexArrays(1, &mesh.vao);
  if (mesh.vbo) gl_.DeleteBuffers(1, &mesh.vbo);
  if (mesh.ebo) gl_.DeleteBuffers(1, &mesh.ebo);
  mesh = GpuMesh{};
}

void SceneRenderer::forget_geometry(std::uint64_t geometry_id) {
  auto it = cache_.find(geometry_id);
  if (it == cache_.end()) return;
  destroy_mesh(it->second);
  cache_.erase(it);
}

void SceneRenderer::clear_geometry_cache() {
  for (auto& [id, mesh] : cache_) destroy_mesh(mesh);
  cache_.clear();
}

void SceneRenderer::evict_stale_geometry() {
  for (auto it = cache_.begin(); it != cache_.end();) {
    if (frame_ - it->second.last_frame > static_cast<std::uint64_t>(cache_lifetime_frames_)) {
      destroy_mesh(it->second);
      it = cache_.erase(it);
    } else {
      ++it;
    }
  }
}

bool SceneRenderer::upload_mesh(const RenderMesh& mesh, GpuMesh& gpu) {
  // Interleave position and normal; take the mesh's normals when complete, else compute them.
  NormalMesh prepared;
  const bool has_normals = mesh.normals.size() == mesh.vertices.size() && !mesh.vertices.empty();
  if (has_normals) {
    prepared.positions = mesh.vertices;
    prepared.normals = mesh.normals;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const std::uint32_t* tri = &mesh.indices[t];
      if (tri[0] < mesh.vertices.size() && tri[1] < mesh.vertices.size() &&
          tri[2] < mesh.vertices.size()) {
        prepared.indices.insert(prepared.indices.end(), tri, tri + 3);
      }
    }
  } else {
    prepared = compute_crease_normals(mesh.vertices, mesh.indices);
  }
  if (prepared.indices.empty()) return false;

  std::vector<float> interleaved(prepared.positions.size() * 6);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = -lo;
  for (std::size_t i = 0; i < prepared.positions.size(); ++i) {
    std::memcpy(&interleaved[6 * i], prepared.positions[i].data(), 3 * sizeof(float));
    std::memcpy(&interleaved[6 * i + 3], prepared.normals[i].data(), 3 * sizeof(float));
    lo = lo.cwiseMin(prepared.positions[i]);
    hi = hi.cwiseMax(prepared.positions[i]);
  }
  gpu.local_center = 0.5f * (lo + hi);

  if (!gpu.vao) {
    gl_.GenVertexArrays(1, &gpu.vao);
    gl_.GenBuffers(1, &gpu.vbo);
    gl_.GenBuffers(1, &gpu.ebo);
    gl_.BindVertexArray(gpu.vao);
    gl_.BindBuffer(GL_ARRAY_BUFFER, gpu.vbo);
    gl_.EnableVertexAttribArray(0);
    gl_.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    gl_.EnableVertexAttribArray(1);
    gl_.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                            reinterpret_cast<const void*>(3 * sizeof(float)));
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.ebo);
  } else {
    gl_.BindVertexArray(gpu.vao);
    gl_.BindBuffer(GL_ARRAY_BUFFER, gpu.vbo);
  }
  gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
                 interleaved.data(), GL_STATIC_DRAW);
  gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(prepared.indices.size() * sizeof(std::uint32_t)),
                 prepared.indices.data(), GL_STATIC_DRAW);
  gpu.index_count = static_cast<GLsizei>(prepared.indices.size());
  gl_.BindVertexArray(0);
  return true;
}

SceneRenderer::GpuMesh* SceneRenderer::gpu_mesh_for(const RenderMesh& mesh,
                                                    std::size_t* stream_slot) {
  if (mesh.geometry_id != 0) {
    auto [it, inserted] = cache_.try_emplace(mesh.geometry_id);
    GpuMesh& gpu = it->second;
    if (inserted && !upload_mesh(mesh, gpu)) {
      // Keep the (empty) entry so a broken mesh is not re-examined every frame.
      gpu.index_count = 0;
    }
    gpu.last_frame = frame_;
    return gpu.index_count > 0 ? &gpu : nullptr;
  }
  GpuMesh& gpu = stream_[(*stream_slot)++];
  if (!upload_mesh(mesh, gpu)) return nullptr;
  return &gpu;
}

void SceneRenderer::set_lighting_uniforms(const Program& program, const Eigen::Matrix4f& view) {
  const Eigen::Vector3f up = (view.block<3, 3>(0, 0) * Eigen::Vector3f::UnitZ()).normalized();
  gl_.Uniform3f(program.key_dir, kKeyDirView.x(), kKeyDirView.y(), kKeyDirView.z());
  gl_.Uniform3f(program.fill_dir, kFillDirView.x(), kFillDirView.y(), kFillDirView.z());
  gl_.Uniform3f(program.up_dir, up.x(), up.y(), up.z());
  gl_.Uniform1i(program.shadow_map, kShadowTextureUnit);
  gl_.Uniform1f(program.shadow_on, shadow_.active ? 1.0f : 0.0f);
  gl_.UniformMatrix4fv(program.view_to_shadow, 1, GL_FALSE, shadow_.view_to_shadow.data());
  gl_.Uniform1f(program.shadow_offset, shadow_.normal_offset_m);
  gl_.Uniform1f(program.shadow_bias, shadow_.depth_bias);
}

void SceneRenderer::draw_mesh(const RenderMesh& mesh, const GpuMesh& gpu,
                              const Eigen::Matrix4f& view) {
  const Eigen::Matrix4f model = mesh.pose.matrix();
  const Eigen::Matrix3f model_view = (view * model).block<3, 3>(0, 0);
  const Eigen::Matrix3f normal_matrix = model_view.inverse().transpose();
  // A mirroring pose flips the winding; tell GL so front faces stay front faces.
  gl_.FrontFace(model.block<3, 3>(0, 0).determinant() < 0.0f ? GL_CW : GL_CCW);
  gl_.UniformMatrix4fv(mesh_program_.model, 1, GL_FALSE, model.data());
  gl_.UniformMatrix3fv(mesh_program_.normal_matrix, 1, GL_FALSE, normal_matrix.data());
  gl_.Uniform4f(mesh_program_.rgba, mesh.rgba.x(), mesh.rgba.y(), mesh.rgba.z(),
                std::clamp(mesh.rgba.w(), 0.0f, 1.0f));
  gl_.Uniform1f(mesh_program_.specular, std::clamp(mesh.specular, 0.0f, 1.0f));
  gl_.Uniform1i(mesh_program_.finish, static_cast<GLint>(mesh.finish));
  gl_.Uniform3f(mesh_program_.pattern_origin, mesh.pattern_origin.x(), mesh.pattern_origin.y(),
                mesh.pattern_origin.z());
  const Eigen::Vector3f axis = mesh.pattern_axis.squaredNorm() > 0.0f
                                   ? mesh.pattern_axis.normalized()
                                   : Eigen::Vector3f::UnitY();
  gl_.Uniform3f(mesh_program_.pattern_axis, axis.x(), axis.y(), axis.z());
  gl_.BindVertexArray(gpu.vao);
  gl_.DrawElements(GL_TRIANGLES, gpu.index_count, GL_UNSIGNED_INT, nullptr);
}

std::size_t SceneRenderer::upload_particles(const RenderParticles& particles,
                                           const Eigen::Matrix4f& view,
                                           const Eigen::Matrix4f& proj, int height,
                                           bool* as_points) {
  // Pack the visible particles (alpha > 0) into the instance stream, and find the largest
  // screen square any of them needs (the same estimate as the point vertex shader).
  const std::size_t n = particles.positions.size();
  const bool per_particle = particles.colors.size() == n;
  const float radius = particles.radius_m;
  const float radius_px_scale = radius * proj(1, 1) * 0.5f * static_cast<float>(height);
  const Eigen::Vector3f view_z_row = view.block<1, 3>(2, 0).transpose();
  const float view_z_offset = view(2, 3);
  instance_bytes_.resize(n * kInstanceBytes);
  std::size_t count = 0;
  float largest_point_px = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector4f& c = per_particle ? particles.colors[i] : particles.default_color;
    const Eigen::Vector3f& p = particles.positions[i];
    if (!(c.w() > 0.0f) || !p.allFinite()) continue;
    const float depth = -(view_z_row.dot(p) + view_z_offset);
    if (depth > radius) {
      const Eigen::Vector3f pv = (view * p.homogeneous()).head<3>();
      const float cos_off_axis = std::max(depth / pv.norm(), 0.3f);
      largest_point_px =
          std::max(largest_point_px, 2.0f * radius_px_scale / depth / cos_off_axis + 1.0f);
    }
    std::uint8_t* dst = &instance_bytes_[count * kInstanceBytes];
    std::memcpy(dst, p.data(), 3 * sizeof(float));
    dst[12] = to_byte(c.x());
    dst[13] = to_byte(c.y());
    dst[14] = to_byte(c.z());
    dst[15] = 255;
    ++count;
  }
  // Points when every sprite fits the point size limit, else quads (a close-up view).
  *as_points = largest_point_px <= max_point_size_px_;
  if (count == 0 || !(radius > 0.0f)) return 0;
  gl_.BindBuffer(GL_ARRAY_BUFFER, particle_instance_vbo_);
  // Orphan and refill: the GL may still read last frame's data.
  gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(count * kInstanceBytes),
                 instance_bytes_.data(), GL_STREAM_DRAW);
  gl_.BindBuffer(GL_ARRAY_BUFFER, 0);
  return count;
}

void SceneRenderer::draw_particles(float radius, std::size_t count, bool as_points,
                                   const Eigen::Matrix4f& view, const Eigen::Matrix4f& proj,
                                   int width, int height) {
  if (count == 0) return;
  const Program& program = as_points ? particle_point_program_ : particle_quad_program_;
  gl_.UseProgram(program.id);
  gl_.UniformMatrix4fv(program.view, 1, GL_FALSE, view.data());
  gl_.UniformMatrix4fv(program.proj, 1, GL_FALSE, proj.data());
  set_lighting_uniforms(program, view);
  gl_.Uniform1f(program.radius, radius);
  gl_.Uniform4f(program.viewport, 0.0f, 0.0f, static_cast<float>(width),
                static_cast<float>(height));
  if (as_points) {
    gl_.Enable(GL_PROGRAM_POINT_SIZE);
    gl_.BindVertexArray(particle_point_vao_);
    gl_.DrawArrays(GL_POINTS, 0, static_cast<GLsizei>(count));
    gl_.Disable(GL_PROGRAM_POINT_SIZE);
  } else {
    gl_.BindVertexArray(particle_quad_vao_);
    gl_.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(count));
  }
}

bool SceneRenderer::ensure_shadow_map(int size) {
  if (shadow_texture_ && shadow_map_size_ == size) return true;
  destroy_shadow_map();
  gl_.GenTextures(1, &shadow_texture_);
  gl_.BindTexture(GL_TEXTURE_2D, shadow_texture_);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT,
                 GL_UNSIGNED_INT, nullptr);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  gl_.BindTexture(GL_TEXTURE_2D, 0);
  gl_.GenFramebuffers(1, &shadow_fbo_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_texture_,
                           0);
  gl_.DrawBuffer(GL_NONE);
  gl_.ReadBuffer(GL_NONE);
  const bool complete = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!complete) {
    destroy_shadow_map();
    return false;
  }
  shadow_map_size_ = size;
  return true;
}

void SceneRenderer::destroy_shadow_map() {
  if (shadow_fbo_) gl_.DeleteFramebuffers(1, &shadow_fbo_);
  if (shadow_texture_) gl_.DeleteTextures(1, &shadow_texture_);
  shadow_fbo_ = shadow_texture_ = 0;
  shadow_map_size_ = 0;
}

void SceneRenderer::draw_shadow_map(const RenderScene& scene, const Bounds3f& bounds,
                                    const Eigen::Matrix4f& view,
                                    const std::vector<MeshDraw>& opaque,
                                    std::size_t particle_count) {
  shadow_.active = false;
  // Remember the caller's framebuffer and viewport (a window's, or a multisampled target)
  // before anything here binds another.
  GLint previous_fbo = 0;
  GLint previous_viewport[4] = {0, 0, 1, 1};
  gl_.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
  gl_.GetIntegerv(GL_VIEWPORT, previous_viewport);
  const int size = std::clamp(scene.shadows.map_size_px, 64, 8192);
  const bool ready = ensure_shadow_map(size);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));
  if (!ready) return;

  // An orthographic view along the key light, enclosing the scene's bounding sphere; the far
  // plane reaches well past it so shadows falling on the ground below are kept.
  const Eigen::Vector3f center = 0.5f * (bounds.min + bounds.max);
  const float radius = std::max(0.5f * (bounds.max - bounds.min).norm(), 1e-4f);
  const Eigen::Vector3f to_light = key_light_direction(scene.camera);
  RenderCamera light;
  light.target = center;
  light.eye = center + 2.0f * radius * to_light;
  light.up = std::abs(to_light.z()) > 0.99f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitZ();
  const float near_m = 0.5f * radius, far_m = 7.0f * radius;
  Eigen::Matrix4f ortho = Eigen::Matrix4f::Identity();
  ortho(0, 0) = 1.0f / radius;
  ortho(1, 1) = 1.0f / radius;
  ortho(2, 2) = -2.0f / (far_m - near_m);
  ortho(2, 3) = -(far_m + near_m) / (far_m - near_m);
  const Eigen::Matrix4f light_vp = ortho * view_matrix(light);

  gl_.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  gl_.Viewport(0, 0, size, size);
  // Depth writes happen only with the depth test on (a fresh context has it off).
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LESS);
  gl_.DepthMask(GL_TRUE);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Clear(GL_DEPTH_BUFFER_BIT);
  // Slope-scaled offset keeps lit faces from shadowing themselves (acne).
  gl_.Enable(GL_POLYGON_OFFSET_FILL);
  gl_.PolygonOffset(2.0f, 4.0f);
  gl_.UseProgram(shadow_mesh_program_.id);
  gl_.UniformMatrix4fv(shadow_mesh_program_.light_vp, 1, GL_FALSE, light_vp.data());
  for (const MeshDraw& d : opaque) {
    const Eigen::Matrix4f model = d.mesh->pose.matrix();
    gl_.UniformMatrix4fv(shadow_mesh_program_.model, 1, GL_FALSE, model.data());
    gl_.BindVertexArray(d.gpu->vao);
    gl_.DrawElements(GL_TRIANGLES, d.gpu->index_count, GL_UNSIGNED_INT, nullptr);
  }
  gl_.Disable(GL_POLYGON_OFFSET_FILL);
  const float pixels_per_m = 0.5f * static_cast<float>(size) / radius;
  const float particle_px = 2.0f * scene.particles.radius_m * pixels_per_m + 1.0f;
  if (scene.shadows.particles_cast && particle_count > 0 && particle_px <= max_point_size_px_) {
    gl_.UseProgram(shadow_particle_program_.id);
    gl_.UniformMatrix4fv(shadow_particle_program_.light_vp, 1, GL_FALSE, light_vp.data());
    gl_.Uniform1f(shadow_particle_program_.point_scale, pixels_per_m);
    gl_.Uniform1f(shadow_particle_program_.radius, scene.particles.radius_m);
    gl_.Uniform1f(shadow_particle_program_.depth_per_m, 1.0f / (far_m - near_m));
    gl_.Enable(GL_PROGRAM_POINT_SIZE);
    gl_.BindVertexArray(particle_point_vao_);
    gl_.DrawArrays(GL_POINTS, 0, static_cast<GLsizei>(particle_count));
    gl_.Disable(GL_PROGRAM_POINT_SIZE);
  }
  gl_.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));
  gl_.Viewport(previous_viewport[0], previous_viewport[1], previous_viewport[2],
               previous_viewport[3]);

  // Receivers look up view-space positions: view -> world -> light clip -> 0..1.
  Eigen::Matrix4f to_unit = Eigen::Matrix4f::Identity();
  to_unit.block<3, 3>(0, 0) *= 0.5f;
  to_unit.block<3, 1>(0, 3).setConstant(0.5f);
  shadow_.view_to_shadow = to_unit * light_vp * view.inverse();
  const float texel_m = 2.0f * radius / static_cast<float>(size);
  shadow_.normal_offset_m = 1.5f * texel_m;
  shadow_.depth_bias = 1.0f * texel_m / (far_m - near_m);
  shadow_.active = true;
  gl_.ActiveTexture(GL_TEXTURE0 + kShadowTextureUnit);
  gl_.BindTexture(GL_TEXTURE_2D, shadow_texture_);
  gl_.ActiveTexture(GL_TEXTURE0);
}

void SceneRenderer::draw_ground(const RenderScene& scene, const Bounds3f& scene_box,
                                const Eigen::Matrix4f& view, const Eigen::Matrix4f& proj) {
  const Bounds3f* bounds = &scene_box;
  const Eigen::Vector3f size = bounds->max - bounds->min;
  // The plane's reach follows the scene's footprint, so a tall thin part (an instrument held
  // high) does not spread the grid far beyond the work site.
  const float extent = std::max({size.x(), size.y(), 0.25f * size.z(), 1e-3f});
  // Just under the lowest point, so the plane never cuts through a floor drawn by the scene.
  const float height = std::isfinite(scene.ground.height_m)
                           ? scene.ground.height_m
                           : bounds->min.z() - 2e-3f * extent;
  const Eigen::Vector2f center = 0.5f * (bounds->min + bounds->max).head<2>();
  const float fade_radius = 2.5f * extent;
  const float corners[12] = {
      center.x() - fade_radius, center.y() - fade_radius, height,
      center.x() + fade_radius, center.y() - fade_radius, height,
      center.x() - fade_radius, center.y() + fade_radius, height,
      center.x() + fade_radius, center.y() + fade_radius, height,
  };
  gl_.UseProgram(ground_program_.id);
  gl_.UniformMatrix4fv(ground_program_.view, 1, GL_FALSE, view.data());
  gl_.UniformMatrix4fv(ground_program_.proj, 1, GL_FALSE, proj.data());
  set_lighting_uniforms(ground_program_, view);
  gl_.Uniform3f(ground_program_.ground_rgb, scene.ground.rgb.x(), scene.ground.rgb.y(),
                scene.ground.rgb.z());
  gl_.Uniform2f(ground_program_.ground_center, center.x(), center.y());
  gl_.Uniform1f(ground_program_.fade_radius, fade_radius);
  gl_.Uniform1f(ground_program_.grid_spacing, std::max(scene.ground.grid_spacing_m, 0.0f));
  gl_.BindVertexArray(ground_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, ground_vbo_);
  gl_.BufferSubData(GL_ARRAY_BUFFER, 0, sizeof(corners), corners);
  gl_.BindBuffer(GL_ARRAY_BUFFER, 0);
  // Blended against what is behind (only the background, as the ground is the lowest thing),
  // so its edge fades out; depth still written so nothing later draws through it.
  gl_.Enable(GL_BLEND);
  gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl_.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  gl_.Disable(GL_BLEND);
}

RenderStats SceneRenderer::render(const RenderScene& scene, int width, int height) {
  const auto start = std::chrono::steady_clock::now();
  RenderStats stats;
  ++frame_;
  width = std::max(width, 1);
  height = std::max(height, 1);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const Eigen::Matrix4f view = view_matrix(scene.camera);
  const Eigen::Matrix4f proj = projection_matrix(scene.camera, aspect);

  // Geometry first: every mesh on the GPU (cached or streamed), the particles packed. Streamed
  // (id 0) meshes get their slots up front, so pointers into stream_ stay valid.
  std::size_t streamed = 0;
  for (const RenderMesh& mesh : scene.meshes) streamed += mesh.geometry_id == 0 ? 1 : 0;
  if (stream_.size() < streamed) stream_.resize(streamed);
  std::size_t stream_slot = 0;
  std::vector<MeshDraw> opaque, translucent;
  for (const RenderMesh& mesh : scene.meshes) {
    const GpuMesh* gpu = gpu_mesh_for(mesh, &stream_slot);
    if (!gpu) {
      ++stats.skipped_meshes;
      continue;
    }
    if (!(mesh.rgba.w() > 0.0f)) continue;  // fully transparent: nothing to draw
    stats.triangles += gpu->index_count / 3;
    if (mesh.rgba.w() < 1.0f) {
      const Eigen::Vector3f center = mesh.pose * gpu->local_center;
      translucent.push_back({(view * center.homogeneous()).z(), &mesh, gpu});
    } else {
      opaque.push_back({0.0f, &mesh, gpu});
    }
  }
  bool as_points = true;
  const std::size_t particle_count =
      upload_particles(scene.particles, view, proj, height, &as_points);
  stats.particles = static_cast<int>(particle_count);
  stats.particles_as_points = as_points;
  const std::optional<Bounds3f> bounds = scene_bounds(scene);

  // The key light's shadow map, drawn into its own framebuffer before the frame.
  shadow_.active = false;
  if (scene.shadows.enabled && bounds) {
    draw_shadow_map(scene, *bounds, view, opaque, particle_count);
  }
  stats.shadows = shadow_.active;

  gl_.Viewport(0, 0, width, height);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_CULL_FACE);
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LESS);
  gl_.DepthMask(GL_TRUE);
  gl_.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl_.ClearColor(scene.background.x(), scene.background.y(), scene.background.z(), 1.0f);
  gl_.ClearDepth(1.0);
  gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Opaque meshes in the order given.
  gl_.UseProgram(mesh_program_.id);
  gl_.UniformMatrix4fv(mesh_program_.view, 1, GL_FALSE, view.data());
  gl_.UniformMatrix4fv(mesh_program_.proj, 1, GL_FALSE, proj.data());
  set_lighting_uniforms(mesh_program_, view);
  for (const MeshDraw& d : opaque) draw_mesh(*d.mesh, *d.gpu, view);
  stats.opaque_meshes = static_cast<int>(opaque.size());

  // Particles: opaque, depth-tested against the meshes.
  draw_particles(scene.particles.radius_m, particle_count, as_points, view, proj, width, height);

  if (scene.ground.visible && bounds) draw_ground(scene, *bounds, view, proj);

  // Translucent meshes back to front (most negative view z first), depth writes off so they
  // do not hide each other; each drawn inside-out first, then its front, so a convex zone shows
  // its far wall through its near one.
  if (!translucent.empty()) {
    std::stable_sort(translucent.begin(), translucent.end(),
                     [](const MeshDraw& a, const MeshDraw& b) { return a.view_z < b.view_z; });
    gl_.UseProgram(mesh_program_.id);
    gl_.Enable(GL_BLEND);
    gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl_.DepthMask(GL_FALSE);
    gl_.Enable(GL_CULL_FACE);
    for (const MeshDraw& d : translucent) {
      gl_.CullFace(GL_FRONT);
      draw_mesh(*d.mesh, *d.gpu, view);
      gl_.CullFace(GL_BACK);
      draw_mesh(*d.mesh, *d.gpu, view);
    }
    stats.translucent_meshes = static_cast<int>(translucent.size());
    gl_.Disable(GL_CULL_FACE);
    gl_.Disable(GL_BLEND);
    gl_.DepthMask(GL_TRUE);
  }

  if (shadow_.active) {
    gl_.ActiveTexture(GL_TEXTURE0 + kShadowTextureUnit);
    gl_.BindTexture(GL_TEXTURE_2D, 0);
    gl_.ActiveTexture(GL_TEXTURE0);
  }
  gl_.FrontFace(GL_CCW);
  gl_.BindVertexArray(0);
  gl_.UseProgram(0);
  evict_stale_geometry();
  stats.gl_error = gl_error_string(gl_, "SceneRenderer::render");
  stats.cpu_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace acdr
