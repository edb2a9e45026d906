// Constitutive update of one 3D particle: the 2D model of plasticity.hpp (Saint Venant-Kirchhoff
// elasticity in Hencky strain, von Mises perfect plasticity; Blatny et al. 2022, Eqs. 1-2) with
// d = 3 in the paper's deviator s = tau - (1/d) tr(tau) I.
//
// With b = Fe Fe^T = Q diag(l_i) Q^T, the principal Hencky strains are e_i = 1/2 log l_i and
//   tau = Q diag(lambda tr(e) + 2 mu e_i) Q^T,  tr(e) = log J,
// so the deviator is s = 2 mu dev(e), q = sqrt(3/2 s:s) = sqrt(6) mu |dev(e)|, and yield
// happens at |dev(e)| = q_y / (sqrt(6) mu) (Material3D::dev_yield). The radial return keeps
// tr(e) = log J and scales dev(e) back to that norm: exact for perfect plasticity in Hencky
// strain (the flow direction dev(e) / |dev(e)| is fixed in principal space). The plastic
// strain increment is |dev(e_trial)| - dev_yield, the Frobenius norm of the cut (as 2D's
// (d_e - d_y) / sqrt(2)). The elastic correction is Fe <- Q diag(exp(dev_new_i - dev_i)) Q^T Fe
// (left stretch scaled, rotation kept).
//
// b is decomposed by cyclic Jacobi rotations (sym_eigen_3d.hpp): eigenvalues to a few ulp of
// |b| ~ 1, so strains to ~1e-16, also where two eigenvalues coincide, as in every state of a
// column compressed along y with x and z alike (the closed form by the characteristic cubic,
// Eigen's computeDirect, loses half its digits there: the uniaxial stress path of
// plasticity_3d_gtest came out 2e-9 off with it). bench/return_map_bench.cpp measures it
// against Eigen's iterative solver.
#pragma once

#include <Eigen/Dense>
#include <cmath>

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
inline double return_map_3d(Mat3& fe, const Material3D& m, Mat3& tau) {
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

}  // namespace compaction
