// pm_view_picture: a picture of a view-dependent level of detail (issue 7; Hoppe 1997,
// "View-dependent refinement of progressive meshes"), coloured by level, so that a person can
// see the detail fall off away from the camera and outside its view.
//
//   pm_view_picture FILE.pm --eye X,Y,Z --target X,Y,Z [--fov DEG] [--height PX]
//                   [--pixel-error P] [--up x|y|z] [--no-culling] [--wire] -o OUT.png
//                   [--size PX] [--views AZ:EL[,AZ:EL...]] [--mark-eye]
//
// --no-culling turns off frustum and back-face culling, so that only the distance to the eye
// (the screen-space error) sets the detail.
//
// The mesh pm::SelectiveRefinement::set_view() gives for that camera is rendered (render.h)
// from three overview cameras around the model (not through the LOD's own camera, which would
// hide the falloff), each face coloured by its level: blue for base-mesh faces, through green,
// to red for the deepest (the depth in the vertex hierarchy of the last split that made or
// changed the face, stretched between the shallowest and deepest such depth in the mesh), with
// the edges drawn under --wire. --views sets the overviews (azimuth:elevation in degrees
// around the up axis; 89 looks straight down on a height field); --mark-eye adds a black
// arrow at the eye, pointing where it looks.
// The counts on stderr.
#include <OpenMesh/Core/Geometry/VectorT.hh>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "pm/pm_codec.h"
#include "pm/selective_refinement.h"
#include "render.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: pm_view_picture FILE.pm --eye X,Y,Z --target X,Y,Z [--fov DEG] [--height PX]\n"
               "                       [--pixel-error P] [--up x|y|z] [--no-culling] [--wire] -o OUT.png\n"
               "                       [--size PX] [--views AZ:EL[,AZ:EL...]] [--mark-eye]\n");
  return 2;
}

bool parse_point(const std::string& text, pm::Point3& p) {
  return std::sscanf(text.c_str(), "%lf,%lf,%lf", &p[0], &p[1], &p[2]) == 3;
}

// Blue (coarse) to green to red (fine).
pm::bench::Rgb level_color(double t) {
  t = std::fmin(1, std::fmax(0, t));
  if (t < 0.5) return {0.15f, float(0.3 + 1.2 * t), float(1 - 1.4 * t)};
  return {float(2 * (t - 0.5) * 0.85 + 0.15), float(0.9 - 1.4 * (t - 0.5)), 0.3f};
}

// A flat arrow at the eye, along the view direction, 4% of the box's diagonal long: two
// triangles (both windings, so that it shows from either side), appended to `mesh`. Faces
// are coloured by level alone, so the attributes (per vertex or corner) are dropped rather
// than extended to the arrow.
void add_eye_arrow(const pm::ViewCamera& camera, const pm::bench::Box& box, pm::Mesh& mesh) {
  using Vec = OpenMesh::Vec3d;
  const Vec eye(camera.eye[0], camera.eye[1], camera.eye[2]);
  const Vec forward = (Vec(camera.target[0], camera.target[1], camera.target[2]) - eye).normalize();
  Vec side = forward % Vec(camera.up[0], camera.up[1], camera.up[2]);
  if (side.norm() > 0) side.normalize();
  const double scale =
      0.04 * (Vec(box.hi[0], box.hi[1], box.hi[2]) - Vec(box.lo[0], box.lo[1], box.lo[2])).norm();
  pm::Mesh shown;
  shown.positions = std::move(mesh.positions);
  shown.triangles = std::move(mesh.triangles);
  mesh = std::move(shown);
  const auto first = static_cast<uint32_t>(mesh.vertex_count());
  for (const Vec& corner : {eye + scale * forward, eye + scale * (-0.3 * forward + 0.5 * side),
                            eye + scale * (-0.3 * forward - 0.5 * side)})
    for (int i = 0; i < 3; ++i) mesh.positions.push_back(static_cast<float>(corner[i]));
  for (uint32_t v : {0u, 1u, 2u, 0u, 2u, 1u}) mesh.triangles.push_back(first + v);
}

}  // namespace

int main(int argc, char** argv) {
  std::string input, output;
  pm::ViewCamera camera;
  pm::ViewOptions options;
  int up_axis = 1, size = 512;
  bool has_eye = false, has_target = false, wire = false, mark_eye = false;
  std::vector<std::pair<double, double>> views = {{0, 20}, {90, 20}, {200, 20}};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool more = i + 1 < argc;
    if (arg == "--eye" && more) {
      has_eye = parse_point(argv[++i], camera.eye);
      if (!has_eye) return usage();
    } else if (arg == "--target" && more) {
      has_target = parse_point(argv[++i], camera.target);
      if (!has_target) return usage();
    } else if (arg == "--fov" && more) {
      camera.fov_degrees = std::atof(argv[++i]);
    } else if (arg == "--height" && more) {
      camera.viewport_height = std::atof(argv[++i]);
    } else if (arg == "--pixel-error" && more) {
      options.pixel_error = std::atof(argv[++i]);
    } else if (arg == "--up" && more) {
      const std::string axis = argv[++i];
      if (axis != "x" && axis != "y" && axis != "z") return usage();
      up_axis = axis[0] - 'x';
    } else if (arg == "--size" && more) {
      size = std::atoi(argv[++i]);
    } else if (arg == "--no-culling") {
      options.frustum_culling = options.backface_culling = false;
    } else if (arg == "--wire") {
      wire = true;
    } else if (arg == "--mark-eye") {
      mark_eye = true;
    } else if (arg == "--views" && more) {
      views.clear();
      const std::string list = argv[++i];
      for (std::size_t at = 0; at < list.size();) {
        std::size_t end = list.find(',', at);
        if (end == std::string::npos) end = list.size();
        double azimuth = 0, elevation = 0;
        if (std::sscanf(list.substr(at, end - at).c_str(), "%lf:%lf", &azimuth, &elevation) != 2)
          return usage();
        views.emplace_back(azimuth, elevation);
        at = end + 1;
      }
      if (views.empty()) return usage();
    } else if (arg == "-o" && more) {
      output = argv[++i];
    } else if (!arg.empty() && arg[0] != '-' && input.empty()) {
      input = arg;
    } else {
      return usage();
    }
  }
  if (input.empty() || output.empty() || !has_eye || !has_target || size < 16) return usage();
  camera.up = {0, 0, 0};
  camera.up[up_axis] = 1;

  std::ifstream file(input, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  pm::ProgressiveMesh pm;
  if (pm::Status s = pm::read_pm(bytes, pm); !s) {
    std::fprintf(stderr, "pm_view_picture: %s: %s\n", input.c_str(), s.message().c_str());
    return 3;
  }
  pm::SelectiveRefinement refinement(pm);
  if (pm::Status s = refinement.set_view(camera, options); !s) {
    std::fprintf(stderr, "pm_view_picture: %s\n", s.message().c_str());
    return 2;
  }
  std::vector<uint32_t> levels;
  pm::Mesh mesh = refinement.to_mesh(&levels);
  const std::size_t lod_faces = mesh.face_count();
  std::fprintf(stderr, "%s: %zu of %zu splits applied, %zu faces (full detail %zu)\n", input.c_str(),
               refinement.applied_count(), refinement.split_count(), lod_faces,
               pm.total_face_count());

  pm::bench::RenderOptions render;
  render.width = render.height = size;
  render.coloring = pm::bench::Coloring::kFaceColors;
  render.wireframe = wire;
  render.wire_width = 0.4;
  render.wire_color = {0.1f, 0.1f, 0.1f};
  // The level of a face: the depth, in the vertex hierarchy, of the last split that made or
  // changed it (0: a base face), over the deepest applied split's depth. Depth rather than the
  // split's index: the index orders splits over the whole model, the depth says how many times
  // this neighbourhood was refined.
  std::vector<uint32_t> depth(refinement.split_count(), 0);
  uint32_t deepest = 1;
  for (std::size_t j = 0; j < depth.size(); ++j) {
    const uint32_t p = refinement.parent(j);
    depth[j] = p == pm::kNoSplit ? 1 : depth[p] + 1;  // parents come first
    if (refinement.applied(j)) deepest = std::max(deepest, depth[j]);
  }
  // Stretched over the depths the mesh's faces have, so that the colours span blue to red.
  uint32_t shallowest = deepest;
  for (uint32_t level : levels)
    if (level > 0) shallowest = std::min(shallowest, depth[level - 1]);
  const double span = std::max<double>(1, deepest - shallowest);
  if (mark_eye) add_eye_arrow(camera, pm::bench::bounding_box(mesh), mesh);
  render.face_color = [&](std::size_t face) -> pm::bench::Rgb {
    if (face >= lod_faces) return {0, 0, 0};  // the eye's arrow
    return level_color(levels[face] == 0 ? 0.0 : (depth[levels[face] - 1] - shallowest) / span);
  };
  // The overviews: the model framed by its own box from three sides.
  const pm::bench::Box frame = pm::bench::bounding_box(mesh);
  std::vector<pm::bench::Image> panels;
  for (const auto& [azimuth, elevation] : views) {
    pm::bench::View view;
    view.azimuth_deg = azimuth;
    view.elevation_deg = elevation;
    view.up_axis = up_axis;
    panels.push_back(pm::bench::render_mesh(mesh, frame, view, render));
  }
  const pm::bench::Image image =
      pm::bench::tile(panels, static_cast<int>(panels.size()), 8, render.background);
  std::string message;
  if (!pm::bench::write_png(output, image, &message)) {
    std::fprintf(stderr, "pm_view_picture: %s\n", message.c_str());
    return 5;
  }
  return 0;
}
