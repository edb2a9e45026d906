// Constitutive update of one particle: Saint Venant-Kirchhoff elasticity in Hencky strain with
// von Mises perfect plasticity (Blatny et al. 2022, Eqs. 1-2), return mapping in closed form.
//
// Convention (the paper's): yield when sqrt(3/2 s:s) > q_y, s = tau - (1/d) tr(tau) I, d = 2.
// In 2D with principal Hencky strains e1 >= e2 and d_e = e1 - e2:
//   tau_i = lambda (e1 + e2) + 2 mu e_i,  s = +-mu d_e,  s:s = 2 mu^2 d_e^2,
//   q = sqrt(3/2 s:s) = sqrt(3) mu d_e,
// so yield happens at d_e = q_y / (sqrt(3) mu). The radial return keeps e1 + e2 = log J and
// scales d_e back to the yield surface; this is exact for perfect plasticity in Hencky strain
// (the flow direction is fixed in principal space). The plastic strain increment is the
// deviatoric cut (+-(d_e - d_y)/2 on the principal axes), of magnitude (d_e - d_y) / sqrt(2).
//
// No eigen solver: with b = Fe Fe^T = [[a, c], [c, e]] and r = sqrt(((a - e)/2)^2 + c^2),
//   eigenvalues l1,2 = (a + e)/2 +- r, l1 l2 = J^2, and the projector difference
//   n1 n1^T - n2 n2^T = N = [[(a - e)/2, c], [c, -(a - e)/2]] / r,
// so tau = (lambda + mu) log J I + mu d_e N and the elastic correction is
//   Fe <- (cosh(k) I - sinh(k) N) Fe  with k = (d_e - d_y) / 2.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "matrix.hpp"

namespace compaction {

struct Material {
  double lambda;   // first Lame parameter                     [N/m]
  double mu;       // shear modulus                             [N/m]
  double d_yield;  // principal strain difference at yield, q_y / (sqrt(3) mu) [-]
};

// atanh(z) by its series z + z^3/3 + ... + z^11/11, for |z| < 2^-5 (the first omitted term is
// below 1e-19 of the result). Estrin's scheme: three independent pairs, so the polynomial is a
// short dependency chain.
inline double atanh_series_short(double z) {
  const double z2 = z * z, z4 = z2 * z2;
  const double p01 = 1.0 + z2 * (1.0 / 3), p23 = 1.0 / 5 + z2 * (1.0 / 7),
               p45 = 1.0 / 9 + z2 * (1.0 / 11);
  return z * (p01 + z4 * (p23 + z4 * p45));
}

// The same series to z^27, for |z| < 1/4 (the first omitted term, z^29/29, is below 5e-19 of
// the result): the elastic strains of strong solids (R up to 0.1 yields at strain differences
// of 0.15).
inline double atanh_series_long(double z) {
  const double z2 = z * z;
  double p = 1.0 / 27;
  p = 1.0 / 25 + z2 * p, p = 1.0 / 23 + z2 * p, p = 1.0 / 21 + z2 * p, p = 1.0 / 19 + z2 * p;
  p = 1.0 / 17 + z2 * p, p = 1.0 / 15 + z2 * p, p = 1.0 / 13 + z2 * p, p = 1.0 / 11 + z2 * p;
  p = 1.0 / 9 + z2 * p, p = 1.0 / 7 + z2 * p, p = 1.0 / 5 + z2 * p, p = 1.0 / 3 + z2 * p;
  return z * (1.0 + z2 * p);
}

inline constexpr double kShortSeries = 0.03125, kLongSeries = 0.25;

// atanh(z) to full double precision, fast for the small arguments of elastic strains: the
// series above where they hold, std::atanh beyond.
inline double atanh_small(double z) {
  const double a = std::abs(z);
  if (a < kShortSeries) return atanh_series_short(z);
  if (a < kLongSeries) return atanh_series_long(z);
  return std::atanh(z);
}

// log(x) = 2 atanh((x - 1) / (x + 1)): one division and a short polynomial near x = 1.
inline double log_near_one(double x) { return 2.0 * atanh_small((x - 1.0) / (x + 1.0)); }

// Updates the elastic deformation gradient fe in place (return mapping), writes the Kirchhoff
// stress and returns the plastic Hencky strain increment magnitude (0 when elastic). Returns
// NaN when J = det(fe) <= 0 (the caller flags the run unstable).
inline double return_map(Mat2& fe, const Material& m, Sym2& tau) {
  const double J = fe.xx * fe.yy - fe.xy * fe.yx;
  if (!(J > 0.0)) return std::nan("");
  const double a = fe.xx * fe.xx + fe.xy * fe.xy;  // b = Fe Fe^T
  const double c = fe.xx * fe.yx + fe.xy * fe.yy;
  const double e = fe.yx * fe.yx + fe.yy * fe.yy;
  const double h = 0.5 * (a - e);
  const double r = std::sqrt(h * h + c * c);
  // e1 - e2 = 1/2 log(l1 / l2) = atanh((l1 - l2) / (l1 + l2)) = atanh(2 r / (a + e)):
  // one division, accurate even when l1 ~ l2.
  double d_e = atanh_small(2.0 * r / (a + e));
  const double inv_r = r > 0.0 ? 1.0 / r : 0.0;   // N = 0 for an isotropic state (d_e = 0)
  const Sym2 n{h * inv_r, c * inv_r, -h * inv_r};

  double plastic = 0.0;
  if (d_e > m.d_yield) {
    const double k = 0.5 * (d_e - m.d_yield);
    const double ep = std::exp(k), em = 1.0 / ep;
    const double ch = 0.5 * (ep + em), sh = 0.5 * (ep - em);
    const Mat2 f = fe;  // Fe <- (ch I - sh N) Fe
    fe.xx = (ch - sh * n.xx) * f.xx - sh * n.xy * f.yx;
    fe.xy = (ch - sh * n.xx) * f.xy - sh * n.xy * f.yy;
    fe.yx = -sh * n.xy * f.xx + (ch - sh * n.yy) * f.yx;
    fe.yy = -sh * n.xy * f.xy + (ch - sh * n.yy) * f.yy;
    plastic = (d_e - m.d_yield) * 0.70710678118654752440;  // / sqrt(2)
    d_e = m.d_yield;
  }
  const double p = (m.lambda + m.mu) * log_near_one(J);
  tau.xx = p + m.mu * d_e * n.xx;
  tau.xy = m.mu * d_e * n.xy;
  tau.yy = p + m.mu * d_e * n.yy;
  return plastic;
}

// A block of particles for return_map_block, structure of arrays.
inline constexpr std::size_t kBlock = 64;

struct ReturnMapBlock {
  alignas(64) double fxx[kBlock], fxy[kBlock], fyx[kBlock], fyy[kBlock];  // trial Fe in
  alignas(64) double exx[kBlock], exy[kBlock], eyx[kBlock], eyy[kBlock];  // Fe out
  alignas(64) double txx[kBlock], txy[kBlock], tyy[kBlock];  // Kirchhoff stress out
  alignas(64) double plastic[kBlock];                         // plastic increment out
  alignas(64) double redo[kBlock];  // 1: out of the series' range, run return_map instead
};

// Some particle of the block was handed back.
inline bool any_redo(const ReturnMapBlock& b, std::size_t n) {
  double any = 0.0;
  for (std::size_t i = 0; i < n; ++i) any += b.redo[i];
  return any != 0.0;
}

// The same return mapping for a block of particles at once, written so that the compiler
// vectorises it across particles (no branch, no library call; checked with
// -fopt-info-vec-optimized): sqrt needs -fno-math-errno, selects are arithmetic, and atanh,
// log and cosh/sinh are their series. A particle outside the series' range (|2r/(a+e)| or
// |(J-1)/(J+1)| at or above the range below, the plastic k at or above 2^-5), with J <= 0 or
// with an input that is not finite is marked in `redo`, and its caller runs the scalar
// return_map on it instead. In range the elastic part (log J, d_e, N, tau) is the scalar
// function's arithmetic step for step, so the two agree to the last bit; the plastic
// correction differs only in the rounding of cosh and sinh (series here, exp there), within
// 2 ulp.
//
// kLong = false uses only the short series (|z| < 2^-5, the elastic strains of weak solids) and
// hands back everything beyond; kLong = true also the long one (|z| < 1/4). The caller runs the
// short pass and repeats the block with the long one only when some particle was handed back:
// computing both series for every particle costs the common case 17 % of its step.
//
// Fe and tau go to the arrays given (the particles' own, in the time step), or to the block's
// (the overload below); the block keeps the trial Fe, so a second pass can read it again. A
// particle handed back gets a plastic increment of 0 here.
template <bool kLong>
[[gnu::always_inline]] inline void return_map_block(
    ReturnMapBlock& b, std::size_t n, const Material& m, double* __restrict exx,
    double* __restrict exy, double* __restrict eyx, double* __restrict eyy,
    double* __restrict txx, double* __restrict txy, double* __restrict tyy) {
  constexpr double range = kLong ? kLongSeries : kShortSeries;
  const double lm = m.lambda + m.mu, mu = m.mu, dy = m.d_yield;
  for (std::size_t i = 0; i < n; ++i) {
    const double xx = b.fxx[i], xy = b.fxy[i], yx = b.fyx[i], yy = b.fyy[i];
    const double J = xx * yy - xy * yx;
    const double a = xx * xx + xy * xy, c = xx * yx + xy * yy, e = yx * yx + yy * yy;
    const double h = 0.5 * (a - e);
    const double r2 = h * h + c * c;
    const double r = std::sqrt(r2);
    const double z = 2.0 * r / (a + e);
    const double zj = (J - 1.0) / (J + 1.0);
    // atanh_small's series (with kLong both computed and one selected: the same bits as its
    // branches)
    double d_trial = atanh_series_short(z), log_j = 2.0 * atanh_series_short(zj);
    if constexpr (kLong) {
      d_trial = std::abs(z) < kShortSeries ? d_trial : atanh_series_long(z);
      log_j = std::abs(zj) < kShortSeries ? log_j : 2.0 * atanh_series_long(zj);
    }
    // 1 / r bit for bit where it matters (r + 1e-300 == r for r > 1e-284); an isotropic state
    // (r = 0) has h = c = 0, so N = 0 as in return_map.
    const double inv_r = 1.0 / (r + 1e-300);
    const double nxx = h * inv_r, nxy = c * inv_r;
    // k = max(0, (d_e - d_y) / 2), as arithmetic
    const double x = d_trial - dy;
    const double k = 0.25 * (x + std::abs(x));
    const double k2 = k * k;
    const double ch = 1.0 + k2 * (0.5 + k2 * (1.0 / 24 + k2 * (1.0 / 720 + k2 * (1.0 / 40320))));
    const double sh = k * (1.0 + k2 * (1.0 / 6 + k2 * (1.0 / 120 + k2 * (1.0 / 5040))));
    // Fe <- (ch I - sh N) Fe: the identity when k = 0
    exx[i] = (ch - sh * nxx) * xx - sh * nxy * yx;
    exy[i] = (ch - sh * nxx) * xy - sh * nxy * yy;
    eyx[i] = -sh * nxy * xx + (ch + sh * nxx) * yx;
    eyy[i] = -sh * nxy * xy + (ch + sh * nxx) * yy;
    const double d_e = std::min(d_trial, dy);
    const double p = lm * log_j;
    txx[i] = p + mu * d_e * nxx;
    txy[i] = mu * d_e * nxy;
    tyy[i] = p + mu * d_e * -nxx;
    // Everything outside the series' range, J <= 0 and NaN fail these comparisons.
    const bool ok = (std::abs(z) < range) & (std::abs(zj) < range) & (k < kShortSeries) &
                    (J > 0.0);
    b.plastic[i] = ok ? 2.0 * k * 0.70710678118654752440 : 0.0;
    b.redo[i] = ok ? 0.0 : 1.0;
  }
}

template <bool kLong>
[[gnu::always_inline]] inline void return_map_block(ReturnMapBlock& b, std::size_t n,
                                                   const Material& m) {
  return_map_block<kLong>(b, n, m, b.exx, b.exy, b.eyx, b.eyy, b.txx, b.txy, b.tyy);
}

}  // namespace compaction
