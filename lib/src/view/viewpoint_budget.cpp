// Distance-weighted simplification within a budget: the source report's ViewDependentModel,
// which simplifies more where the model is far from a viewpoint, built on selective
// refinement. From the base mesh, the splits are taken greedily by priority
// deviation / distance (the screen-space error of Hoppe 1997, §3.3, without the frustum: the
// size on screen of the detail a split adds, seen from the viewpoint), each with the splits it
// depends on, while the mesh stays within the budget; a split whose dependencies would
// overflow the budget is passed over. Only splits whose hierarchy parent is applied are
// candidates, so the refinement front moves outward from the viewpoint (Hoppe 1997, §2: the
// active front of the vertex hierarchy).
#include <cmath>
#include <queue>

#include "pm/selective_refinement.h"
#include "core/no_throw.h"
#include "view/view_criteria.h"

namespace pm {

Status SelectiveRefinement::refine_toward(const Point3& viewpoint, std::size_t max_faces,
                                          std::size_t max_vertices) {
  return detail::no_throw([&]() -> Status {
    for (double x : viewpoint)
      if (!std::isfinite(x)) return Status(ErrorCode::kInvalidArgument, "viewpoint is not finite");
    if (max_faces == 0 && max_vertices == 0)
      return Status(ErrorCode::kInvalidArgument, "no face or vertex budget given");
    reset();
    if (max_faces && max_faces < face_count())
      return Status(ErrorCode::kInvalidArgument,
                    "budget of " + std::to_string(max_faces) + " faces is below the base mesh's " +
                        std::to_string(face_count()));
    if (max_vertices && max_vertices < vertex_count())
      return Status(ErrorCode::kInvalidArgument,
                    "budget of " + std::to_string(max_vertices) +
                        " vertices is below the base mesh's " + std::to_string(vertex_count()));

    const view::Vec eye = view::vec(viewpoint);
    // Distances below this count as this (the viewpoint on the surface).
    const double nearest = 1e-9 * (model_radius_ + 1);
    auto priority = [&](uint32_t j) {
      const SplitBounds& b = bounds_[j];
      const double distance = view::length(view::vec(b.center) - eye) - b.radius;
      return double(b.deviation) / std::max(distance, nearest);
    };
    // Highest priority first; among equals, the earlier split.
    using Candidate = std::pair<double, uint32_t>;
    auto lower = [](const Candidate& a, const Candidate& b) {
      return a.first < b.first || (a.first == b.first && a.second > b.second);
    };
    std::priority_queue<Candidate, std::vector<Candidate>, decltype(lower)> queue(lower);
    std::vector<uint8_t> queued(split_count(), 0);
    auto offer = [&](uint32_t j) {
      if (j == kNoSplit || applied_[j] || queued[j]) return;
      queued[j] = 1;
      queue.push({priority(j), j});
    };
    for (uint32_t j : roots_) offer(j);

    std::vector<uint32_t> mark(split_count(), kNoSplit), closure, stack;
    std::size_t faces = face_count(), vertices = vertex_count();
    const std::size_t n = split_count();
    for (uint32_t round = 0; !queue.empty(); ++round) {
      if ((max_faces && faces >= max_faces) || (max_vertices && vertices >= max_vertices)) break;
      const uint32_t j = queue.top().second;
      queue.pop();
      if (applied_[j]) continue;
      // What applying j costs: j and its unapplied dependencies, recursively.
      closure.clear();
      stack.assign(1, j);
      mark[j] = round;
      std::size_t added_faces = 0;
      while (!stack.empty()) {
        const uint32_t x = stack.back();
        stack.pop_back();
        closure.push_back(x);
        added_faces += new_face_begin_[x + 1] - new_face_begin_[x];
        for (uint32_t k = deps_begin_[x]; k < deps_begin_[x + 1]; ++k) {
          const uint32_t d = deps_[k];
          if (!applied_[d] && mark[d] != round) {
            mark[d] = round;
            stack.push_back(d);
          }
        }
      }
      std::size_t added_vertices = closure.size();
      if (applied_count_ + closure.size() == n) added_vertices += pm_->loose_vertex_count;
      if ((max_faces && faces + added_faces > max_faces) ||
          (max_vertices && vertices + added_vertices > max_vertices)) {
        continue;  // passed over (its children are offered if another split forces it)
      }
      apply_with_dependencies(j);
      faces += added_faces;
      vertices += added_vertices;
      for (uint32_t x : closure) {
        offer(child_u_[x]);
        offer(child_v_[x]);
      }
    }
    return Status::ok();
  });
}

}  // namespace pm
