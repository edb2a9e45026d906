// The small matrices of a 2D particle: a general 2 x 2 (deformation gradient, affine velocity)
// and a symmetric one (Kirchhoff stress). Plain values, row-major fields.
#pragma once

namespace compaction {

struct Mat2 {
  double xx, xy, yx, yy;
};

struct Sym2 {
  double xx, xy, yy;
};

}  // namespace compaction
