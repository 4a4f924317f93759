// pmdec --view, --region, --viewpoint: one selectively refined mesh instead of a level
// (Hoppe 1997, "View-dependent refinement of progressive meshes"; pm/selective_refinement.h).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "pmdec/pmdec.h"

namespace pmdec {

// Comma-separated finite numbers, exactly `count` of them.
bool parse_numbers(const std::string& text, std::size_t count, std::vector<double>& values) {
  values.clear();
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, comma - begin);
    try {
      std::size_t used = 0;
      const double value = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(value)) return false;
      values.push_back(value);
    } catch (const std::exception&) {
      return false;
    }
    if (comma == text.size()) break;
    begin = comma + 1;
  }
  return values.size() == count;
}

// eye=X,Y,Z,target=X,Y,Z[,up=X,Y,Z],fov=DEG,height=PX[,width=PX]: keys in any order.
bool parse_view(const std::string& text, pm::ViewCamera& camera, std::string& problem) {
  const char* keys[] = {"eye=", "target=", "up=", "fov=", "height=", "width="};
  // The positions of the keys split the text; each key's value runs to the next key.
  std::vector<std::pair<std::size_t, int>> found;
  for (int k = 0; k < 6; ++k)
    for (std::size_t at = text.find(keys[k]); at != std::string::npos;
         at = text.find(keys[k], at + 1))
      if (at == 0 || text[at - 1] == ',') found.push_back({at, k});
  std::sort(found.begin(), found.end());
  if (found.empty() || found[0].first != 0) {
    problem = "expected eye=X,Y,Z,target=X,Y,Z[,up=X,Y,Z],fov=DEG,height=PX[,width=PX]";
    return false;
  }
  bool seen[6] = {};
  for (std::size_t i = 0; i < found.size(); ++i) {
    const int k = found[i].second;
    const std::size_t begin = found[i].first + std::strlen(keys[k]);
    const std::size_t end = i + 1 < found.size() ? found[i + 1].first - 1 : text.size();
    const std::string value = begin <= end ? text.substr(begin, end - begin) : "";
    const std::string name(keys[k], std::strlen(keys[k]) - 1);
    if (seen[k]) {
      problem = name + " given twice";
      return false;
    }
    seen[k] = true;
    std::vector<double> numbers;
    if (!parse_numbers(value, k < 3 ? 3 : 1, numbers)) {
      problem = name + "=" + value + ": expected " + (k < 3 ? "three numbers X,Y,Z" : "a number");
      return false;
    }
    pm::Point3* points[] = {&camera.eye, &camera.target, &camera.up};
    if (k < 3) *points[k] = {numbers[0], numbers[1], numbers[2]};
    if (k == 3) camera.fov_degrees = numbers[0];
    if (k == 4) camera.viewport_height = numbers[0];
    if (k == 5) camera.viewport_width = numbers[0];
  }
  for (int k : {0, 1, 3, 4})
    if (!seen[k]) {
      problem = std::string("missing ") + std::string(keys[k], std::strlen(keys[k]) - 1);
      return false;
    }
  if (pm::Status s = pm::check_camera(camera); !s) {
    problem = s.message();
    return false;
  }
  return true;
}

// sphere:X,Y,Z,R or box:X0,Y0,Z0,X1,Y1,Z1.
bool parse_region(const std::string& text, SelectiveRequest& request) {
  std::vector<double> v;
  if (text.rfind("sphere:", 0) == 0 && parse_numbers(text.substr(7), 4, v) && v[3] >= 0) {
    request.kind = SelectiveRequest::Kind::kSphere;
    request.a = {v[0], v[1], v[2]};
    request.radius = v[3];
    return true;
  }
  if (text.rfind("box:", 0) == 0 && parse_numbers(text.substr(4), 6, v) && v[0] <= v[3] &&
      v[1] <= v[4] && v[2] <= v[5]) {
    request.kind = SelectiveRequest::Kind::kBox;
    request.a = {v[0], v[1], v[2]};
    request.b = {v[3], v[4], v[5]};
    return true;
  }
  return false;
}

pm::Status refine_selectively(const pm::ProgressiveMesh& progressive, const Settings& settings,
                              pm::Mesh& mesh, std::size_t& level) {
  const SelectiveRequest& request = settings.selective;
  pm::SelectiveRefinement refinement(progressive, request.rule);
  switch (request.kind) {
    case SelectiveRequest::Kind::kView:
      if (pm::Status s = refinement.set_view(request.camera, request.options); !s) return s;
      break;
    case SelectiveRequest::Kind::kSphere:
      refinement.refine_sphere(request.a, request.radius);
      break;
    case SelectiveRequest::Kind::kBox:
      refinement.refine_box(request.a, request.b);
      break;
    case SelectiveRequest::Kind::kViewpoint: {
      const LevelRequest& budget = settings.levels.front();
      const std::size_t faces = budget.kind == LevelRequest::Kind::kFaces ? budget.count : 0;
      const std::size_t vertices = budget.kind == LevelRequest::Kind::kVertices ? budget.count : 0;
      if (pm::Status s = refinement.refine_toward(request.a, faces, vertices); !s) return s;
      break;
    }
    case SelectiveRequest::Kind::kNone:
      break;
  }
  mesh = refinement.to_mesh();
  level = refinement.applied_count();
  return pm::Status::ok();
}

}  // namespace pmdec
