// The collapse loop's recorded error: every removed input vertex carried on a face of the
// simplified surface, as the former default loop's RemovedPoints carried them (Klein, Liebich
// and Straßer 1996, "Mesh reduction with error control": the correspondence between the
// input's vertices and the reduced mesh bounds their distance), so that a collapse records
// the largest distance of the points it moves, and every point rests within the records so
// far of its face. Internal to simplify/.
//
// Why beside kept_points.h: the measure that orders the collapses reads only a face's few
// farthest points, to stay bounded per collapse. The points it leaves off a list were first
// bounded by a slack per face (dropped_points_bound.h, deleted) that grew by the gap between
// the surfaces at every later collapse of their face: a true bound but loose, the records 1.0
// to 8.7 times the largest distance of an input vertex to the level on the shared meshes at
// 50/10/2% of the faces (tests/bench/bound.md at c0f33ce), where the kept points alone came
// within 0.94 to 1.02 times of it and 16 kept points a face still 4 to 6 times: any point
// dropped early carried its slack's growth into the coarse levels. `pmdec --error` and
// view-dependent refinement choose levels by the records, so a loose record buys faces that
// the requested error does not need. Tracking every point costs what it moves: each collapse
// measures all the points of v's faces against the new fan, more the more a face has absorbed
// (about N log N moves over the sequence: the points of a face double as the faces halve),
// which is why the measure does not read them; they are the record only. Most stay on the
// face they were on at one distance: within the kept points' largest (with the measure) or
// the records so far (without it, EncodeOptions::fast, which keeps no points else: cheaper
// than the kept lists and their slack were).
//
// Per face a singly linked list of its points (head per face, next per vertex: 4 bytes each),
// so that moving them costs no allocation. Safe on several threads for collapses whose faces
// are apart (the collapse loop's regions): a point is on one face's list, and a collapse
// moves only the points of its own faces; the scratch is the caller's.
//
// A collapse that moves many points moves them in parts of kPartPoints, each part on its own
// (the largest distance so far that lets a point stay where it was is its part's), so that
// another thread can take some of the parts (PartRunner; tracking_thread.h's loop thread,
// which would otherwise wait). The parts are the same on any number of threads, and so are
// the lists (each part's points go onto its own lists, joined in the parts' order) and the
// records. Why: the coarsest collapses move the most points (a face holds more the coarser
// the level), and they come last, in the one heap after the rounds, where the loop's thread
// waited for the tracking thread (tracking_thread.h has the numbers). Parts of 256 points
// rather than 1024: that wait 0.25 s rather than 0.28 on nefertiti after two Loop steps,
// 0.75 rather than 0.84 on the bunny after three. Against one part a collapse, as before:
// without the measure the same .pm bytes on the shared meshes, the samples, the 950K-face
// textured mesh and both Loop meshes (points settle within the record floor, which the
// parts share); with the measure cow, homer, nefertiti and rocker-arm have other records,
// each as true a bound (the collapses are the same: the records do not order them).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "simplify/face_renumbering.h"
#include "simplify/geometry.h"
#include "simplify/kept_points.h"

namespace pm::collapse_loop {

class TrackedPoints {
 public:
  static constexpr int kMaxOldFaces = 64;  // collapse()'s n_old at most
  // n_faces faces, none holding a point; n_vertices input vertices at xyz (three floats each,
  // the caller's, unchanged while the points are tracked). n_faces 0: frees the memory.
  void reset(std::size_t n_faces, std::size_t n_vertices, const float* xyz);
  // Asks for face f's list ahead of collapse().
  [[gnu::always_inline]] void prefetch(uint32_t f) const { __builtin_prefetch(&head_[f]); }
  // The faces renamed without the dead ones (face_renumbering.h), whose lists are empty.
  void compact(const FaceRenumbering& faces) { faces.compact(head_, 1); }
  // The points on face f's list, first to last (tests read the lists through it).
  std::vector<uint32_t> points_on(uint32_t f) const {
    std::vector<uint32_t> points;
    for (uint32_t x = head_[f]; x != kNone; x = next_[x]) points.push_back(x);
    return points;
  }

  // The collapse v -> u (before the faces change): v and every point on old_faces (v's
  // faces, those at v-u among them) go to a face of `fan` (the faces around u after it, v's
  // moved faces among them with their ids): the first within `settled` of it, or within the
  // largest distance of a point of its part moved before it (the face it was on tried first,
  // when in the fan, else a moved face next to it around v), else its nearest. Returns the
  // largest distance of a moved point to its new face, leaving out points within `settled`
  // (at least the exact largest distance to the fan where that is above `settled`, at most
  // the larger of that and `settled`); infinity when a point is nearer to no face
  // (non-finite input, or an empty fan). `settled`: a distance the sequence records anyway
  // at this collapse (the kept points' exact largest, kept_points.h, or a record before
  // it), below which a point's own does not change the record; most points are that near
  // the face they were on, and take one distance instead of a search (and, by its square, no
  // root: move()). With the measure, one thread, alternating runs against the slack alone:
  // nefertiti 0.95 -> 0.99 s, armadillo 0.42 -> 0.44 s; with every point's nearest face
  // searched, 11% slower.
  // `scratch` holds the moving points and their parts' lists; `runner`, when given, runs the
  // parts of a collapse that has more than one (else they run here, in turn).
  struct Scratch {
    std::vector<uint32_t> points;  // pairs: a point, the fan index it tries first or kNone
    std::vector<uint32_t> lists;   // per part, per fan face: its head, then its tail
    std::vector<double> farthest;  // per part, its points' largest distance
    std::vector<uint8_t> lost;     // per part, whether a point found no face
  };
  // Runs part(0), ..., part(count - 1), each once, and returns when all are done.
  class PartRunner {
   public:
    virtual void run_parts(uint32_t count, const std::function<void(uint32_t)>& part) = 0;

   protected:
    ~PartRunner() = default;
  };
  // The points a collapse moves in one part at most, when it moves at least twice as many.
  static constexpr std::size_t kPartPoints = 256;
  double collapse(uint32_t v, const uint32_t* old_faces, int n_old, const KeptPoints::FanFace* fan,
                  int n_fan, double settled, Scratch& scratch, PartRunner* runner = nullptr);

  // The collapse's tracking and its record, as the loop makes them: the points settle within
  // the kept points' exact largest distance `farthest` with the measure, else within *floor
  // (the largest record so far), which then takes the record.
  float track(uint32_t v, const uint32_t* old_faces, int n_old, const KeptPoints::FanFace* fan,
              int n_fan, bool measured, double farthest, float* floor, Scratch& scratch,
              PartRunner* runner = nullptr) {
    const double moved = collapse(v, old_faces, n_old, fan, n_fan,
                                  measured ? farthest : double{*floor}, scratch, runner);
    const float recorded = record(farthest, moved);
    *floor = std::max(*floor, recorded);
    return recorded;
  }

  // A collapse's record: the larger of the kept points' distance `farthest` (0 without the
  // measure) and the moved points' (collapse()'s), rounded up to a float; the largest float
  // where a point found no face (then no finite record bounds it). At most the largest
  // float: no distance on a mesh encode() accepts is larger (its diagonal is at most
  // kMaxEncodeDiagonal, below that).
  static float record(double farthest, double moved) {
    const double own =
        std::min<double>(std::max(farthest, moved), std::numeric_limits<float>::max());
    const float recorded = static_cast<float>(own);
    return double(recorded) < own ? std::nextafter(recorded, HUGE_VALF) : recorded;
  }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  struct PlaneScreen;  // a fan face's plane and frame (tracked_points.cpp)
  // Moves `count` of collapse()'s pairs onto the fan, each onto the front of a list of its new
  // face's: push(i, x) puts point x there, i its face's index in the fan (the faces' own lists
  // for a collapse in one part; else the part's, to be joined). Returns their largest
  // distance to their new faces, leaving out those within `settled` (collapse()'s result);
  // *lost when a point found no face.
  // `screens`: the fan faces' planes and frames (tracked_points.cpp), made once per collapse
  // and read by every part; nullptr where the collapse moves fewer points than its fan has
  // faces, or settles nothing.
  template <typename Push>
  double move(const uint32_t* pairs, std::size_t count, const KeptPoints::FanFace* fan, int n_fan,
              const PlaneScreen* screens, double settled, uint8_t* lost, Push push);
  std::vector<uint32_t> head_;  // per face: its first point, kNone when it holds none
  std::vector<uint32_t> next_;  // per vertex: the next point on its face's list
  const float* xyz_ = nullptr;
};

}  // namespace pm::collapse_loop
