// Draws a RenderScene with OpenGL 3.3 core through a GlFunctions table: lit meshes (opaque,
// then translucent back to front), particles as ray-cast sphere impostors, a ground grid.
// It owns its GL objects but not the context: the same renderer serves an OSMesa buffer and
// a GLFW window. No globals; one renderer per context, used on the thread where that context
// is current.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "ui/gl_functions.hpp"
#include "ui/render_camera.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

/// What one render() call did.
struct RenderStats {
  int opaque_meshes = 0;       ///< meshes drawn opaque
  int translucent_meshes = 0;  ///< meshes drawn blended
  int skipped_meshes = 0;      ///< meshes with no valid triangle (bad indices, empty)
  int particles = 0;           ///< particles drawn (hidden ones excluded)
  bool particles_as_points = false;  ///< point sprites (true) or instanced quads (close-ups)
  bool shadows = false;        ///< the key light's shadow map was drawn and applied
  int triangles = 0;           ///< mesh triangles submitted (both translucent passes count once)
  double cpu_ms = 0.0;         ///< wall time spent in render() on the CPU (GPU may still run)
  std::string gl_error;        ///< non-empty when the GL reported an error during the frame
};

/// Unit direction towards the key light in world coordinates for a camera: the light rides
/// with the camera (upper left, in front), so shadows fall down and to the right in the view.
Eigen::Vector3f key_light_direction(const RenderCamera& camera);

class SceneRenderer {
 public:
  /// Compiles the shaders and creates the buffers. `gl` must be loaded and its context current.
  /// Returns null and an error (the shader log) on failure.
  static std::unique_ptr<SceneRenderer> create(const GlFunctions& gl, std::string* error);

  /// Deletes the GL objects; the context that created them must be current.
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// Draws `scene` into the currently bound framebuffer over the viewport (0, 0, width, height)
  /// in pixels, clearing colour and depth first. Leaves blending and culling off, depth writes
  /// on, no program or vertex array bound, so an overlay (ImGui) can follow.
  RenderStats render(const RenderScene& scene, int width, int height);

  /// Frees the uploaded copy of one cached mesh (RenderMesh::geometry_id), or of all of them.
  void forget_geometry(std::uint64_t geometry_id);
  void clear_geometry_cache();

  /// Number of meshes whose geometry is currently kept on the GPU.
  std::size_t cached_geometry_count() const { return cache_.size(); }

  /// Cached meshes not drawn for this many frames are freed (default 600, ~10 s at 60 Hz).
  void set_cache_lifetime_frames(int frames) { cache_lifetime_frames_ = frames; }

 private:
  struct Program {
    GLuint id = 0;
    GLint model = -1, view = -1, proj = -1, normal_matrix = -1, rgba = -1, specular = -1;
    GLint key_dir = -1, fill_dir = -1, up_dir = -1, radius = -1;
    GLint ground_center = -1, ground_extent = -1, ground_rgb = -1, grid_spacing = -1;
    GLint fade_radius = -1, viewport = -1;
    GLint shadow_map = -1, view_to_shadow = -1, shadow_on = -1, shadow_offset = -1;
    GLint shadow_bias = -1, light_vp = -1, point_scale = -1, depth_per_m = -1;
    GLint finish = -1, pattern_origin = -1, pattern_axis = -1;
  };
  struct GpuMesh {
    GLuint vao = 0, vbo = 0, ebo = 0;
    GLsizei index_count = 0;
    Eigen::Vector3f local_center = Eigen::Vector3f::Zero();  ///< centre of the local bounds
    std::uint64_t last_frame = 0;
  };

  // A mesh ready to draw this frame, with its depth in view space (for sorting translucent).
  struct MeshDraw {
    float view_z;
    const RenderMesh* mesh;
    const GpuMesh* gpu;
  };
  // The shadow map's state for the frame being drawn.
  struct ShadowState {
    bool active = false;
    Eigen::Matrix4f view_to_shadow = Eigen::Matrix4f::Identity();
    float normal_offset_m = 0.0f;
    float depth_bias = 0.0f;
  };

  explicit SceneRenderer(const GlFunctions& gl) : gl_(gl) {}
  bool init(std::string* error);
  bool build_program(Program& program, const char* vertex_src, const char* fragment_src,
                     const char* name, std::string* error, const char* fragment_prelude = "");
  void destroy_mesh(GpuMesh& mesh);
  // Uploads `mesh` (normals computed when absent) into `gpu`; false when nothing is drawable.
  bool upload_mesh(const RenderMesh& mesh, GpuMesh& gpu);
  // The GPU copy of `mesh`: from the cache when it has a geometry id, else a per-frame slot.
  GpuMesh* gpu_mesh_for(const RenderMesh& mesh, std::size_t* stream_slot);
  void set_lighting_uniforms(const Program& program, const Eigen::Matrix4f& view);
  void draw_mesh(const RenderMesh& mesh, const GpuMesh& gpu, const Eigen::Matrix4f& view);
  // Packs the visible particles into the instance buffer; returns how many, and whether they
  // fit as point sprites.
  std::size_t upload_particles(const RenderParticles& particles, const Eigen::Matrix4f& view,
                               const Eigen::Matrix4f& proj, int height, bool* as_points);
  void draw_particles(float radius, std::size_t count, bool as_points,
                      const Eigen::Matrix4f& view, const Eigen::Matrix4f& proj, int width,
                      int height);
  void draw_ground(const RenderScene& scene, const Bounds3f& bounds, const Eigen::Matrix4f& view,
                   const Eigen::Matrix4f& proj);
  bool ensure_shadow_map(int size);
  void destroy_shadow_map();
  void draw_shadow_map(const RenderScene& scene, const Bounds3f& bounds,
                       const Eigen::Matrix4f& view, const std::vector<MeshDraw>& opaque,
                       std::size_t particle_count);
  void evict_stale_geometry();

  GlFunctions gl_;
  Program mesh_program_;
  Program particle_point_program_;
  Program particle_quad_program_;
  Program ground_program_;
  Program shadow_mesh_program_;
  Program shadow_particle_program_;
  GLuint shadow_fbo_ = 0, shadow_texture_ = 0;
  int shadow_map_size_ = 0;
  ShadowState shadow_;
  std::unordered_map<std::uint64_t, GpuMesh> cache_;  ///< by RenderMesh::geometry_id
  std::vector<GpuMesh> stream_;                        ///< reused slots for id-0 meshes
  GLuint particle_point_vao_ = 0, particle_quad_vao_ = 0;
  GLuint particle_corner_vbo_ = 0, particle_instance_vbo_ = 0;
  float max_point_size_px_ = 1.0f;  ///< the implementation's largest point sprite
  GLuint ground_vao_ = 0, ground_vbo_ = 0;
  std::vector<std::uint8_t> instance_bytes_;  ///< scratch: packed particle instances
  std::uint64_t frame_ = 0;
  int cache_lifetime_frames_ = 600;
};

}  // namespace acdr
