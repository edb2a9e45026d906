// Quadratic B-spline kernel on a 3 x 3 x 3 stencil: the tensor product of the 1D weights of
// kernel.hpp, N(x) N(y) N(z), and its gradient (N'(x) N(y) N(z), N(x) N'(y) N(z), ...).
//
// Stencil node (a, b, c) (offsets along x, y, z) is entry s = (b * 3 + c) * 3 + a: y outermost,
// x innermost, the order of the 3D grid's node array (nodes[(j * nz + k) * nx + i]), so that a
// loop over s walks the nodes in memory order. The MLS gradient needs no dw: it is
// kInverseInertia w (x_i - x_p) / dx^2, as in 2D (D = dx^2 / 4 I in every direction).
#pragma once

#include "kernel.hpp"

namespace compaction::kernel {

struct Stencil3D {
  Stencil1D x, y, z;  // the 1D stencils (base node, offset, weights, derivatives)
  double w[27];       // weights, sum to 1
  double dw[27][3];   // gradient (d/dx, d/dy, d/dz) in units of 1/dx
};

// The stencil of a particle at grid coordinates (xg, yg, zg) (position / dx + ghost offset).
inline Stencil3D quadratic_3d(double xg, double yg, double zg) {
  Stencil3D s;
  s.x = quadratic(xg);
  s.y = quadratic(yg);
  s.z = quadratic(zg);
  for (int b = 0; b < 3; ++b) {
    for (int c = 0; c < 3; ++c) {
      const double wyz = s.y.w[b] * s.z.w[c];
      const double dyz = s.y.dw[b] * s.z.w[c], ydz = s.y.w[b] * s.z.dw[c];
      for (int a = 0; a < 3; ++a) {
        const int k = (b * 3 + c) * 3 + a;
        s.w[k] = s.x.w[a] * wyz;
        s.dw[k][0] = s.x.dw[a] * wyz;
        s.dw[k][1] = s.x.w[a] * dyz;
        s.dw[k][2] = s.x.w[a] * ydz;
      }
    }
  }
  return s;
}

}  // namespace compaction::kernel
