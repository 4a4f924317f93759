// pm_render: meshes to a PNG, side by side, each through the same camera (render.h).
//
//   pm_render MESH [MESH...] -o OUT.png [--size W[xH]] [--columns N] [--gap PX]
//             [--view AZIMUTH,ELEVATION]... [--up x|y|z] [--zoom Z] [--frame MESH]
//             [--color checker|vertex|faces|plain] [--squares N] [--wire] [--wire-width PX]
//             [--supersampling N]
//
// Every panel is framed by the first mesh's bounding box (or --frame's), so that levels of
// detail of one mesh line up with it. One column per mesh, one row per --view.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "render.h"

namespace {

const char kUsage[] =
    "usage: pm_render MESH [MESH...] -o OUT.png [--size W[xH]] [--columns N] [--gap PX]\n"
    "                 [--view AZIMUTH,ELEVATION]... [--up x|y|z] [--zoom Z] [--frame MESH]\n"
    "                 [--color checker|vertex|faces|plain] [--squares N] [--wire]\n"
    "                 [--wire-width PX] [--supersampling N]\n"
    "Renders each mesh (OBJ, PLY, OFF, STL) with flat Lambert shading times a colour: a\n"
    "checker of its texture coordinates (default), its vertex colours, a colour per face, or\n"
    "grey; --wire draws the edges (--wire-width pixels wide). One panel per mesh and view:\n"
    "a column per mesh and a row per --view (or --columns per row), all framed by the first\n"
    "mesh's bounding box (or --frame MESH's), so that they line up. Defaults: --size 512,\n"
    "--view 30,15, --up y, --squares 32, --wire-width 1, --supersampling 3.\n";

bool read(const std::string& path, pm::Mesh& mesh) {
  if (pm::Status s = pm::read_mesh(path, mesh); !s) {
    std::cerr << "pm_render: " << path << ": " << s.message() << "\n";
    return false;
  }
  return true;
}

bool parse_number(const std::string& text, double& value) {
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(value);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> inputs;
  std::string output, frame_path;
  pm::bench::View view;
  std::vector<pm::bench::View> views;
  pm::bench::RenderOptions options;
  options.checker_squares = 32;
  int columns = 0, gap = 8;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    const bool has_value = i + 1 < argc;
    const std::string value = has_value ? argv[i + 1] : "";
    double number = 0;
    auto bad = [&]() {
      std::cerr << "pm_render: bad value for " << argument << ": " << value << "\n" << kUsage;
      return 2;
    };
    if (argument == "--help" || argument == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (argument == "-o" && has_value) {
      output = argv[++i];
    } else if (argument == "--size" && has_value) {
      ++i;
      const std::size_t x = value.find('x');
      double w = 0, h = 0;
      if (!parse_number(value.substr(0, x), w) ||
          (x != std::string::npos && !parse_number(value.substr(x + 1), h)) || w < 1 || w > 8192)
        return bad();
      options.width = int(w);
      options.height = x == std::string::npos ? int(w) : int(h);
      if (options.height < 1 || options.height > 8192) return bad();
    } else if (argument == "--columns" && has_value) {
      ++i;
      if (!parse_number(value, number) || number < 1) return bad();
      columns = int(number);
    } else if (argument == "--gap" && has_value) {
      ++i;
      if (!parse_number(value, number) || number < 0) return bad();
      gap = int(number);
    } else if (argument == "--view" && has_value) {
      ++i;
      const std::size_t comma = value.find(',');
      pm::bench::View another;
      if (comma == std::string::npos ||
          !parse_number(value.substr(0, comma), another.azimuth_deg) ||
          !parse_number(value.substr(comma + 1), another.elevation_deg))
        return bad();
      views.push_back(another);
    } else if (argument == "--up" && has_value) {
      ++i;
      if (value != "x" && value != "y" && value != "z") return bad();
      view.up_axis = value[0] - 'x';
    } else if (argument == "--zoom" && has_value) {
      ++i;
      if (!parse_number(value, view.zoom) || view.zoom <= 0) return bad();
    } else if (argument == "--frame" && has_value) {
      frame_path = argv[++i];
    } else if (argument == "--color" && has_value) {
      ++i;
      if (value == "checker")
        options.coloring = pm::bench::Coloring::kChecker;
      else if (value == "vertex")
        options.coloring = pm::bench::Coloring::kVertexColors;
      else if (value == "faces")
        options.coloring = pm::bench::Coloring::kFaceColors;
      else if (value == "plain")
        options.coloring = pm::bench::Coloring::kPlain;
      else
        return bad();
    } else if (argument == "--squares" && has_value) {
      ++i;
      if (!parse_number(value, options.checker_squares) || options.checker_squares <= 0)
        return bad();
    } else if (argument == "--supersampling" && has_value) {
      ++i;
      if (!parse_number(value, number) || number < 1 || number > 8) return bad();
      options.supersampling = int(number);
    } else if (argument == "--wire-width" && has_value) {
      ++i;
      if (!parse_number(value, options.wire_width) || options.wire_width <= 0) return bad();
      options.wireframe = true;
    } else if (argument == "--wire") {
      options.wireframe = true;
    } else if (!argument.empty() && argument[0] == '-') {
      std::cerr << "pm_render: unknown or incomplete option " << argument << "\n" << kUsage;
      return 2;
    } else {
      inputs.push_back(argument);
    }
  }
  if (inputs.empty() || output.empty()) {
    std::cerr << kUsage;
    return 2;
  }

  std::vector<pm::Mesh> meshes(inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i)
    if (!read(inputs[i], meshes[i])) return 3;
  pm::bench::Box frame = pm::bench::bounding_box(meshes[0]);
  if (!frame_path.empty()) {
    pm::Mesh framing;
    if (!read(frame_path, framing)) return 3;
    frame = pm::bench::bounding_box(framing);
  }
  // --up and --zoom apply to every view, whatever the order of the options.
  if (views.empty()) views.push_back(view);
  for (pm::bench::View& v : views) {
    v.up_axis = view.up_axis;
    v.zoom = view.zoom;
  }
  std::vector<pm::bench::Image> panels;
  for (const pm::bench::View& v : views)
    for (const pm::Mesh& mesh : meshes)
      panels.push_back(pm::bench::render_mesh(mesh, frame, v, options));
  const pm::bench::Image image =
      pm::bench::tile(panels, columns > 0 ? columns : int(meshes.size()), gap, options.background);
  std::string message;
  if (!pm::bench::write_png(output, image, &message)) {
    std::cerr << "pm_render: " << message << "\n";
    return 5;
  }
  return 0;
}
