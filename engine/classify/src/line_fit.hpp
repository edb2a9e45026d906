// Least-squares straight line y = a + b x through points added one at a time (the speed fit of
// a front's leading edge, the trend under the top stress's harmonic).
#pragma once

#include <algorithm>
#include <cmath>

namespace compaction::classify {

struct LineFit {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;  // the sums of the normal equations

  void add(double x, double y) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  // The slope is defined when the x values differ (and there are two or more).
  bool has_slope() const { return n * sxx - sx * sx > 0; }
  double slope() const { return (n * sxy - sx * sy) / (n * sxx - sx * sx); }
  double intercept(double slope) const { return (sy - slope * sx) / n; }
  // Standard error of the slope from the scatter of the points about the line (needs three or
  // more points): sqrt(residual variance / sum (x - mean x)^2).
  double slope_standard_error() const {
    const double b = slope(), a = intercept(b);
    const double residuals = syy - 2 * a * sy - 2 * b * sxy + n * a * a + 2 * a * b * sx + b * b * sxx;
    const double spread = sxx - sx * sx / n;
    return n > 2 && spread > 0 ? std::sqrt(std::max(residuals, 0.0) / (n - 2) / spread) : NAN;
  }
};

}  // namespace compaction::classify
