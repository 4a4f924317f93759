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
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "pm/selective_refinement.h"
#include "core/no_throw.h"
#include "view/view_criteria.h"

namespace pm {

struct SelectiveRefinement::ViewState {
  struct Entry {
    uint32_t split, version;
  };
  // Evaluations due after some amount of motion: buckets of motion in a ring, and the
  // evaluations due at the next update whatever the motion.
  struct Calendar {
    static constexpr int64_t kBuckets = 4096;
    std::vector<std::vector<Entry>> buckets;
    std::vector<Entry> next_frame;
    double odometer = 0;      // motion since the boundary was set up
    double bucket_width = 1;  // of motion
    int64_t bucket_now = 0;   // floor(odometer / bucket_width)

    void clear(double width) {
      buckets.assign(kBuckets, {});
      next_frame.clear();
      odometer = 0;
      bucket_width = width;
      bucket_now = 0;
    }
    void add(Entry entry, double margin) {
      const double slot = std::floor((odometer + margin) / bucket_width);
      if (!(slot > double(bucket_now))) {
        next_frame.push_back(entry);
        return;
      }
      const int64_t b = slot >= double(bucket_now + kBuckets - 1) ? bucket_now + kBuckets - 1
                                                                  : static_cast<int64_t>(slot);
      buckets[static_cast<std::size_t>(b % kBuckets)].push_back(entry);
    }
    // Moves the entries due after `moved` more motion into `due`.
    void advance(double moved, std::vector<Entry>& due) {
      odometer += moved;
      const int64_t now = static_cast<int64_t>(std::floor(odometer / bucket_width));
      due.insert(due.end(), next_frame.begin(), next_frame.end());
      next_frame.clear();
      for (int64_t b = bucket_now + 1; b <= now && b <= bucket_now + kBuckets; ++b) {
        std::vector<Entry>& bucket = buckets[static_cast<std::size_t>(b % kBuckets)];
        due.insert(due.end(), bucket.begin(), bucket.end());
        bucket.clear();
      }
      bucket_now = std::max(bucket_now, now);
    }
    std::size_t memory_bytes() const {
      std::size_t total = sizeof(Entry) * next_frame.capacity();
      for (const auto& bucket : buckets) total += sizeof(bucket) + sizeof(Entry) * bucket.capacity();
      return total;
    }
  };

  view::Frame frame;  // its frustum test off while the model is inside the frustum
  ViewCamera camera;
  ViewOptions options;
  bool model_inside = false;
  // Per split, together so that one evaluation touches one cache line of them: the version of
  // its live calendar entries, whether it is wanted, how many of its children are, whether
  // its calendar entries are live, whether it waits in `dirty`.
  struct Flags {
    uint32_t version;
    uint8_t wanted, wanted_children, monitored, queued;
  };
  std::vector<Flags> flags;
  // By the eye's motion (screen-space error, orientation) and the camera's (frustum).
  Calendar by_eye, by_camera;
  std::vector<Entry> due, sorted;  // sorted: sort_by_split()'s scratch
  int split_bits = 1;              // enough bits for any split index

  // A stable radix sort by split, 11 bits a pass: linear, where the entries due in a frame
  // (tens of thousands) took std::sort a tenth of the update.
  static void sort_by_split(std::vector<Entry>& entries, std::vector<Entry>& scratch, int bits) {
    constexpr int kBits = 11;
    scratch.resize(entries.size());
    for (int shift = 0; shift < bits; shift += kBits) {
      std::size_t count[(1 << kBits) + 1] = {};
      for (const Entry& e : entries) ++count[((e.split >> shift) & ((1 << kBits) - 1)) + 1];
      for (int i = 0; i < (1 << kBits); ++i) count[i + 1] += count[i];
      for (const Entry& e : entries) scratch[count[(e.split >> shift) & ((1 << kBits) - 1)]++] = e;
      entries.swap(scratch);
    }
  }
  std::vector<uint32_t> dirty;  // splits whose wanted flag changed: to split or collapse
  std::size_t dirty_head = 0;
  std::size_t evaluations = 0;

  view::Decision evaluate(const SelectiveRefinement& r, uint32_t j) {
    ++evaluations;
    return view::evaluate(r.bounds_[j], frame, true);
  }

  // Watches j again once the eye or the camera has moved by the decision's margins.
  void schedule(uint32_t j, const view::Decision& d) {
    flags[j].monitored = 1;
    const Entry entry{j, ++flags[j].version};
    if (d.eye_margin < std::numeric_limits<double>::infinity()) by_eye.add(entry, d.eye_margin);
    if (d.margin < std::numeric_limits<double>::infinity()) by_camera.add(entry, d.margin);
  }
  void unmonitor(uint32_t j) {
    if (!flags[j].monitored) return;
    flags[j].monitored = 0;
    ++flags[j].version;
  }
  void mark_dirty(uint32_t j) {
    if (flags[j].queued) return;
    flags[j].queued = 1;
    dirty.push_back(j);
  }

  // j was in F and is now wanted: its parent leaves L, its children join F (evaluated now).
  void become_wanted(const SelectiveRefinement& r, uint32_t j, const view::Decision& decision) {
    flags[j].wanted = 1;
    mark_dirty(j);
    const uint32_t p = r.parent_[j];
    if (p != kNoSplit && flags[p].wanted_children++ == 0) unmonitor(p);
    for (uint32_t c : {r.child_u_[j], r.child_v_[j]}) {
      if (c == kNoSplit) continue;
      const view::Decision d = evaluate(r, c);
      if (d.want)
        become_wanted(r, c, d);
      else
        schedule(c, d);
    }
    if (flags[j].wanted_children == 0)
      schedule(j, decision);
    else
      unmonitor(j);
  }

  // j was in L and is no longer wanted: its children leave F, it joins F, and its parent may
  // become a leaf (evaluated now).
  void become_unwanted(const SelectiveRefinement& r, uint32_t j, const view::Decision& decision) {
    flags[j].wanted = 0;
    mark_dirty(j);
    for (uint32_t c : {r.child_u_[j], r.child_v_[j]})
      if (c != kNoSplit) unmonitor(c);
    schedule(j, decision);
    const uint32_t p = r.parent_[j];
    if (p != kNoSplit && --flags[p].wanted_children == 0) {
      const view::Decision d = evaluate(r, p);
      if (d.want)
        schedule(p, d);
      else
        become_unwanted(r, p, d);
    }
  }

  void reevaluate(const SelectiveRefinement& r, uint32_t j) {
    const view::Decision d = evaluate(r, j);
    if (d.want == bool(flags[j].wanted))
      schedule(j, d);
    else if (d.want)
      become_wanted(r, j, d);
    else
      become_unwanted(r, j, d);
  }

  // The boundary from scratch, top-down; every split applied or wanted is then looked at.
  void initialize(const SelectiveRefinement& r) {
    const std::size_t n = r.split_count();
    flags.assign(n, Flags{0, 0, 0, 0, 0});
    split_bits = 1;
    while (split_bits < 32 && (std::size_t{1} << split_bits) < n) ++split_bits;
    by_eye.clear(std::max(r.model_radius_, 1e-30) / 1024);
    by_camera.clear(std::max(r.model_radius_, 1e-30) / 1024);
    dirty.clear();
    dirty_head = 0;
    struct Seen {
      uint32_t split;
      view::Decision decision;
    };
    std::vector<Seen> seen;
    std::vector<uint32_t> stack(r.roots_.rbegin(), r.roots_.rend());
    while (!stack.empty()) {
      const uint32_t j = stack.back();
      stack.pop_back();
      const view::Decision d = evaluate(r, j);
      seen.push_back({j, d});
      if (!d.want) continue;
      flags[j].wanted = 1;
      if (r.parent_[j] != kNoSplit) ++flags[r.parent_[j]].wanted_children;
      if (r.child_v_[j] != kNoSplit) stack.push_back(r.child_v_[j]);
      if (r.child_u_[j] != kNoSplit) stack.push_back(r.child_u_[j]);
    }
    for (const Seen& s : seen)
      if (!flags[s.split].wanted || flags[s.split].wanted_children == 0) schedule(s.split, s.decision);
    for (uint32_t j = 0; j < n; ++j)
      if (flags[j].wanted || r.applied_[j]) mark_dirty(j);
  }

  // The evaluations that are due after the eye and the camera moved by these amounts. An
  // entry may be due in both calendars: the first evaluation renews its version.
  void advance(const SelectiveRefinement& r, double eye_moved, double camera_moved) {
    due.clear();
    by_eye.advance(eye_moved, due);
    by_camera.advance(camera_moved, due);
    // In split order: the bounds and flags are then read in address order, which the
    // hardware prefetches (the order does not change the result, the wanted set of the camera).
    sort_by_split(due, sorted, split_bits);
    // The due splits are sparse (a tenth of the boundary): each evaluation would wait for its
    // bounds and flags from memory, one at a time. Asking for them some entries ahead lets
    // those loads overlap.
    constexpr std::size_t kAhead = 16;
    for (std::size_t i = 0; i < due.size(); ++i) {
      if (i + kAhead < due.size()) {
        const uint32_t ahead = due[i + kAhead].split;
        __builtin_prefetch(&r.bounds_[ahead]);
        __builtin_prefetch(reinterpret_cast<const char*>(&r.bounds_[ahead]) + sizeof(SplitBounds) - 1);
        __builtin_prefetch(&flags[ahead]);
      }
      const Entry& e = due[i];
      if (flags[e.split].monitored && flags[e.split].version == e.version) reevaluate(r, e.split);
    }
  }
};

void SelectiveRefinement::ViewStateDeleter::operator()(ViewState* state) const { delete state; }

std::size_t SelectiveRefinement::view_memory_bytes() const {
  if (!view_) return 0;
  const ViewState& s = *view_;
  std::size_t total = sizeof(ViewState) + sizeof(ViewState::Flags) * s.flags.capacity() +
                      4 * s.dirty.capacity() +
                      sizeof(ViewState::Entry) * (s.due.capacity() + s.sorted.capacity());
  return total + s.by_eye.memory_bytes() + s.by_camera.memory_bytes();
}

Status SelectiveRefinement::update_view(const ViewCamera& camera, const ViewOptions& options,
                                        const UpdateBudget& budget, UpdateStats* stats) {
  return detail::no_throw([&]() -> Status {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    if (Status s = check_camera(camera); !s) return s;
    if (!(options.pixel_error > 0 && std::isfinite(options.pixel_error)))
      return Status(ErrorCode::kInvalidArgument, "pixel error must be a positive number");
    view::Frame frame = view::make_frame(camera, options);
    // While the model's box is inside the frustum, so is every split's box (they nest in it): the frustum test passes everywhere, so it is neither evaluated nor watched,
    // and the boundary is watched by the eye's motion alone. When the model starts to leave
    // the frustum the whole boundary is evaluated again.
    const view::Vec center = view::vec(model_center_);
    const bool model_inside =
        options.frustum_culling && view::box_inside_frustum(frame, box_lo_, box_hi_);
    if (model_inside) frame.frustum = false;
    UpdateStats local;
    const bool same_projection = !(view_ && view_->model_inside && !model_inside) &&
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
    state.model_inside = model_inside;
    if (!same_projection) {
      state.initialize(*this);
    } else {
      state.advance(*this, view::eye_motion(previous, frame, center, model_radius_),
                    view::motion(previous, frame, center, model_radius_));
    }

    // W's changes become splits and collapses, within the budget.
    std::size_t operations = 0, looked_at = 0;
    while (state.dirty_head < state.dirty.size()) {
      if (budget.max_operations && operations >= budget.max_operations) break;
      if (budget.max_microseconds && (looked_at++ & 15) == 0 &&
          std::chrono::duration<double, std::micro>(Clock::now() - start).count() >=
              budget.max_microseconds)
        break;
      // As in advance(): the flags and counts of a split some entries ahead, asked for now.
      if (state.dirty_head + 8 < state.dirty.size()) {
        const uint32_t ahead = state.dirty[state.dirty_head + 8];
        __builtin_prefetch(&state.flags[ahead]);
        __builtin_prefetch(&refcount_[ahead]);
        __builtin_prefetch(&applied_[ahead]);
        __builtin_prefetch(&deps_begin_[ahead]);
      }
      const uint32_t j = state.dirty[state.dirty_head++];
      state.flags[j].queued = 0;
      const bool needed = state.flags[j].wanted || refcount_[j] > 0;
      if (needed && !applied_[j]) {
        const std::size_t count = apply_with_dependencies(j);
        operations += count;
        local.splits += count;
      } else if (!needed && applied_[j]) {
        // Collapse it, then whatever only it held (dependencies no longer needed).
        std::vector<std::pair<uint32_t, uint32_t>>& stack = collapse_stack_;
        stack.assign(1, {j, 0});
        while (!stack.empty()) {
          const uint32_t x = stack.back().first;
          stack.pop_back();
          if (!applied_[x] || refcount_[x] != 0 || state.flags[x].wanted) continue;
          collapse_one(x);
          ++operations;
          ++local.collapses;
          for (uint32_t k = deps_begin_[x]; k < deps_begin_[x + 1]; ++k) {
            const uint32_t d = deps_[k];
            if (refcount_[d] == 0 && !state.flags[d].wanted && applied_[d]) stack.push_back({d, 0});
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
  });
}

}  // namespace pm
