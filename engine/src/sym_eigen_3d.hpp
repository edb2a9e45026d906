// Eigen-decomposition of a symmetric 3 x 3 matrix by cyclic Jacobi rotations, for the 3D return
// mapping (plasticity_3d.hpp), where it decomposes b = Fe Fe^T once per particle and step.
//
// Why Jacobi: it is accurate where the closed form (Eigen's computeDirect, roots of the
// characteristic cubic by acos) is not. Two equal eigenvalues, which every state of a column
// compressed along y with x and z alike has, cost the closed form half its digits, and cost
// Jacobi nothing (a rotation in a degenerate plane is as good as any). Each rotation zeroes its
// element with the stable formula of Rutishauser, so eigenvalues come out to a few ulp of |A|
// and the eigenvectors orthonormal to round-off. The column's b is nearly diagonal in the
// grid's axes (compression along y, small rotations), so the off-diagonal part shrinks
// quadratically from the first sweep; two or three sweeps reach round-off, the last of them
// by rotations of small angles that cost one division each.
// tests/engine/sym_eigen_3d_gtest.cpp checks it against Eigen's iterative solver
// (SelfAdjointEigenSolver::compute) over random and degenerate matrices;
// bench/return_map_bench.cpp measures both.
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace compaction {

// A = Q diag(l) Q^T with Q orthonormal (columns the eigenvectors); the eigenvalues in no
// particular order.
struct SymEigen3 {
  Eigen::Vector3d l;
  Eigen::Matrix3d q;
};

// Sweeps stop when every off-diagonal element is below kJacobiTolerance times the diagonal's
// largest magnitude: its effect on the eigenvalues is then its square, far below an ulp, and on
// the eigenvectors an angle of that size. kJacobiMaxSweeps bounds the loop for non-finite input
// (a finite symmetric 3 x 3 converges in at most five or six).
inline constexpr double kJacobiTolerance = 1e-17;
inline constexpr int kJacobiMaxSweeps = 12;

// The rotation of cyclic Jacobi that zeroes a[p][q]: t = tan of its angle, the root of
// t^2 + 2 theta t - 1 = 0 of smaller magnitude (Rutishauser), theta = (a_qq - a_pp) / (2 a_pq).
// Where a_pq is small against the gap (|u| = |a_pq / (a_qq - a_pp)| < 5e-5, as in the last sweep),
// t = u - u^3 and c = 1 - t^2 / 2 are exact to 2u^4 < 1.3e-17 and cost one division instead of
// two square roots and three.
struct JacobiRotation {
  double t, c, s;
};
inline JacobiRotation jacobi_rotation(double app, double aqq, double apq) {
  const double d = aqq - app;
  if (std::fabs(apq) < 5e-5 * std::fabs(d)) {
    const double u = apq / d, t = u - u * u * u, c = 1.0 - 0.5 * t * t;
    return {t, c, t * c};
  }
  const double theta = d / (2.0 * apq);
  const double t = std::fabs(theta) > 1e150  // theta^2 would overflow
                       ? 0.5 / theta
                       : std::copysign(1.0, theta) /
                             (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
  const double c = 1.0 / std::sqrt(t * t + 1.0);
  return {t, c, t * c};
}

inline SymEigen3 sym_eigen_3d(const Eigen::Matrix3d& a_in) {
  double a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = a_in(i, j);
  Eigen::Matrix3d v = Eigen::Matrix3d::Identity();
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < kJacobiMaxSweeps; ++sweep) {
    const double scale =
        std::fmax(std::fabs(a[0][0]), std::fmax(std::fabs(a[1][1]), std::fabs(a[2][2])));
    const double limit = kJacobiTolerance * scale;
    if (std::fabs(a[0][1]) <= limit && std::fabs(a[0][2]) <= limit && std::fabs(a[1][2]) <= limit)
      break;
    for (const auto& pq : kPairs) {
      const int p = pq[0], q = pq[1], r = 3 - p - q;
      const double apq = a[p][q];
      if (apq == 0.0) continue;
      const auto [t, c, s] = jacobi_rotation(a[p][p], a[q][q], apq);
      a[p][p] -= t * apq;
      a[q][q] += t * apq;
      a[p][q] = a[q][p] = 0.0;
      const double arp = a[r][p], arq = a[r][q];
      a[r][p] = a[p][r] = c * arp - s * arq;
      a[r][q] = a[q][r] = s * arp + c * arq;
      for (int k = 0; k < 3; ++k) {
        const double vkp = v(k, p), vkq = v(k, q);
        v(k, p) = c * vkp - s * vkq;
        v(k, q) = s * vkp + c * vkq;
      }
    }
  }
  return {Eigen::Vector3d(a[0][0], a[1][1], a[2][2]), v};
}

}  // namespace compaction
