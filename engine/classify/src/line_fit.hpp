// Least-squares straight line y = a + b x through points added one at a time (the speed fit of
// a front's leading edge, the trend under the top stress's harmonic).
#pragma once

namespace compaction::classify {

struct LineFit {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;  // the sums of the normal equations

  void add(double x, double y) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  // The slope is defined when the x values differ (and there are two or more).
  bool has_slope() const { return n * sxx - sx * sx > 0; }
  double slope() const { return (n * sxy - sx * sy) / (n * sxx - sx * sx); }
  double intercept(double slope) const { return (sy - slope * sx) / n; }
};

}  // namespace compaction::classify
