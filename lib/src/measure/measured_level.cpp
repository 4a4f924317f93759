// Selection of a level of detail by measured error: a galloping search (Bentley and Yao
// 1976, "An almost optimal algorithm for unbounded searching") from the recorded errors'
// guess, then bisection, in face count, over Metro measurements (Cignoni et al. 1998).
#include "pm/measured_level.h"
#include "core/no_throw.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "pm/lod.h"

namespace pm {
namespace {

class LevelSearch {
 public:
  LevelSearch(const ProgressiveMesh& pm, double max_hausdorff, const MeasuredLevelOptions& options)
      : pm_(pm), max_hausdorff_(max_hausdorff), options_(options) {
    faces_.resize(pm.splits.size() + 1);
    faces_[0] = faces_at_level(pm, 0);
    for (std::size_t k = 0; k < pm.splits.size(); ++k)
      faces_[k + 1] = faces_[k] + pm.splits[k].new_face_count();
  }

  Status run(MeasuredLevel& out) {
    const std::size_t full = pm_.splits.size();
    original_ = extract_level(pm_, full);
    // Invariant: `fits_` measures within the tolerance; `exceeds_`, when known, is a coarser
    // level that does not. Full detail is the original itself: distance zero.
    fits_ = {full, SurfaceDistance{}};
    fits_.distance.diagonal = bounding_box_diagonal(original_.positions);
    exceeds_.reset();

    const std::size_t guess = std::min(level_for_error(pm_, max_hausdorff_), full);
    if (guess < full)
      if (Status s = try_level(guess); !s) return s;

    // Gallop away from the guess until the answer is bracketed.
    while (!exceeds_ && fits_.level > 0) {
      const std::size_t coarser = std::min(
          level_with_faces(double(faces_[fits_.level]) / kGallopFactor), fits_.level - 1);
      if (Status s = try_level(coarser); !s) return s;
    }
    while (exceeds_ && fits_.level == full && exceeds_->level + 1 < full) {
      const std::size_t finer = std::max(
          level_with_faces(double(faces_[exceeds_->level]) * kGallopFactor), exceeds_->level + 1);
      if (finer >= full) break;  // full detail fits by definition
      if (Status s = try_level(finer); !s) return s;
    }
    // Bisect the bracket, geometrically in faces, down to the requested ratio.
    while (exceeds_ && fits_.level - exceeds_->level > 1 &&
           double(faces_[fits_.level]) > options_.face_ratio * double(faces_[exceeds_->level])) {
      const double middle =
          std::sqrt(double(faces_[exceeds_->level]) * double(faces_[fits_.level]));
      const std::size_t level =
          std::clamp(level_with_faces(middle), exceeds_->level + 1, fits_.level - 1);
      if (Status s = try_level(level); !s) return s;
    }
    out.level = fits_.level;
    out.distance = fits_.distance;
    out.measurements = measurements_;
    return Status::ok();
  }

 private:
  static constexpr double kGallopFactor = 1.5;

  struct Measured {
    std::size_t level = 0;
    SurfaceDistance distance;
  };

  // The coarsest level with at least `faces` faces (the finest level if none).
  std::size_t level_with_faces(double faces) const {
    const auto at_least = std::lower_bound(faces_.begin(), faces_.end(), std::ceil(faces),
                                           [](std::size_t f, double x) { return double(f) < x; });
    return std::min<std::size_t>(at_least - faces_.begin(), faces_.size() - 1);
  }

  Status try_level(std::size_t level) {
    Measured m{level, {}};
    if (Status s = measure_surface_distance(original_, extract_level(pm_, level),
                                            options_.distance, m.distance);
        !s)
      return s;
    ++measurements_;
    if (m.distance.hausdorff <= max_hausdorff_) {
      if (level < fits_.level) fits_ = m;
    } else if (!exceeds_ || level > exceeds_->level) {
      exceeds_ = m;
    }
    // Measured error is not strictly monotone: a coarser level may fit where a finer one
    // did not. Keep the bracket ordered by forgetting the failure it contradicts.
    if (exceeds_ && exceeds_->level >= fits_.level) exceeds_.reset();
    return Status::ok();
  }

  const ProgressiveMesh& pm_;
  const double max_hausdorff_;
  const MeasuredLevelOptions& options_;
  std::vector<std::size_t> faces_;  // faces at each level
  Mesh original_;
  Measured fits_;
  std::optional<Measured> exceeds_;
  std::size_t measurements_ = 0;
};

}  // namespace

Status level_for_measured_error(const ProgressiveMesh& pm, double max_hausdorff,
                                const MeasuredLevelOptions& options, MeasuredLevel& out) {
  return detail::no_throw([&]() -> Status {
    if (!(max_hausdorff >= 0) || !std::isfinite(max_hausdorff))
      return Status(ErrorCode::kInvalidArgument, "the error tolerance must be a finite number >= 0");
    if (!(options.face_ratio > 1) || !std::isfinite(options.face_ratio))
      return Status(ErrorCode::kInvalidArgument, "the face ratio must be a finite number > 1");
    if (Status valid = validate(pm); !valid)
      return Status(ErrorCode::kInvalidArgument, "invalid progressive mesh: " + valid.message());
    return LevelSearch(pm, max_hausdorff, options).run(out);
  });
}

}  // namespace pm
