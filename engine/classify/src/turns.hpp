// Turns of a path with hysteresis (the centroid of a front, the band in the velocity map).
//
// Once a path has set off in a direction, it is followed to its extreme; it turns there when it
// has come back from the extreme by at least `turn_travel`. Smaller wiggles are no turns, and
// the turn is placed at the extreme, not where it was recognised. When and in which direction
// a path sets off is the caller's rule.
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>

namespace compaction::classify {

struct Turn {
  std::size_t index = 0;  // the point of the extreme
  double at = 0.0;        // its value
  int came = 0;           // the direction the path came from: +1 up (a turn at a high point),
                          // -1 down
};

class TurnFollower {
 public:
  explicit TurnFollower(double turn_travel) : turn_travel_(turn_travel) {}

  bool moving() const { return dir_ != 0; }
  // The path sets off in dir (+1 up, -1 down) from point i with value x.
  void set_off(int dir, std::size_t i, double x) {
    dir_ = dir;
    extreme(i, x);
  }
  // The next point of a moving path; a turn when it comes back far enough from the extreme
  // (then the path goes on in the other direction from this point).
  std::optional<Turn> next(std::size_t i, double x) {
    if ((dir_ < 0 && x < ext_) || (dir_ > 0 && x > ext_)) {
      extreme(i, x);
      return std::nullopt;
    }
    if (!(std::abs(x - ext_) >= turn_travel_)) return std::nullopt;
    const Turn t{ext_i_, ext_, dir_};
    dir_ = -dir_;
    extreme(i, x);
    return t;
  }

 private:
  void extreme(std::size_t i, double x) {
    ext_i_ = i;
    ext_ = x;
  }
  double turn_travel_;
  int dir_ = 0;
  std::size_t ext_i_ = 0;
  double ext_ = 0.0;
};

}  // namespace compaction::classify
