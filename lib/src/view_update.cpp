// Incremental view-dependent refinement (Hoppe 1997, "View-dependent refinement of progressive
// meshes", §5: the active mesh of the previous frame is adapted to the new viewpoint by
// splitting and collapsing where the criteria changed, exploiting frame-to-frame coherence).
//
// Hoppe 1997 re-evaluates the whole active vertex front every frame. Here, since the criteria
// are monotone up the hierarchy (view_criteria.cpp), the wanted set W of a camera is fixed by
// its boundary: its leaves L (wanted, no wanted child) and the splits just outside it F (not
// wanted, parent wanted or a root). Only L and F are watched, and each of them only when the
// camera has moved by more than the margin of its last evaluation (the motion within which
// its decision cannot change; compare the per-vertex validity intervals of temporal
// coherence in Xia and Varshney 1996, §5). The due evaluations sit in a calendar of
// buckets of camera motion. When a watched split changes side, the boundary moves and the
// splits that join it are evaluated at once. W's changes then become splits and collapses:
// the applied set is the closure of W under the dependencies, each split applied while it is
// wanted or an applied split depends on it (a reference count), collapsed when neither holds.
#include <chrono>
#include <cmath>

#include "pm/selective_refinement.h"
#include "view_criteria.h"

namespace pm {

struct SelectiveRefinement::ViewState {
  struct Entry {
    uint32_t split, version;
  };
  static constexpr int64_t kBuckets = 4096;

  view::Frame frame;
  ViewCamera camera;
  ViewOptions options;
  std::vector<uint8_t> wanted, wanted_children, monitored, queued;
  std::vector<uint32_t> version;  // of each split's one live calendar entry
  std::vector<std::vector<Entry>> buckets;
  std::vector<Entry> next_frame, due;
  double odometer = 0;      // camera motion since the boundary was set up (view::motion)
  double bucket_width = 1;  // of motion
  int64_t bucket_now = 0;   // floor(odometer / bucket_width)
  std::vector<uint32_t> dirty;  // splits whose wanted flag changed: to split or collapse
  std::size_t dirty_head = 0;
  std::size_t evaluations = 0;

  view::Decision evaluate(const SelectiveRefinement& r, uint32_t j) {
    ++evaluations;
    return view::evaluate(r.bounds_[j], frame, true);
  }

  // Watches j again once the camera has moved by `margin`, or at the next update when that is
  // within the current bucket.
  void schedule(uint32_t j, double margin) {
    monitored[j] = 1;
    ++version[j];
    const double slot = std::floor((odometer + margin) / bucket_width);
    if (!(slot > double(bucket_now))) {
      next_frame.push_back({j, version[j]});
      return;
    }
    const int64_t b = slot >= double(bucket_now + kBuckets - 1) ? bucket_now + kBuckets - 1
                                                                : static_cast<int64_t>(slot);
    buckets[static_cast<std::size_t>(b % kBuckets)].push_back({j, version[j]});
  }
  void unmonitor(uint32_t j) {
    if (!monitored[j]) return;
    monitored[j] = 0;
    ++version[j];
  }
  void mark_dirty(uint32_t j) {
    if (queued[j]) return;
    queued[j] = 1;
    dirty.push_back(j);
  }

  // j was in F and is now wanted: its parent leaves L, its children join F (evaluated now).
  void become_wanted(const SelectiveRefinement& r, uint32_t j, double margin) {
    wanted[j] = 1;
    mark_dirty(j);
    const uint32_t p = r.parent_[j];
    if (p != kNoSplit && wanted_children[p]++ == 0) unmonitor(p);
    for (uint32_t c : {r.child_u_[j], r.child_v_[j]}) {
      if (c == kNoSplit) continue;
      const view::Decision d = evaluate(r, c);
      if (d.want)
        become_wanted(r, c, d.margin);
      else
        schedule(c, d.margin);
    }
    if (wanted_children[j] == 0)
      schedule(j, margin);
    else
      unmonitor(j);
  }

  // j was in L and is no longer wanted: its children leave F, it joins F, and its parent may
  // become a leaf (evaluated now).
  void become_unwanted(const SelectiveRefinement& r, uint32_t j, double margin) {
    wanted[j] = 0;
    mark_dirty(j);
    for (uint32_t c : {r.child_u_[j], r.child_v_[j]})
      if (c != kNoSplit) unmonitor(c);
    schedule(j, margin);
    const uint32_t p = r.parent_[j];
    if (p != kNoSplit && --wanted_children[p] == 0) {
      const view::Decision d = evaluate(r, p);
      if (d.want)
        schedule(p, d.margin);
      else
        become_unwanted(r, p, d.margin);
    }
  }

  void reevaluate(const SelectiveRefinement& r, uint32_t j) {
    const view::Decision d = evaluate(r, j);
    if (d.want == bool(wanted[j]))
      schedule(j, d.margin);
    else if (d.want)
      become_wanted(r, j, d.margin);
    else
      become_unwanted(r, j, d.margin);
  }

  // The boundary from scratch, top-down; every split applied or wanted is then looked at.
  void initialize(const SelectiveRefinement& r) {
    const std::size_t n = r.split_count();
    wanted.assign(n, 0);
    wanted_children.assign(n, 0);
    monitored.assign(n, 0);
    queued.assign(n, 0);
    version.assign(n, 0);
    buckets.assign(kBuckets, {});
    next_frame.clear();
    dirty.clear();
    dirty_head = 0;
    odometer = 0;
    bucket_now = 0;
    bucket_width = std::max(r.model_radius_, 1e-30) / 1024;
    struct Seen {
      uint32_t split;
      double margin;
    };
    std::vector<Seen> seen;
    std::vector<uint32_t> stack(r.roots_.rbegin(), r.roots_.rend());
    while (!stack.empty()) {
      const uint32_t j = stack.back();
      stack.pop_back();
      const view::Decision d = evaluate(r, j);
      seen.push_back({j, d.margin});
      if (!d.want) continue;
      wanted[j] = 1;
      if (r.parent_[j] != kNoSplit) ++wanted_children[r.parent_[j]];
      if (r.child_v_[j] != kNoSplit) stack.push_back(r.child_v_[j]);
      if (r.child_u_[j] != kNoSplit) stack.push_back(r.child_u_[j]);
    }
    for (const Seen& s : seen)
      if (!wanted[s.split] || wanted_children[s.split] == 0) schedule(s.split, s.margin);
    for (uint32_t j = 0; j < n; ++j)
      if (wanted[j] || r.applied_[j]) mark_dirty(j);
  }

  // The evaluations that are due after the camera moved by `moved`.
  void advance(const SelectiveRefinement& r, double moved) {
    odometer += moved;
    const int64_t now = static_cast<int64_t>(std::floor(odometer / bucket_width));
    due.clear();
    due.swap(next_frame);
    for (int64_t b = bucket_now + 1; b <= now && b <= bucket_now + kBuckets; ++b) {
      std::vector<Entry>& bucket = buckets[static_cast<std::size_t>(b % kBuckets)];
      due.insert(due.end(), bucket.begin(), bucket.end());
      bucket.clear();
    }
    bucket_now = std::max(bucket_now, now);
    for (const Entry& e : due)
      if (monitored[e.split] && version[e.split] == e.version) reevaluate(r, e.split);
  }
};

void SelectiveRefinement::ViewStateDeleter::operator()(ViewState* state) const { delete state; }

std::size_t SelectiveRefinement::view_memory_bytes() const {
  if (!view_) return 0;
  const ViewState& s = *view_;
  std::size_t total = sizeof(ViewState) + s.wanted.capacity() + s.wanted_children.capacity() +
                      s.monitored.capacity() + s.queued.capacity() + 4 * s.version.capacity() +
                      4 * s.dirty.capacity() +
                      sizeof(ViewState::Entry) * (s.next_frame.capacity() + s.due.capacity());
  for (const auto& bucket : s.buckets)
    total += sizeof(bucket) + sizeof(ViewState::Entry) * bucket.capacity();
  return total;
}

Status SelectiveRefinement::update_view(const ViewCamera& camera, const ViewOptions& options,
                                        const UpdateBudget& budget, UpdateStats* stats) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  if (Status s = check_camera(camera); !s) return s;
  if (!(options.pixel_error > 0 && std::isfinite(options.pixel_error)))
    return Status(ErrorCode::kInvalidArgument, "pixel error must be a positive number");
  const view::Frame frame = view::make_frame(camera, options);
  UpdateStats local;
  const bool same_projection =
      view_ && view_->options.pixel_error == options.pixel_error &&
      view_->options.frustum_culling == options.frustum_culling &&
      view_->options.backface_culling == options.backface_culling &&
      view_->camera.fov_degrees == camera.fov_degrees &&
      view_->camera.viewport_height == camera.viewport_height &&
      view_->camera.viewport_width == camera.viewport_width;
  if (!view_) view_.reset(new ViewState);
  ViewState& state = *view_;
  const std::size_t evaluations_before = state.evaluations;
  const view::Frame previous = state.frame;
  state.frame = frame;
  state.camera = camera;
  state.options = options;
  if (!same_projection) {
    state.initialize(*this);
  } else {
    state.advance(*this, view::motion(previous, frame, view::vec(model_center_), model_radius_));
  }

  // W's changes become splits and collapses, within the budget.
  std::size_t operations = 0, looked_at = 0;
  while (state.dirty_head < state.dirty.size()) {
    if (budget.max_operations && operations >= budget.max_operations) break;
    if (budget.max_microseconds && (looked_at++ & 15) == 0 &&
        std::chrono::duration<double, std::micro>(Clock::now() - start).count() >=
            budget.max_microseconds)
      break;
    const uint32_t j = state.dirty[state.dirty_head++];
    state.queued[j] = 0;
    const bool needed = state.wanted[j] || refcount_[j] > 0;
    if (needed && !applied_[j]) {
      const std::size_t count = apply(j);
      operations += count;
      local.splits += count;
    } else if (!needed && applied_[j]) {
      // Collapse it, then whatever only it held (dependencies no longer needed).
      std::vector<uint32_t> stack{j};
      while (!stack.empty()) {
        const uint32_t x = stack.back();
        stack.pop_back();
        if (!applied_[x] || refcount_[x] != 0 || state.wanted[x]) continue;
        collapse_one(x);
        ++operations;
        ++local.collapses;
        for (uint32_t k = deps_begin_[x]; k < deps_begin_[x + 1]; ++k) {
          const uint32_t d = deps_[k];
          if (refcount_[d] == 0 && !state.wanted[d] && applied_[d]) stack.push_back(d);
        }
      }
    }
  }
  if (state.dirty_head == state.dirty.size()) {
    state.dirty.clear();
    state.dirty_head = 0;
  } else if (state.dirty_head > state.dirty.size() / 2) {
    state.dirty.erase(state.dirty.begin(), state.dirty.begin() + state.dirty_head);
    state.dirty_head = 0;
  }
  local.pending = state.dirty.size() - state.dirty_head;
  local.evaluations = state.evaluations - evaluations_before;
  if (stats) *stats = local;
  return Status::ok();
}

}  // namespace pm
