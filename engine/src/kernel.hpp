// Quadratic B-spline interpolation kernel (support 3 grid cells, C1).
//
// For a particle at grid coordinate xg (position / dx + ghost offset), the stencil starts at
// node base = floor(xg - 0.5) and the particle sits at fx = xg - base in [0.5, 1.5) from it.
// Node base + k is at distance (k - fx) dx. Weights (Steffen et al. 2008, Eq. 3; Jiang et al.
// 2016, Eq. 123):  N(u) = 3/4 - u^2 (|u| < 1/2),  1/2 (3/2 - |u|)^2 (1/2 <= |u| < 3/2).
#pragma once

#include <cmath>

namespace compaction::kernel {

struct Stencil1D {
  int base;     // first node of the 3-node stencil
  double fx;    // particle offset from that node, in cells, in [0.5, 1.5)
  double w[3];  // weights, sum to 1
  double dw[3]; // derivatives dN/dx in units of 1/dx (gradient = bspline; MLS does without)
};

// xg >= -0.5 always (ghost nodes and the stability checks keep particles there), so
// floor(xg - 0.5) is a truncation of xg + 0.5 minus one: no libm call in the hot loops.
inline Stencil1D quadratic(double xg) {
  Stencil1D s;
  s.base = static_cast<int>(xg + 0.5) - 1;
  s.fx = xg - s.base;
  const double fx = s.fx;
  s.w[0] = 0.5 * (1.5 - fx) * (1.5 - fx);
  s.w[1] = 0.75 - (fx - 1.0) * (fx - 1.0);
  s.w[2] = 0.5 * (fx - 0.5) * (fx - 0.5);
  s.dw[0] = fx - 1.5;
  s.dw[1] = -2.0 * (fx - 1.0);
  s.dw[2] = fx - 0.5;
  return s;
}

// For the quadratic B-spline the APIC inertia tensor is D = dx^2 / 4 I (Jiang et al. 2015), so
// the MLS gradient of a weight is w * D^-1 (x_i - x_p) = 4 w (x_i - x_p) / dx^2.
constexpr double kInverseInertia = 4.0;  // D^-1 in units of 1/dx^2

}  // namespace compaction::kernel
