// The bench's software renderer; see render.h. Triangles are rasterized with edge functions
// (Pineda 1988, "A parallel algorithm for polygon rasterization") into a supersampled
// colour and depth buffer; attributes are interpolated perspective-correctly by weighting
// the screen-space barycentrics with 1/z (Heckbert and Moreton 1991, "Interpolation for
// polygon texture mapping and shading"); the depth test keeps the largest 1/z, which is
// linear in screen space.
#include "render.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

namespace pm::bench {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec add_scaled(const Vec& a, const Vec& b, double s) {
  return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}
double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec normalized(const Vec& a) {
  const double length = std::sqrt(dot(a, a));
  return length > 0 ? Vec{a[0] / length, a[1] / length, a[2] / length} : a;
}
Vec position(const pm::Mesh& mesh, uint32_t v) {
  const float* p = &mesh.positions[3 * std::size_t(v)];
  return {p[0], p[1], p[2]};
}

double fraction(double x) {
  return x - std::floor(x);
}

// A UV test pattern: squares alternating light and dark, the whole tinted by where in the
// texture they are (red grows with u, green with v), so that a square in the wrong place,
// or a chart torn from its neighbour, shows as a jump in the pattern or in the tint.
Rgb checker(double u, double v, double squares) {
  const bool light = (int64_t(std::floor(u * squares)) + int64_t(std::floor(v * squares))) % 2 == 0;
  const double fu = fraction(u), fv = fraction(v);
  const Rgb tint = {float(0.35 + 0.65 * fu), float(0.35 + 0.65 * fv), float(0.85 - 0.3 * fu)};
  const float k = light ? 1.0f : 0.4f;
  return {k * tint.r, k * tint.g, k * tint.b};
}

// A colour per index, well spread in hue (the golden-ratio sequence), for telling faces apart.
Rgb index_color(std::size_t index) {
  const double hue = fraction(0.618033988749895 * double(index) + 0.1) * 6;
  const double x = 1 - std::fabs(std::fmod(hue, 2.0) - 1);
  const double c[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
  const double* rgb = c[std::min(5, int(hue))];
  return {float(0.35 + 0.55 * rgb[0]), float(0.35 + 0.55 * rgb[1]), float(0.35 + 0.55 * rgb[2])};
}

struct Camera {
  Vec eye, right, up, forward;
  double focal = 1, aspect = 1;
};

Camera make_camera(const Box& frame, const View& view, double aspect) {
  const Vec centre = {(frame.lo[0] + frame.hi[0]) / 2, (frame.lo[1] + frame.hi[1]) / 2,
                      (frame.lo[2] + frame.hi[2]) / 2};
  const double radius =
      std::max(1e-12, std::sqrt(dot(sub(frame.hi, centre), sub(frame.hi, centre))));
  // The model's up axis, a front and a right axis around it.
  const int k = std::clamp(view.up_axis, 0, 2);
  Vec up_axis{}, front{}, side{};
  up_axis[k] = 1;
  front[k == 2 ? 1 : 2] = k == 2 ? -1 : 1;  // y up: +z is the front; z up: -y
  side = cross(up_axis, front);
  const double azimuth = view.azimuth_deg * M_PI / 180, elevation = view.elevation_deg * M_PI / 180;
  Vec to_eye{};
  for (int axis = 0; axis < 3; ++axis)
    to_eye[axis] =
        std::cos(elevation) * (std::cos(azimuth) * front[axis] + std::sin(azimuth) * side[axis]) +
        std::sin(elevation) * up_axis[axis];
  const double half_fov = view.field_of_view_deg * M_PI / 360;
  // The bounding sphere fits the smaller of the two fields of view.
  const double fit = std::min(std::tan(half_fov), std::tan(half_fov) * aspect);
  const double distance = radius / std::sin(std::atan(fit)) / std::max(1e-6, view.zoom);
  Camera camera;
  camera.eye = add_scaled(centre, to_eye, distance);
  camera.forward = normalized(sub(centre, camera.eye));
  camera.right = normalized(cross(camera.forward, up_axis));
  if (dot(camera.right, camera.right) == 0) camera.right = side;  // looking straight down
  camera.up = cross(camera.right, camera.forward);
  camera.focal = 1 / std::tan(half_fov);
  camera.aspect = aspect;
  return camera;
}

}  // namespace

Image::Image(int w, int h, Rgb fill) : width(w), height(h), rgb(std::size_t(w) * h * 3) {
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) set(x, y, fill);
}

void Image::set(int x, int y, Rgb c) {
  uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
  p[0] = uint8_t(std::lround(std::clamp(c.r, 0.0f, 1.0f) * 255));
  p[1] = uint8_t(std::lround(std::clamp(c.g, 0.0f, 1.0f) * 255));
  p[2] = uint8_t(std::lround(std::clamp(c.b, 0.0f, 1.0f) * 255));
}

Box bounding_box(const pm::Mesh& mesh) {
  Box box;
  box.lo.fill(std::numeric_limits<double>::infinity());
  box.hi.fill(-std::numeric_limits<double>::infinity());
  auto include = [&](uint32_t v) {
    for (int axis = 0; axis < 3; ++axis) {
      box.lo[axis] = std::min(box.lo[axis], double(mesh.positions[3 * std::size_t(v) + axis]));
      box.hi[axis] = std::max(box.hi[axis], double(mesh.positions[3 * std::size_t(v) + axis]));
    }
  };
  if (mesh.face_count() > 0)
    for (uint32_t v : mesh.triangles) include(v);
  else
    for (uint32_t v = 0; v < mesh.vertex_count(); ++v) include(v);
  if (!(box.lo[0] <= box.hi[0])) box = Box{};
  return box;
}

Image render_mesh(const pm::Mesh& mesh, const Box& frame, const View& view,
                  const RenderOptions& options) {
  const int s = std::max(1, options.supersampling);
  const int width = options.width * s, height = options.height * s;
  const Camera camera = make_camera(frame, view, double(options.width) / options.height);
  std::vector<Rgb> color(std::size_t(width) * height, options.background);
  std::vector<double> depth(std::size_t(width) * height, 0);  // 1/z; 0 is infinitely far
  // Light from above the camera's left shoulder; two-sided, so back faces are lit too.
  const Vec light = normalized(
      add_scaled(add_scaled(Vec{-camera.forward[0], -camera.forward[1], -camera.forward[2]},
                            camera.right, -0.45),
                 camera.up, 0.6));
  const double near = 1e-9 * std::sqrt(dot(sub(frame.hi, frame.lo), sub(frame.hi, frame.lo)));
  const double wire = 0.5 * options.wire_width * s;

  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* corners = &mesh.triangles[3 * f];
    Vec world[3];
    double sx[3], sy[3], inverse_z[3];
    bool behind = false;
    for (int c = 0; c < 3; ++c) {
      world[c] = position(mesh, corners[c]);
      const Vec d = sub(world[c], camera.eye);
      const double z = dot(d, camera.forward);
      if (z <= near) behind = true;
      inverse_z[c] = 1 / z;
      sx[c] = (1 + camera.focal * dot(d, camera.right) * inverse_z[c] / camera.aspect) / 2 * width;
      sy[c] = (1 - camera.focal * dot(d, camera.up) * inverse_z[c]) / 2 * height;
    }
    if (behind) continue;  // the camera is outside the frame's sphere: only stray geometry
    const double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
    if (std::fabs(area) < 1e-12) continue;
    const Vec normal = normalized(cross(sub(world[1], world[0]), sub(world[2], world[0])));
    const float shade = float(0.3 + 0.7 * std::fabs(dot(normal, light)));

    // What is interpolated: UVs (checker) or colours (vertex colours), per corner.
    std::array<std::array<double, 3>, 3> attribute{};
    bool has_attribute = false;
    Rgb flat = {0.8f, 0.8f, 0.8f};
    switch (options.coloring) {
      case Coloring::kChecker:
        if (mesh.has_uvs()) {
          has_attribute = true;
          for (int c = 0; c < 3; ++c) {
            const uint32_t id = mesh.uv_indices[3 * f + c];
            if (id == pm::kNoAttribute)
              has_attribute = false;
            else
              attribute[c] = {mesh.uvs[2 * std::size_t(id)], mesh.uvs[2 * std::size_t(id) + 1], 0};
          }
        }
        break;
      case Coloring::kVertexColors:
        if (options.vertex_color || mesh.has_colors()) {
          has_attribute = true;
          for (int c = 0; c < 3; ++c) {
            if (options.vertex_color) {
              const Rgb rgb = options.vertex_color(corners[c]);
              attribute[c] = {rgb.r, rgb.g, rgb.b};
            } else {
              const float* rgb = &mesh.colors[std::size_t(corners[c]) * mesh.color_components];
              attribute[c] = {rgb[0], rgb[1], rgb[2]};
            }
          }
        }
        break;
      case Coloring::kFaceColors:
        flat = options.face_color ? options.face_color(f) : index_color(f);
        break;
      case Coloring::kPlain:
        break;
    }
    const double edge_length[3] = {std::hypot(sx[2] - sx[1], sy[2] - sy[1]),
                                   std::hypot(sx[0] - sx[2], sy[0] - sy[2]),
                                   std::hypot(sx[1] - sx[0], sy[1] - sy[0])};

    const int x0 = std::max(0, int(std::floor(std::min({sx[0], sx[1], sx[2]}))));
    const int x1 = std::min(width - 1, int(std::ceil(std::max({sx[0], sx[1], sx[2]}))));
    const int y0 = std::max(0, int(std::floor(std::min({sy[0], sy[1], sy[2]}))));
    const int y1 = std::min(height - 1, int(std::ceil(std::max({sy[0], sy[1], sy[2]}))));
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5;
        // Edge functions: twice the signed areas of the sub-triangles opposite each corner.
        const double e[3] = {(sx[2] - sx[1]) * (py - sy[1]) - (sy[2] - sy[1]) * (px - sx[1]),
                             (sx[0] - sx[2]) * (py - sy[2]) - (sy[0] - sy[2]) * (px - sx[2]),
                             (sx[1] - sx[0]) * (py - sy[0]) - (sy[1] - sy[0]) * (px - sx[0])};
        const double b[3] = {e[0] / area, e[1] / area, e[2] / area};
        if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
        const double z = b[0] * inverse_z[0] + b[1] * inverse_z[1] + b[2] * inverse_z[2];
        const std::size_t pixel = std::size_t(y) * width + x;
        if (z <= depth[pixel]) continue;
        depth[pixel] = z;
        Rgb base = flat;
        if (has_attribute) {
          // Perspective-correct weights: the screen-space ones times 1/z, renormalized.
          double value[3] = {0, 0, 0};
          for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 3; ++i) value[i] += b[c] * inverse_z[c] / z * attribute[c][i];
          base = options.coloring == Coloring::kChecker
                     ? checker(value[0], value[1], options.checker_squares)
                     : Rgb{float(value[0]), float(value[1]), float(value[2])};
        }
        Rgb out = {base.r * shade, base.g * shade, base.b * shade};
        if (options.wireframe) {
          double nearest_edge = std::numeric_limits<double>::infinity();
          for (int c = 0; c < 3; ++c)
            if (edge_length[c] > 0)
              nearest_edge = std::min(nearest_edge, std::fabs(e[c]) / edge_length[c]);
          if (nearest_edge < wire) out = options.wire_color;
        }
        color[pixel] = out;
      }
    }
  }

  // Box filter down to the output size.
  Image image(options.width, options.height, options.background);
  const float weight = 1.0f / float(s * s);
  for (int y = 0; y < options.height; ++y) {
    for (int x = 0; x < options.width; ++x) {
      Rgb sum;
      for (int dy = 0; dy < s; ++dy)
        for (int dx = 0; dx < s; ++dx) {
          const Rgb& c = color[std::size_t(y * s + dy) * width + (x * s + dx)];
          sum.r += c.r;
          sum.g += c.g;
          sum.b += c.b;
        }
      image.set(x, y, {sum.r * weight, sum.g * weight, sum.b * weight});
    }
  }
  return image;
}

Image tile(const std::vector<Image>& images, int columns, int gap, Rgb background) {
  if (images.empty()) return Image();
  columns = std::max(1, std::min(columns, int(images.size())));
  const int rows = (int(images.size()) + columns - 1) / columns;
  const int w = images[0].width, h = images[0].height;
  Image out(columns * w + (columns - 1) * gap, rows * h + (rows - 1) * gap, background);
  for (std::size_t i = 0; i < images.size(); ++i) {
    const int ox = int(i) % columns * (w + gap), oy = int(i) / columns * (h + gap);
    for (int y = 0; y < std::min(h, images[i].height); ++y)
      std::memcpy(&out.rgb[3 * (std::size_t(oy + y) * out.width + ox)],
                  &images[i].rgb[3 * std::size_t(y) * images[i].width],
                  3 * std::size_t(std::min(w, images[i].width)));
  }
  return out;
}

namespace {

void put_u32(std::string& out, uint32_t x) {
  for (int shift = 24; shift >= 0; shift -= 8) out += char((x >> shift) & 0xFF);
}

void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32(out, uint32_t(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  put_u32(out, uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
}

uint8_t paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return uint8_t(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

}  // namespace

bool write_png(const std::string& path, const Image& image, std::string* message) {
  const std::size_t stride = 3 * std::size_t(image.width);
  std::vector<uint8_t> filtered;
  filtered.reserve((stride + 1) * image.height);
  std::vector<uint8_t> zero(stride, 0), candidate(stride), best(stride);
  for (int y = 0; y < image.height; ++y) {
    const uint8_t* row = &image.rgb[y * stride];
    const uint8_t* above = y > 0 ? &image.rgb[(y - 1) * stride] : zero.data();
    long best_cost = -1;
    uint8_t best_type = 0;
    for (uint8_t type = 0; type < 5; ++type) {
      long cost = 0;
      for (std::size_t i = 0; i < stride; ++i) {
        const int a = i >= 3 ? row[i - 3] : 0, b = above[i], c = i >= 3 ? above[i - 3] : 0;
        const int predictor = type == 0   ? 0
                              : type == 1 ? a
                              : type == 2 ? b
                              : type == 3 ? (a + b) / 2
                                          : paeth(a, b, c);
        candidate[i] = uint8_t(row[i] - predictor);
        cost += std::abs(int(int8_t(candidate[i])));
      }
      if (best_cost < 0 || cost < best_cost) {
        best_cost = cost;
        best_type = type;
        best.swap(candidate);
      }
    }
    filtered.push_back(best_type);
    filtered.insert(filtered.end(), best.begin(), best.end());
  }
  uLongf compressed_size = compressBound(uLong(filtered.size()));
  std::string compressed(compressed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(compressed.data()), &compressed_size, filtered.data(),
                uLong(filtered.size()), 9) != Z_OK) {
    if (message) *message = "zlib could not compress the image";
    return false;
  }
  compressed.resize(compressed_size);

  std::string png = "\x89PNG\r\n\x1a\n";
  std::string header;
  put_u32(header, uint32_t(image.width));
  put_u32(header, uint32_t(image.height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, filters, no interlace
  put_chunk(png, "IHDR", header);
  put_chunk(png, "IDAT", compressed);
  put_chunk(png, "IEND", "");
  std::ofstream out(path, std::ios::binary);
  out << png;
  if (!out) {
    if (message) *message = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace pm::bench
