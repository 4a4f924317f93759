// A small software renderer for looking at levels of detail: z-buffered triangles seen
// through a perspective camera, flat Lambert shading times a colour that is pluggable (a
// checker texture from the UVs, the mesh's vertex colours, or per-face / per-vertex colours
// from a callback), an optional wireframe, and PNG output. Bench-only (pm_render, the
// images of tests/bench/images/); it has no place in the library.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pm/mesh.h"

namespace pm::bench {

struct Rgb {
  float r = 0, g = 0, b = 0;  // 0..1, display values (no gamma handling)
};

// 8-bit RGB, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  Image() = default;
  Image(int w, int h, Rgb fill);
  void set(int x, int y, Rgb c);
};

struct Box {
  std::array<double, 3> lo{}, hi{};
};
// The box of the vertices used by faces (a mesh without faces: all vertices).
Box bounding_box(const pm::Mesh& mesh);

// A camera on a sphere around a box's centre, looking at it: from azimuth (around the up
// axis, 0 = looking along -front) and elevation (above the horizon), far enough that the
// box's bounding sphere fills the field of view. Meshes rendered with the same box and view
// line up, whatever their own extent.
struct View {
  double azimuth_deg = 30;
  double elevation_deg = 15;
  double field_of_view_deg = 30;  // vertical
  int up_axis = 1;                // 0 x, 1 y, 2 z: the model's up
  double zoom = 1;                // > 1 moves closer
};

enum class Coloring {
  kChecker,       // a checker of the interpolated UVs (perspective-correct), tinted by (u, v)
  kVertexColors,  // RenderOptions::vertex_color, else Mesh::colors, interpolated
  kFaceColors,    // RenderOptions::face_color, else a colour per face from its index
  kPlain,         // light grey
};

struct RenderOptions {
  int width = 512, height = 512;
  int supersampling = 3;  // samples per pixel along each axis, box-filtered
  Coloring coloring = Coloring::kChecker;
  double checker_squares = 16;  // squares per UV unit
  bool wireframe = false;
  Rgb wire_color = {0.1f, 0.1f, 0.1f};
  double wire_width = 1.0;  // pixels
  Rgb background = {1, 1, 1};
  // Pluggable colours (issue 7 colours a view-dependent LOD by level): when set, they
  // replace the mesh's own colours for kFaceColors and kVertexColors.
  std::function<Rgb(std::size_t face)> face_color;
  std::function<Rgb(uint32_t vertex)> vertex_color;
};

// Renders the mesh framed by `frame` (usually its own bounding_box). Faces without UVs are
// grey in checker mode. Degenerate and behind-the-camera faces are skipped.
Image render_mesh(const pm::Mesh& mesh, const Box& frame, const View& view,
                  const RenderOptions& options);

// Images side by side in rows of `columns` (all of the first image's size), separated by
// `gap` pixels of `background`.
Image tile(const std::vector<Image>& images, int columns, int gap, Rgb background);

// PNG (ISO/IEC 15948): 8-bit RGB, each row with the filter (None, Sub, Up, Average, Paeth)
// that minimizes the sum of absolute differences (the heuristic of the PNG specification,
// §12.8), deflated by zlib. Returns false with a message when the file cannot be written.
bool write_png(const std::string& path, const Image& image, std::string* message);

}  // namespace pm::bench
