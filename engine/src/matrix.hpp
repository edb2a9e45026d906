// The small matrices of a 2D particle: a general 2 x 2 (deformation gradient, affine velocity)
// and a symmetric one (Kirchhoff stress). Plain values, row-major fields; and the particles'
// sets of them, one array per entry (structure of arrays), so that the loops over particles
// load and store each entry of eight particles as one vector.
#pragma once

#include <cstddef>
#include <vector>

namespace compaction {

struct Mat2 {
  double xx, xy, yx, yy;
};

struct Sym2 {
  double xx, xy, yy;
};

// n general 2 x 2 matrices, an array per entry.
struct Mat2Columns {
  std::vector<double> xx, xy, yx, yy;

  void assign(std::size_t n, const Mat2& m) {
    xx.assign(n, m.xx), xy.assign(n, m.xy), yx.assign(n, m.yx), yy.assign(n, m.yy);
  }
  Mat2 operator[](std::size_t k) const { return {xx[k], xy[k], yx[k], yy[k]}; }
  void set(std::size_t k, const Mat2& m) {
    xx[k] = m.xx, xy[k] = m.xy, yx[k] = m.yx, yy[k] = m.yy;
  }
  std::size_t size() const { return xx.size(); }
};

// n symmetric 2 x 2 matrices, an array per entry.
struct Sym2Columns {
  std::vector<double> xx, xy, yy;

  void assign(std::size_t n, const Sym2& m) {
    xx.assign(n, m.xx), xy.assign(n, m.xy), yy.assign(n, m.yy);
  }
  Sym2 operator[](std::size_t k) const { return {xx[k], xy[k], yy[k]}; }
  void set(std::size_t k, const Sym2& m) { xx[k] = m.xx, xy[k] = m.xy, yy[k] = m.yy; }
  std::size_t size() const { return xx.size(); }
};

}  // namespace compaction
