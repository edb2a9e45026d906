// The Jacobi eigen-decomposition of a symmetric 3 x 3 (sym_eigen_3d.hpp) against Eigen's
// iterative solver (SelfAdjointEigenSolver::compute, backward stable) as the oracle: random
// matrices of every spread of eigenvalues, the degenerate cases (two or three equal eigenvalues,
// a diagonal matrix, the zero matrix), the column's near-diagonal b, and entries near overflow
// and underflow. Tolerance: a few ulp of |A| for the eigenvalues and the reconstruction
// Q diag(l) Q^T = A, Q orthonormal to a few ulp; both solvers are backward stable, so the
// eigenvalues agree to their round-off (32 ulp of |A| allows for the two).
#include "sym_eigen_3d.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "splitmix64.hpp"

namespace compaction {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

constexpr double kUlp = std::numeric_limits<double>::epsilon();

Mat3 random_rotation(SplitMix64& rng) {
  const double u1 = rng.uniform(), u2 = 2 * M_PI * rng.uniform(), u3 = 2 * M_PI * rng.uniform();
  const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                             std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
  return q.normalized().toRotationMatrix();
}

Vec3 sorted(Vec3 v) {
  std::sort(v.data(), v.data() + 3);
  return v;
}

// One matrix: eigenvalues against the oracle, the reconstruction, the orthonormality. |A| is the
// largest entry's magnitude (the Frobenius norm's squares would underflow at 1e-300).
void expect_decomposes(const Mat3& a, double tol_ulp = 32) {
  const SymEigen3 e = sym_eigen_3d(a);
  const double norm = std::max(a.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  const Eigen::SelfAdjointEigenSolver<Mat3> oracle(a);
  EXPECT_LE((sorted(e.l) - oracle.eigenvalues()).cwiseAbs().maxCoeff(), tol_ulp * kUlp * norm)
      << "A =\n" << a;
  EXPECT_LE((e.q * e.l.asDiagonal() * e.q.transpose() - a).cwiseAbs().maxCoeff(),
            tol_ulp * kUlp * norm) << "A =\n" << a;
  EXPECT_LE((e.q.transpose() * e.q - Mat3::Identity()).cwiseAbs().maxCoeff(), tol_ulp * kUlp)
      << "A =\n" << a;
}

TEST(SymEigen3dGtest, RandomMatricesOfEverySpreadMatchEigen) {
  SplitMix64 rng(11);
  for (int i = 0; i < 20000; ++i) {
    // Eigenvalues of magnitude 10^[-3, 3], some negative, rotated at random.
    Vec3 l;
    for (int k = 0; k < 3; ++k)
      l(k) = (rng.uniform() < 0.2 ? -1 : 1) * std::pow(10.0, 6 * rng.uniform() - 3);
    const Mat3 r = random_rotation(rng);
    const Mat3 a = r * l.asDiagonal() * r.transpose();
    expect_decomposes(0.5 * (a + a.transpose()));
  }
}

TEST(SymEigen3dGtest, RepeatedEigenvaluesAndDiagonalMatrices) {
  SplitMix64 rng(12);
  for (int i = 0; i < 5000; ++i) {
    const double x = 0.5 + rng.uniform(), y = 0.5 + rng.uniform();
    const Mat3 r = random_rotation(rng);
    Mat3 a = r * Vec3(x, x, y).asDiagonal() * r.transpose();  // two equal
    expect_decomposes(0.5 * (a + a.transpose()));
    a = r * Vec3(x, x, x).asDiagonal() * r.transpose();  // three equal
    expect_decomposes(0.5 * (a + a.transpose()));
    expect_decomposes(Vec3(x, y, x).asDiagonal().toDenseMatrix());
  }
  expect_decomposes(Mat3::Zero());
  expect_decomposes(Mat3::Identity());
}

// b of the column: compression along y with x and z alike, small shears and rotations (the
// states return_map_3d meets most).
TEST(SymEigen3dGtest, NearlyDiagonalColumnStates) {
  SplitMix64 rng(13);
  for (int i = 0; i < 20000; ++i) {
    Mat3 f = Vec3(1.0, 1.0 - 0.3 * rng.uniform(), 1.0).asDiagonal();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (r != c) f(r, c) += std::pow(10.0, -12 * rng.uniform()) * (rng.uniform() - 0.5);
    expect_decomposes(f * f.transpose());
  }
}

TEST(SymEigen3dGtest, ScalesNearOverflowAndUnderflow) {
  SplitMix64 rng(14);
  for (const double scale : {1e-150, 1e-300, 1e150, 1e300}) {
    for (int i = 0; i < 200; ++i) {
      const Mat3 r = random_rotation(rng);
      const Vec3 l(rng.uniform(), rng.uniform() + 0.1, -rng.uniform());
      const Mat3 a = r * (scale * l).asDiagonal() * r.transpose();
      expect_decomposes(0.5 * (a + a.transpose()));
    }
  }
}

}  // namespace
}  // namespace compaction
