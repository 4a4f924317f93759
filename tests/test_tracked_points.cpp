// The tracked points' collapse in parts (simplify/tracked_points.h): a collapse that moves many
// points moves them in parts, which another thread may take (tracking_thread.h). Whoever runs
// the parts, in whatever order, the lists and the record must be the same, and the record a
// bound of every moved point's distance to the face it went to.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <thread>
#include <vector>

#include "simplify/geometry.h"
#include "simplify/kept_points.h"
#include "simplify/tracked_points.h"
#include "simplify/tracking_thread.h"

namespace pm::collapse_loop {
namespace {

using FanFace = KeptPoints::FanFace;

// Runs the parts last first.
class BackwardsRunner final : public TrackedPoints::PartRunner {
 public:
  void run_parts(uint32_t count, const std::function<void(uint32_t)>& part) override {
    counts.push_back(count);
    for (uint32_t j = count; j-- > 0;) part(j);
  }
  std::vector<uint32_t> counts;
};

// Runs the parts on two threads at once, each taking the next part left.
class TwoThreadRunner final : public TrackedPoints::PartRunner {
 public:
  void run_parts(uint32_t count, const std::function<void(uint32_t)>& part) override {
    counts.push_back(count);
    std::atomic<uint32_t> next{0};
    auto take = [&] {
      for (uint32_t j; (j = next.fetch_add(1)) < count;) part(j);
    };
    std::thread other(take);
    take();
    other.join();
  }
  std::vector<uint32_t> counts;
};

// A disc of kSpokes triangles around the origin (faces kFanFace, ...) and, above and below
// it, kPoints input vertices scattered over it; vertices kPoints, ... are the ones collapsed.
constexpr int kSpokes = 8;
constexpr uint32_t kPoints = 5000, kCollapsed = 20;
constexpr uint32_t kHolder = 0, kEmpty = 1, kFanFace = 10, kTurnedFanFace = 20;

std::vector<float> scattered_points() {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f), radius(0.0f, 0.95f),
      height(-0.1f, 0.1f);
  std::vector<float> xyz;
  for (uint32_t i = 0; i < kPoints + kCollapsed; ++i) {
    const float a = angle(random), r = radius(random);
    xyz.insert(xyz.end(), {r * std::cos(a), r * std::sin(a), height(random)});
  }
  return xyz;
}

// The disc's faces, or (turned) the same disc turned half a spoke, faces kTurnedFanFace, ....
std::vector<FanFace> disc(bool turned = false) {
  std::vector<FanFace> fan;
  const Vec3 centre(0, 0, 0);
  const double turn = turned ? 0.5 : 0.0;
  for (int k = 0; k < kSpokes; ++k) {
    const double a = 6.283185307179586 * (k + turn) / kSpokes,
                 b = 6.283185307179586 * (k + 1 + turn) / kSpokes;
    fan.push_back(FanFace::make((turned ? kTurnedFanFace : kFanFace) + k, centre,
                                Vec3(std::cos(a), std::sin(a), 0),
                                Vec3(std::cos(b), std::sin(b), 0)));
  }
  return fan;
}

// Every point collapsed onto face kHolder, one at a time, in turn.
void hold_every_point(TrackedPoints& tracked, const std::vector<float>& xyz) {
  tracked.reset(kTurnedFanFace + kSpokes, kPoints + kCollapsed, xyz.data());
  TrackedPoints::Scratch scratch;
  // A triangle far wider than the disc, below it: one face to hold every point.
  const FanFace holder =
      FanFace::make(kHolder, Vec3(-10, -10, -1), Vec3(10, -10, -1), Vec3(0, 10, -1));
  for (uint32_t x = 0; x < kPoints; ++x) {
    const uint32_t none[] = {kEmpty};
    tracked.collapse(x, none, 1, &holder, 1, 0.0, scratch);
  }
}

// A collapse's record, and the lists of the faces it moved points onto.
struct Moved {
  double record;
  std::vector<std::vector<uint32_t>> lists;
};

// Every point on face kHolder (each collapsed there alone), then vertex kPoints collapsed
// from kHolder onto the disc, its parts run by `runner` (in turn when null).

Moved collapse_onto_disc(const std::vector<float>& xyz, TrackedPoints::PartRunner* runner) {
  TrackedPoints tracked;
  hold_every_point(tracked, xyz);
  TrackedPoints::Scratch scratch;
  EXPECT_EQ(tracked.points_on(kHolder).size(), kPoints);
  const std::vector<FanFace> fan = disc();
  const uint32_t old_faces[] = {kHolder};
  Moved moved;
  moved.record = tracked.collapse(kPoints, old_faces, 1, fan.data(), kSpokes, 0.0, scratch, runner);
  EXPECT_TRUE(tracked.points_on(kHolder).empty());
  for (const FanFace& face : fan) moved.lists.push_back(tracked.points_on(face.face));
  return moved;
}

TEST(TrackedPoints, PartsGiveTheSameListsAndRecordWhoeverRunsThem) {
  const std::vector<float> xyz = scattered_points();
  const Moved in_turn = collapse_onto_disc(xyz, nullptr);
  BackwardsRunner backwards;
  TwoThreadRunner two_threads;
  const Moved last_first = collapse_onto_disc(xyz, &backwards);
  const Moved side_by_side = collapse_onto_disc(xyz, &two_threads);
  // The collapse moved its kPoints + 1 points in parts of kPartPoints (the other collapses,
  // one point each, ran in turn without the runner).
  const auto parts = static_cast<uint32_t>((kPoints + 1 + TrackedPoints::kPartPoints - 1) /
                                           TrackedPoints::kPartPoints);
  EXPECT_EQ(backwards.counts, std::vector<uint32_t>{parts});
  EXPECT_EQ(two_threads.counts, std::vector<uint32_t>{parts});
  EXPECT_EQ(last_first.record, in_turn.record);
  EXPECT_EQ(side_by_side.record, in_turn.record);
  // (Checked to fail when the parts share their largest distance as they end: the points near
  // two faces then go to the other one, run last first.)
  EXPECT_EQ(last_first.lists, in_turn.lists);
  EXPECT_EQ(side_by_side.lists, in_turn.lists);
  // Every point is on one face, within the record of it (the largest distance it claims).
  std::size_t on_faces = 0;
  double farthest = 0;
  const std::vector<FanFace> fan = disc();
  for (int k = 0; k < kSpokes; ++k) {
    for (const uint32_t x : in_turn.lists[k]) {
      const Vec3 p(xyz[3 * x], xyz[3 * x + 1], xyz[3 * x + 2]);
      const double d = point_triangle_distance(p, fan[k].a, fan[k].b, fan[k].c);
      EXPECT_LE(d, in_turn.record) << "point " << x;
      farthest = std::max(farthest, d);
      ++on_faces;
    }
  }
  EXPECT_EQ(on_faces, kPoints + 1);
  // And the record is no looser than it must be: some point is that far from its face.
  EXPECT_EQ(farthest, in_turn.record);
}

// Points at heights `z` above face kHolder's plane (z = 0; the first height is collapsed last),
// each collapsed there alone, then one more vertex (on the plane) collapsed from kHolder onto
// kHolder as it was and a face kOther above it (z = 0.3), with `settled`.
constexpr uint32_t kOther = 30;
struct Settled {
  double record;
  std::vector<uint32_t> on_holder, on_other;  // the heights' indices
};
Settled collapse_with_settled(const std::vector<float>& z, double settled) {
  std::vector<float> xyz;
  for (std::size_t i = 0; i < z.size(); ++i)
    xyz.insert(xyz.end(), {0.1f * static_cast<float>(i % 5), 0.05f * static_cast<float>(i), z[i]});
  xyz.insert(xyz.end(), {0.3f, 0.3f, 0.0f});
  const auto n = static_cast<uint32_t>(z.size());
  TrackedPoints tracked;
  tracked.reset(kOther + 1, n + 1, xyz.data());
  TrackedPoints::Scratch scratch;
  const auto plane = [](uint32_t id, double height) {
    return FanFace::make(id, Vec3(-10, -10, height), Vec3(10, -10, height), Vec3(0, 10, height));
  };
  const FanFace fan[] = {plane(kHolder, 0.0), plane(kOther, 0.3)};
  for (uint32_t x = 0; x < n; ++x) {
    const uint32_t none[] = {kEmpty};
    tracked.collapse(x, none, 1, fan, 1, 0.0, scratch);
  }
  const uint32_t old_faces[] = {kHolder};
  Settled out;
  out.record = tracked.collapse(n, old_faces, 1, fan, 2, settled, scratch);
  for (const uint32_t x : tracked.points_on(kHolder))
    if (x < n) out.on_holder.push_back(x);
  out.on_other = tracked.points_on(kOther);
  std::sort(out.on_holder.begin(), out.on_holder.end());
  std::sort(out.on_other.begin(), out.on_other.end());
  // Whatever the record leaves out is within `settled`: every point is within the larger
  // of the two of its face.
  for (const uint32_t x : tracked.points_on(kHolder))
    EXPECT_LE(std::abs(double{xyz[3 * x + 2]}), std::max(settled, out.record)) << "point " << x;
  for (const uint32_t x : out.on_other)
    EXPECT_LE(std::abs(0.3 - double{xyz[3 * x + 2]}), std::max(settled, out.record))
        << "point " << x;
  return out;
}

// A point within `settled` of the face it was on stays there, even where another face is
// nearer, and its distance is no part of the record (the sequence records `settled` anyway);
// a point farther, by as little as a unit in the last place, goes to its nearest face and
// counts. Most points stay so: move() decides by their squared distance, without its root.
TEST(TrackedPoints, PointsWithinSettledStayAndLeaveTheRecordAlone) {
  const double settled = 0.25;
  const double just_below = std::nextafter(settled, 0.0);  // 0.25 is a unit beyond it
  const double to_other_from_28 = 0.3 - double{0.28f}, to_other_from_25 = 0.3 - 0.25;
  // 0.1, 0.25 and 0.2 stay on kHolder (within 0.25, though kOther is nearer to 0.25 and
  // 0.2); 0.28 goes to kOther; -0.5, the last, stays on kHolder as its nearest, and is the
  // record.
  Settled with_far = collapse_with_settled({-0.5f, 0.1f, 0.25f, 0.28f, 0.2f}, settled);
  EXPECT_EQ(with_far.record, 0.5);
  EXPECT_EQ(with_far.on_holder, (std::vector<uint32_t>{0, 1, 2, 4}));
  EXPECT_EQ(with_far.on_other, std::vector<uint32_t>{3});
  // Without it, the record is 0.28's distance to kOther: the points that stayed within 0.25
  // are left out.
  Settled near = collapse_with_settled({0.1f, 0.24f, 0.28f, 0.2f}, settled);
  EXPECT_EQ(near.record, to_other_from_28);
  EXPECT_EQ(near.on_holder, (std::vector<uint32_t>{0, 1, 3}));
  // A point at 0.25 exactly stays as well (its square cannot say so; its root does, and
  // may count, within `settled`).
  Settled at = collapse_with_settled({0.1f, 0.25f, 0.2f}, settled);
  EXPECT_EQ(at.on_holder, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_LE(at.record, settled);
  // Settled a unit below 0.25: 0.25 goes to kOther, and is the record.
  Settled below = collapse_with_settled({0.1f, 0.25f, 0.28f, 0.2f}, just_below);
  EXPECT_EQ(below.record, to_other_from_25);
  EXPECT_EQ(below.on_holder, (std::vector<uint32_t>{0, 3}));
  EXPECT_EQ(below.on_other, (std::vector<uint32_t>{1, 2}));
  // Settled 0: the record is every moved point's largest distance to its face.
  Settled none = collapse_with_settled({0.1f, 0.25f, 0.28f, 0.2f}, 0.0);
  EXPECT_EQ(none.record, double{0.1f});
}

// Each moved point goes onto the front of its new face's list in turn, before the points the
// face held already (a collapse of few points, in one part, writes the faces' lists
// directly; a larger one joins its parts' lists so: the test above).
TEST(TrackedPoints, EachPointGoesOntoTheFrontOfItsFacesList) {
  // Points 0 to 3 at heights 0.29, 0.28, 0.27 and 0.01, vertex 4 on the plane z = 0.
  const std::vector<float> xyz = {0.1f,  0.1f, 0.29f, 0.2f,  0.1f, 0.28f, 0.3f, 0.1f,
                                  0.27f, 0.4f, 0.1f,  0.01f, 0.5f, 0.1f,  0.0f};
  TrackedPoints tracked;
  tracked.reset(kOther + 1, 5, xyz.data());
  TrackedPoints::Scratch scratch;
  const auto plane = [](uint32_t id, double height) {
    return FanFace::make(id, Vec3(-10, -10, height), Vec3(10, -10, height), Vec3(0, 10, height));
  };
  const FanFace fan[] = {plane(kHolder, 0.0), plane(kOther, 0.3)};
  const uint32_t none[] = {kEmpty};
  tracked.collapse(0, none, 1, &fan[1], 1, 0.0, scratch);  // point 0 onto kOther
  for (uint32_t x = 1; x <= 3; ++x) tracked.collapse(x, none, 1, &fan[0], 1, 0.0, scratch);
  EXPECT_EQ(tracked.points_on(kHolder), (std::vector<uint32_t>{3, 2, 1}));
  // Vertex 4 from kHolder: it and 3 stay (within 0.05), 2 and then 1 go to kOther (0.03 and
  // 0.02 from it), in front of point 0.
  const uint32_t old_faces[] = {kHolder};
  const double record = tracked.collapse(4, old_faces, 1, fan, 2, 0.05, scratch);
  EXPECT_EQ(tracked.points_on(kHolder), (std::vector<uint32_t>{3, 4}));
  EXPECT_EQ(tracked.points_on(kOther), (std::vector<uint32_t>{1, 2, 0}));
  EXPECT_EQ(record, 0.3 - double{0.27f});
}

// A collapse that moves at least as many points as its fan has faces screens them by each
// face's plane first (move()): a point whose foot falls inside the face it was on stays there
// when its height is within `settled`. The screen must not keep a point whose height is
// within `settled` but whose foot falls outside the face: its distance to the face is more.
TEST(TrackedPoints, APointBesideItsFaceIsNotKeptByItsHeight) {
  const std::vector<FanFace> fan = disc();  // face kFanFace spans 0 to 45 degrees
  const double settled = 0.12, to_radians = 6.283185307179586 / 360;
  std::vector<float> xyz;
  const auto add = [&](double degrees, double radius, double height) {
    xyz.insert(xyz.end(), {static_cast<float>(radius * std::cos(degrees * to_radians)),
                           static_cast<float>(radius * std::sin(degrees * to_radians)),
                           static_cast<float>(height)});
  };
  for (int i = 0; i < 10; ++i) add(5 + 3.5 * i, 0.3 + 0.05 * i, 0.01 * i);  // 0-9: above it
  add(20, 1.3, 0.05);   // 10: beyond the disc's rim, 0.38 from kFanFace
  add(60, 0.5, 0.1);    // 11: above the next face, 0.163 from kFanFace
  add(30, 0.5, 0.11);   // 12: above it, within `settled`
  add(10, 0.2, 0.0);    // 13: the vertex collapsed
  const auto n = static_cast<uint32_t>(xyz.size() / 3);
  TrackedPoints tracked;
  tracked.reset(kTurnedFanFace, n, xyz.data());
  TrackedPoints::Scratch scratch;
  for (uint32_t x = 0; x + 1 < n; ++x) {  // every point on kFanFace
    const uint32_t none[] = {kEmpty};
    tracked.collapse(x, none, 1, &fan[0], 1, 0.0, scratch);
  }
  const uint32_t old_faces[] = {kFanFace};
  const double record = tracked.collapse(n - 1, old_faces, 1, fan.data(), kSpokes, settled, scratch);
  std::vector<uint32_t> on_face = tracked.points_on(kFanFace);
  std::sort(on_face.begin(), on_face.end());
  // The list's last point moves first: 11 before 10, whose distance, once the largest so
  // far, would keep 11 where it was.
  EXPECT_EQ(on_face, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 13}));
  EXPECT_EQ(tracked.points_on(kFanFace + 1), std::vector<uint32_t>{11});
  // Point 10 stays on its nearest face, beyond `settled`: the record.
  const Vec3 far(xyz[30], xyz[31], xyz[32]);
  EXPECT_EQ(record, point_triangle_distance(far, fan[0].a, fan[0].b, fan[0].c));
  EXPECT_GT(record, 0.37);
}

// The collapses of the test below: kHolder's points onto the disc, then back and forth between
// the disc and the disc turned, each time every point and a vertex more (kPoints + i). Each
// collapse's record, and the lists at the end.
struct Sequence {
  std::vector<float> records;
  std::vector<std::vector<uint32_t>> lists;
};

template <typename Track>
Sequence back_and_forth(TrackedPoints& tracked, Track track) {
  const std::vector<FanFace> fans[2] = {disc(false), disc(true)};
  std::vector<uint32_t> faces[2];
  for (int d = 0; d < 2; ++d)
    for (const FanFace& face : fans[d]) faces[d].push_back(face.face);
  Sequence sequence;
  sequence.records.resize(kCollapsed);
  for (uint32_t i = 0; i < kCollapsed; ++i) {
    const int to = i % 2;
    const std::vector<uint32_t> from = i == 0 ? std::vector<uint32_t>{kHolder} : faces[1 - to];
    track(kPoints + i, from, fans[to], &sequence.records[i]);
  }
  for (const std::vector<uint32_t>& d : faces)
    for (const uint32_t f : d) sequence.lists.push_back(tracked.points_on(f));
  return sequence;
}

// The loop's thread takes parts of the collapses the tracking thread tracks while it waits
// (drain() here): the records and lists are those of the collapses tracked in turn. Whether it
// takes any depends on the scheduler (both threads must run at once): up to 10 tries for one
// where it did, each compared.
TEST(TrackingThread, TheLoopsThreadTakesPartsAndTheRecordsStayAsInTurn) {
  const std::vector<float> xyz = scattered_points();
  TrackedPoints in_turn_points;
  hold_every_point(in_turn_points, xyz);
  TrackedPoints::Scratch scratch;
  float floor = 0;
  const Sequence in_turn =
      back_and_forth(in_turn_points, [&](uint32_t v, const std::vector<uint32_t>& from,
                                         const std::vector<FanFace>& to, float* record) {
        *record = in_turn_points.track(v, from.data(), static_cast<int>(from.size()), to.data(),
                                       static_cast<int>(to.size()), false, 0.0, &floor, scratch);
      });
  uint64_t helped = 0;
  for (int attempt = 0; attempt < 10 && helped == 0; ++attempt) {
    TrackedPoints threaded_points;
    hold_every_point(threaded_points, xyz);
    TrackingThread tracking;
    if (!tracking.start(threaded_points, false, 0.0f)) {
      GTEST_SKIP() << "no thread to be had";
    }
    float drained = -1;
    const Sequence threaded =
        back_and_forth(threaded_points, [&](uint32_t v, const std::vector<uint32_t>& from,
                                            const std::vector<FanFace>& to, float* record) {
          tracking.push(v, from.data(), static_cast<int>(from.size()), to.data(),
                        static_cast<int>(to.size()), 0.0, record);
          // After the last, so that back_and_forth() reads the lists once all are tracked.
          if (v + 1 == kPoints + kCollapsed) drained = tracking.drain();
        });
    EXPECT_EQ(drained, floor);
    EXPECT_EQ(threaded.records, in_turn.records) << "attempt " << attempt;
    EXPECT_EQ(threaded.lists, in_turn.lists) << "attempt " << attempt;
    helped = tracking.parts_helped();
    tracking.stop();
  }
  // 20 collapses of 5,000 points, in parts of 256, while this thread waited in drain().
  EXPECT_GT(helped, 0u);
}

}  // namespace
}  // namespace pm::collapse_loop
