// Functions of a small symmetric 3 x 3 matrix by their power series, for the 3D return mapping
// without an eigen-decomposition (plasticity_3d.hpp): the Hencky strain 1/2 log b through
// atanh, and the plastic correction through exp.
//
// A matrix function f(X) of a symmetric X is Q diag(f(x_i)) Q^T; a power series in X gives the
// same without Q, and converges at the rate of its scalar series at X's spectral radius, which
// the Frobenius norm bounds from above. So each series below holds where |X|_F is below its
// range, with the first omitted term as its error bound (relative to the result, as the 2D
// series of plasticity.hpp). Products of polynomials in one matrix commute, so each product
// here is symmetric and only its upper triangle is formed.
#pragma once

namespace compaction {

// A symmetric 3 x 3 matrix by its six distinct entries.
struct Sym3 {
  double xx, yy, zz, xy, xz, yz;
};

inline Sym3 operator+(const Sym3& a, const Sym3& b) {
  return {a.xx + b.xx, a.yy + b.yy, a.zz + b.zz, a.xy + b.xy, a.xz + b.xz, a.yz + b.yz};
}
inline Sym3 operator*(double s, const Sym3& a) {
  return {s * a.xx, s * a.yy, s * a.zz, s * a.xy, s * a.xz, s * a.yz};
}
// a + s I
inline Sym3 plus_identity(const Sym3& a, double s) {
  return {a.xx + s, a.yy + s, a.zz + s, a.xy, a.xz, a.yz};
}
inline double frobenius2(const Sym3& a) {
  return a.xx * a.xx + a.yy * a.yy + a.zz * a.zz +
         2.0 * (a.xy * a.xy + a.xz * a.xz + a.yz * a.yz);
}
inline double trace(const Sym3& a) { return a.xx + a.yy + a.zz; }

// a b for a and b that commute (polynomials in one matrix): the upper triangle of the product.
inline Sym3 commuting_product(const Sym3& a, const Sym3& b) {
  return {a.xx * b.xx + a.xy * b.xy + a.xz * b.xz,
          a.xy * b.xy + a.yy * b.yy + a.yz * b.yz,
          a.xz * b.xz + a.yz * b.yz + a.zz * b.zz,
          a.xx * b.xy + a.xy * b.yy + a.xz * b.yz,
          a.xx * b.xz + a.xy * b.yz + a.xz * b.zz,
          a.xy * b.xz + a.yy * b.yz + a.yz * b.zz};
}

// a m^-1 for a symmetric m that commutes with a (a function of the same matrix), the two
// triangles of the product averaged: m^-1 by its cofactors, which is accurate for the well
// conditioned m = 2 I + (b - I) it is used on.
inline Sym3 commuting_solve(const Sym3& a, const Sym3& m) {
  const double cxx = m.yy * m.zz - m.yz * m.yz, cyy = m.xx * m.zz - m.xz * m.xz,
               czz = m.xx * m.yy - m.xy * m.xy, cxy = m.xz * m.yz - m.xy * m.zz,
               cxz = m.xy * m.yz - m.xz * m.yy, cyz = m.xy * m.xz - m.xx * m.yz;
  const double inv_det = 1.0 / (m.xx * cxx + m.xy * cxy + m.xz * cxz);
  const Sym3 c{cxx, cyy, czz, cxy, cxz, cyz};
  // (a c)_ij and (a c)_ji differ by round-off only: their mean keeps the result symmetric.
  const double xy = a.xx * c.xy + a.xy * c.yy + a.xz * c.yz;
  const double yx = a.xy * c.xx + a.yy * c.xy + a.yz * c.xz;
  const double xz = a.xx * c.xz + a.xy * c.yz + a.xz * c.zz;
  const double zx = a.xz * c.xx + a.yz * c.xy + a.zz * c.xz;
  const double yz = a.xy * c.xz + a.yy * c.yz + a.yz * c.zz;
  const double zy = a.xz * c.xy + a.yz * c.yy + a.zz * c.yz;
  return inv_det * Sym3{a.xx * c.xx + a.xy * c.xy + a.xz * c.xz,
                        a.xy * c.xy + a.yy * c.yy + a.yz * c.yz,
                        a.xz * c.xz + a.yz * c.yz + a.zz * c.zz,
                        0.5 * (xy + yx), 0.5 * (xz + zx), 0.5 * (yz + zy)};
}

// Ranges of |X|_F: the short and long ones as the scalar series of plasticity.hpp
// (kShortSeries, kLongSeries); the tiny one for the elastic strains of weak solids (R = 1e-5
// strains to about 1e-5), where three terms of atanh reach the precision of eleven.
inline constexpr double kSym3TinySeries = 0x1p-10, kSym3ShortSeries = 0x1p-5,
                        kSym3LongSeries = 0.25;

// atanh(Z) = Z + Z^3/3 + Z^5/5 for |Z|_F < 2^-10 (the first omitted term, Z^7/7, is below 2e-19
// of the result).
inline Sym3 atanh_sym3_tiny(const Sym3& z) {
  const Sym3 z2 = commuting_product(z, z);
  const Sym3 p = plus_identity((1.0 / 5) * z2, 1.0 / 3);
  return commuting_product(z, plus_identity(commuting_product(z2, p), 1.0));
}

// atanh(Z) = Z + Z^3/3 + ... + Z^11/11 for |Z|_F < 2^-5 (the first omitted term is below 1e-19
// of the result), in Estrin's scheme as atanh_series_short.
inline Sym3 atanh_sym3_short(const Sym3& z) {
  const Sym3 z2 = commuting_product(z, z), z4 = commuting_product(z2, z2);
  const Sym3 p01 = plus_identity((1.0 / 3) * z2, 1.0);
  const Sym3 p23 = plus_identity((1.0 / 7) * z2, 1.0 / 5);
  const Sym3 p45 = plus_identity((1.0 / 11) * z2, 1.0 / 9);
  return commuting_product(z, p01 + commuting_product(z4, p23 + commuting_product(z4, p45)));
}

// The same series to Z^27 for |Z|_F < 1/4 (the first omitted term below 5e-19 of the result).
inline Sym3 atanh_sym3_long(const Sym3& z) {
  const Sym3 z2 = commuting_product(z, z);
  Sym3 p = plus_identity((1.0 / 27) * z2, 1.0 / 25);
  for (int k = 23; k >= 3; k -= 2) p = plus_identity(commuting_product(z2, p), 1.0 / k);
  return commuting_product(z, plus_identity(commuting_product(z2, p), 1.0));
}

inline constexpr double kSym3TinyExp = 0x1p-12;

// exp(K) = I + K + K^2/2 + K^3/6 + K^4/24 for |K|_F < 2^-12 (the first omitted term, K^5/5!, is
// below 1e-20): the plastic cut of one time step.
inline Sym3 exp_sym3_tiny(const Sym3& k) {
  const Sym3 k2 = commuting_product(k, k);
  const Sym3 tail = plus_identity((1.0 / 6) * k + (1.0 / 24) * k2, 0.5);
  return plus_identity(k, 1.0) + commuting_product(k2, tail);
}

// exp(K) = I + K + ... + K^8/8! for |K|_F < 2^-5 (the first omitted term, K^9/9!, is below 1e-19).
inline Sym3 exp_sym3_short(const Sym3& k) {
  const Sym3 k2 = commuting_product(k, k), k4 = commuting_product(k2, k2);
  const Sym3 c0 = plus_identity(k, 1.0), c1 = plus_identity((1.0 / 6) * k, 0.5),
             c2 = plus_identity((1.0 / 120) * k, 1.0 / 24),
             c3 = plus_identity((1.0 / 5040) * k, 1.0 / 720);
  const Sym3 high = c2 + commuting_product(k2, c3) + (1.0 / 40320) * k4;
  return c0 + commuting_product(k2, c1) + commuting_product(k4, high);
}

}  // namespace compaction
