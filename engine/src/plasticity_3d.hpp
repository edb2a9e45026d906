// Constitutive update of one 3D particle: the 2D model of plasticity.hpp (Saint Venant-Kirchhoff
// elasticity in Hencky strain, von Mises perfect plasticity; Blatny et al. 2022, Eqs. 1-2) with
// d = 3 in the paper's deviator s = tau - (1/d) tr(tau) I.
//
// With b = Fe Fe^T, the Hencky strain is e = 1/2 log b, tr(e) = log J, and
//   tau = lambda tr(e) I + 2 mu e,
// so the deviator is s = 2 mu dev(e), q = sqrt(3/2 s:s) = sqrt(6) mu |dev(e)|, and yield
// happens at |dev(e)| = q_y / (sqrt(6) mu) (Material3D::dev_yield). The radial return keeps
// tr(e) = log J and scales dev(e) back to that norm: exact for perfect plasticity in Hencky
// strain (the flow direction dev(e) / |dev(e)| is fixed in principal space). The plastic
// strain increment is |dev(e_trial)| - dev_yield, the Frobenius norm of the cut (as 2D's
// (d_e - d_y) / sqrt(2)). The elastic correction is Fe <- exp(dev_new - dev) Fe (left stretch
// scaled, rotation kept).
//
// Two ways to the same update:
// - return_map_3d_series, without a decomposition: e = atanh(Z) with Z = (b - I)(b + I)^-1
//   (log b = 2 atanh Z) and the correction exp((s - 1) dev(e)) by their matrix power series
//   (sym3_series.hpp), b - I formed from G = Fe - I as G + G^T + G G^T so that a strain of 1e-6
//   keeps its digits. It holds for the small elastic strains of these solids (|Z| < 1/4,
//   Hencky strains up to about 0.25) and per-step plastic cuts below 2^-5, and reports whether
//   it did.
// - return_map_3d_principal, in principal space: b = Q diag(l_i) Q^T by cyclic Jacobi rotations
//   (sym_eigen_3d.hpp), e_i = 1/2 log l_i; eigenvalues to a few ulp of |b| ~ 1, so strains to
//   ~1e-16, also where two eigenvalues coincide, as in every state of a column compressed along
//   y with x and z alike (the closed form by the characteristic cubic, Eigen's computeDirect,
//   loses half its digits there: the uniaxial stress path of plasticity_3d_gtest came out 2e-9
//   off with it). It takes any state; it costs about four times the series per call
//   (bench/results/return_map_bench.md).
// return_map_3d runs the series and hands the state to the principal update where the series
// do not hold; the two agree to round-off (plasticity_3d_gtest).
#pragma once

#include <Eigen/Dense>
#include <cmath>

#include "plasticity.hpp"  // log_near_one
#include "sym3_series.hpp"
#include "sym_eigen_3d.hpp"

namespace compaction {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

struct Material3D {
  double lambda;     // first Lame parameter                                  [N/m^2]
  double mu;         // shear modulus                                          [N/m^2]
  double dev_yield;  // norm of the deviatoric Hencky strain at yield, q_y / (sqrt(6) mu) [-]
};

// Updates the elastic deformation gradient fe in place (return mapping), writes the Kirchhoff
// stress and returns the plastic Hencky strain increment (0 when elastic). Returns NaN when
// J = det(fe) <= 0 or fe is not finite (the caller flags the run unstable).
inline double return_map_3d_principal(Mat3& fe, const Material3D& m, Mat3& tau) {
  const double J = fe.determinant();
  if (!(J > 0.0) || !fe.allFinite()) return std::nan("");
  const SymEigen3 eig = sym_eigen_3d(fe * fe.transpose());
  const Vec3& l = eig.l;
  const Mat3& q = eig.q;
  const double log_j = std::log(J);  // tr(e), from det(Fe) rather than the rounded l_i
  Vec3 e(0.5 * std::log(l(0)), 0.5 * std::log(l(1)), 0.5 * std::log(l(2)));
  const Vec3 dev = e.array() - e.sum() / 3.0;
  const double norm = dev.norm();
  double plastic = 0.0;
  Vec3 dev_new = dev;
  if (norm > m.dev_yield) {
    dev_new = dev * (m.dev_yield / norm);
    plastic = norm - m.dev_yield;
    const Vec3 scale = (dev_new - dev).array().exp();
    fe = (q * scale.asDiagonal() * q.transpose() * fe).eval();
  }
  // lambda tr(e) + 2 mu e_i with e_i = tr(e) / 3 + dev_i
  const Vec3 t = ((m.lambda + 2.0 * m.mu / 3.0) * log_j + 2.0 * m.mu * dev_new.array()).matrix();
  tau = q * t.asDiagonal() * q.transpose();
  return plastic;
}

// A symmetric matrix of the series as the particles' Mat3.
inline Mat3 as_matrix(const Sym3& a) {
  Mat3 m;
  m << a.xx, a.xy, a.xz, a.xy, a.yy, a.yz, a.xz, a.yz, a.zz;
  return m;
}

// The same update by the power series: returns false, with fe and tau untouched, where they do
// not hold (|Z|_F >= 1/4, a plastic cut of 2^-5 or more, J <= 0 or a state that is not finite);
// else writes fe, tau and the plastic increment and returns true.
[[gnu::always_inline]] inline bool return_map_3d_series(Mat3& fe, const Material3D& m, Mat3& tau,
                                                       double& plastic) {
  const double J = fe.determinant();
  if (!(J > 0.0) || !fe.allFinite()) return false;
  // b - I = G + G^T + G G^T with G = Fe - I (the diagonal's subtraction is exact near 1)
  const Mat3 g = fe - Mat3::Identity();
  const Sym3 a{2 * g(0, 0) + g.row(0).squaredNorm(), 2 * g(1, 1) + g.row(1).squaredNorm(),
               2 * g(2, 2) + g.row(2).squaredNorm(), g(0, 1) + g(1, 0) + g.row(0).dot(g.row(1)),
               g(0, 2) + g(2, 0) + g.row(0).dot(g.row(2)),
               g(1, 2) + g(2, 1) + g.row(1).dot(g.row(2))};
  const Sym3 z = commuting_solve(a, plus_identity(a, 2.0));  // (b - I)(b + I)^-1
  const double z2 = frobenius2(z);
  if (!(z2 < kSym3LongSeries * kSym3LongSeries)) return false;
  const Sym3 e = z2 < kSym3TinySeries * kSym3TinySeries     ? atanh_sym3_tiny(z)
                 : z2 < kSym3ShortSeries * kSym3ShortSeries ? atanh_sym3_short(z)
                                                            : atanh_sym3_long(z);
  const double log_j = log_near_one(J);  // tr(e), from det(Fe) as return_map_3d_principal
  const Sym3 dev = plus_identity(e, -trace(e) / 3.0);
  const double norm = std::sqrt(frobenius2(dev));
  double scale = 1.0, cut = 0.0;
  if (norm > m.dev_yield) {
    cut = norm - m.dev_yield;
    if (!(cut < kSym3ShortSeries)) return false;
    scale = m.dev_yield / norm;
    const Sym3 k = (scale - 1.0) * dev;  // dev_new - dev, of norm `cut`
    const Sym3 x = cut < kSym3TinyExp ? exp_sym3_tiny(k) : exp_sym3_short(k);
    fe = (as_matrix(x) * fe).eval();
  }
  // lambda tr(e) + 2 mu e with e = tr(e) / 3 I + dev_new
  const Sym3 t = plus_identity((2.0 * m.mu * scale) * dev, (m.lambda + 2.0 * m.mu / 3.0) * log_j);
  tau = as_matrix(t);
  plastic = cut;
  return true;
}

// The return mapping of one particle: by the series where they hold, else in principal space
// (see the top of this file). Returns what return_map_3d_principal returns.
[[gnu::always_inline]] inline double return_map_3d(Mat3& fe, const Material3D& m, Mat3& tau) {
  double plastic;
  if (return_map_3d_series(fe, m, tau, plastic)) return plastic;
  return return_map_3d_principal(fe, m, tau);
}

}  // namespace compaction
