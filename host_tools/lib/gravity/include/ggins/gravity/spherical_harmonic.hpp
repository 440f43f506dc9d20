// Spherical-harmonic gravitation models (EGM96 and the like).
//
// V = (GM/a) sum_n sum_m Re[(Cnm - i Snm) Phi_nm],  Phi_nm = (a/r)^(n+1) Pnm(sin phi) e^(i m lambda)
// (Montenbruck & Gill 2000, "Satellite Orbits", eq. (3.27)-(3.28) with the
// solid harmonics Vnm + i Wnm = Phi_nm, fully-normalised coefficients,
// no Condon-Shortley phase: the NASA/NGA and ICGEM convention).
//
// Evaluation: Cunningham's Cartesian recursion for the solid harmonics
// (M&G eqs. (3.29)-(3.31)), fully normalised, in long double:
//   Phi_00 = a/r,  Phi_mm = s_m (X + iY) Phi_{m-1,m-1},
//   Phi_nm = a_nm Z Phi_{n-1,m} - b_nm Q Phi_{n-2,m},
//   X,Y,Z = (x,y,z) a/r^2, Q = a^2/r^2,
//   s_1 = sqrt(3), s_m = sqrt((2m+1)/(2m)),
//   a_nm = sqrt((2n-1)(2n+1)/((n-m)(n+m))),
//   b_nm = sqrt((2n+1)(n+m-1)(n-m-1)/((2n-3)(n+m)(n-m))).
// The recursion works on Cartesian quantities only: no division by cos(phi),
// hence no singularity at the poles; the column recursion in n is the stable
// forward-column one (Holmes & Featherstone 2002, J. Geod. 76, eq. (11)-(12),
// there written for Pnm), and long double's exponent range (1e-4951) removes
// the underflow of the sectorial terms that limits double to degree ~1900.
//
// Derivatives of any order by the ladder identities of the unnormalised solid
// harmonics (the operator form of M&G eq. (3.33); Cunningham 1970):
//   d/dz Phi_nm = -(n-m+1)/a Phi_{n+1,m},
//   (d/dx + i d/dy) Phi_nm = -1/a Phi_{n+1,m+1},
//   (d/dx - i d/dy) Phi_nm = (n-m+1)(n-m+2)/a Phi_{n+1,m-1},
// with Phi_{n,-k} = (-1)^k (n-k)!/(n+k)! conj(Phi_nk). The three operators
// commute, so d+^a d-^b dz^c Phi_nm = (-1)^(a+c) (l+2b+c)!/l! a^-j Phi_{n+j,m+a-b},
// l = n-m, j = a+b+c; Cartesian partials follow from dx = (d+ + d-)/2,
// dy = (d+ - d-)/(2i). (Derivation in docs/gravity.md.)
#pragma once

#include "ggins/gravity/field.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace ggins::gravity {

namespace detail {
template <class T>
class ShEngine;
struct Dd;
}

struct ShCoefficients {
  Real gm = 0;   // m^3/s^2
  Real a = 0;    // reference radius, m
  int nmax = -1;
  std::string source;
  // Permanent-tide convention of C20: "tide_free", "zero_tide", "mean_tide",
  // or empty when the file does not say (NASA/NGA ASCII; EGM96 and EGM2008 are tide free).
  std::string tide_system;
  // Fully-normalised coefficients, index n(n+1)/2 + m.
  std::vector<Real> c, s, sigma_c, sigma_s;
  static std::size_t idx(int n, int m) { return static_cast<std::size_t>(n) * (n + 1) / 2 + m; }
  Real C(int n, int m) const { return c[idx(n, m)]; }
  Real S(int n, int m) const { return s[idx(n, m)]; }
  void resize(int n);
  // Truncated copy (degrees 0..n).
  ShCoefficients truncated(int n) const;
};

// EGM96 constants (Lemoine et al. 1998, NASA/TP-1998-206861, sec. 11).
constexpr Real kEgm96Gm = 3.986004415e14L;
constexpr Real kEgm96A = 6378136.3L;

// Readers. Every malformed line is reported as "path:line: what is wrong".
// NASA/NGA ASCII: lines "n m C S [sigmaC sigmaS]" (Fortran D or E exponents).
// GM and a are not in the file; nmax < 0 reads everything. C00 = 1 when absent.
ShCoefficients read_nasa_ascii(const std::string& path, Real gm = kEgm96Gm, Real a = kEgm96A, int nmax = -1);
// ICGEM .gfc (static models, "gfc n m C S [sigmaC sigmaS]" after end_of_head;
// earth_gravity_constant, radius, max_degree, norm, errors and tide_system
// from the header; Barthelmes & Foerste, "The ICGEM-format", GFZ 2011).
// Time-variable models (gfct/trnd/acos/asin) are rejected.
ShCoefficients read_icgem_gfc(const std::string& path, int nmax = -1);
// Either format, recognised by the content (an ICGEM header keyword before the
// first numeric line); gm and a are used for NASA/NGA files only.
ShCoefficients read_model(const std::string& path, int nmax = -1, Real gm = kEgm96Gm, Real a = kEgm96A);
// The same model in another permanent-tide convention: C20 shifted by the
// IERS Conventions (2010) sec. 6.2.2 offsets (zero - free = -4.1736e-9,
// mean - zero = -4.1736e-9 / k20, k20 = 0.30190). Throws when k.tide_system is empty.
ShCoefficients to_tide_system(const ShCoefficients& k, const std::string& target);

// A synthetic model for tests and benchmarks at any degree: C00 = 1, degree 1
// zero, C_nm and S_nm (S_n0 = 0) independent normal deviates with Kaula's rule
// sigma_n = 1e-5 / n^2 (Kaula 1966, "Theory of Satellite Geodesy", eq. (4.3.2)),
// a realistic degree variance for the Earth; splitmix64 + Box-Muller, so the
// set is the same on every platform for a given seed. GM and a of EGM2008.
ShCoefficients synthetic_kaula(int nmax, std::uint64_t seed = 1);

// Derivatives of order j as the components of a symmetric tensor, indexed by
// the multi-index (ax, ay, az) with ax+ay+az = j: value d^j V / dx^ax dy^ay dz^az.
struct ShDerivatives {
  int order = 0;
  std::vector<std::array<int, 3>> index;
  std::vector<Real> value;
  Real at(int ax, int ay, int az) const;
};

// Arithmetic of the synthesis (eval(); derivatives() and third() use the
// Cunningham engine, in long double for LongDouble, in double otherwise).
//  LongDouble: everything in x87 long double (64-bit mantissa): total fields
//    at the 1e-19 relative level.
//  Double: everything in double (15x faster than LongDouble at degree 360:
//    two orders per pass in vector lanes, see src/sh_engine.cpp). Enough for a
//    DISTURBING field, e.g. the coefficients from subtract_normal(), used to
//    build fast-path nodes: EGM96 disturbance to degree 360 agrees with the
//    long-double total minus the normal field to 2e-17 m/s^2 and 1e-12 E. On a
//    total field the degree-0 term (GM/r^2 = 9.8 m/s^2) alone costs ~1e-14 m/s^2.
//  Mixed: degrees 0..kMixedSplit in long double, the rest in double: a total
//    field at the cost of Double; the rounding is that of the double part,
//    about 1e-16 x sum |terms| of degrees > kMixedSplit: EGM96 (degree 360)
//    5e-17 m/s^2 and 1.4e-12 E from LongDouble, synthetic degree 2190 2e-16
//    m/s^2 and 4e-11 E (tests/gravity/test_sh_2190.cpp, scripts/bench-field).
//    LongDouble is where the truth needs it: a total field whose Gamma must be
//    right below 1e-12 E (Gamma of the 1 m accelerometer differences).
enum class ShPrecision { LongDouble, Double, Mixed };
constexpr int kMixedSplit = 8;

// Coefficients of T = V_model - V_normal (the WGS-84 normal gravitation of
// NormalField) at the model's GM and a: the normal field's zonal series
// C_2k,0 = -J2k / sqrt(4k+1), J2k = (-1)^(k+1) 3 e^2k / ((2k+1)(2k+3)) (1 - k + 5k J2/e^2)
// (Heiskanen & Moritz 1967 eq. (2-92)), J2 = e^2/3 (1 - 2 m e' / (15 q0))
// (H&M eq. (2-90), m = w^2 a^2 b / GM), rescaled by (GM_n/GM)(a_n/a)^n,
// subtracted to degree min(nmax, 20) (J2k ~ e^2k: J22 ~ 1e-24).
ShCoefficients subtract_normal(const ShCoefficients& model);
// J2n of the WGS-84 normal field (n = 1 gives J2).
Real normal_j2n(int n);

class SphericalHarmonicField final : public Field {
 public:
  // nmax < 0: all degrees of the coefficient set. max_order: highest derivative
  // order precomputed (>= 2; 3 gives third derivatives via derivatives()).
  explicit SphericalHarmonicField(ShCoefficients coeffs, int nmax = -1, int max_order = 2,
                                  ShPrecision precision = ShPrecision::LongDouble);
  FieldSample eval(const Vec3& r_e) const override;
  Vec3 gravitation(const Vec3& r_e) const override;  // without the second derivatives (same bits as eval().g)
  // The circle of latitude (rho cos lon, rho sin lon, z): r and t = z/r, hence
  // the column sums of the point synthesis (its O(N^2) Legendre part), are the
  // same at every longitude and are computed once; each longitude then costs
  // the sum over m, O(N) (the idea of GeographicLib's GravityCircle; Karney).
  // V, G, Gamma as eval() (same arithmetic, to rounding: the points differ
  // from eval()'s only by the rounding of rho cos lon, rho sin lon). dgamma
  // (along e_rho rho^ + e_z z^) by dual numbers through the same synthesis in
  // double, whatever the precision (its rounding ~1e-16 of |dGamma| is far
  // below the third() it replaces needs); no max_order requirement.
  std::unique_ptr<FieldCircle> circle(Real rho, Real z, Real e_rho = 0, Real e_z = 0) const override;
  std::string name() const override;
  bool third(const Vec3& r_e, Tensor3& t) const override;  // needs max_order >= 3
  // All partial derivatives of V of orders 0..order (order <= max_order).
  std::vector<ShDerivatives> derivatives(const Vec3& r_e, int order) const;
  int nmax() const { return nmax_; }
  const ShCoefficients& coefficients() const { return k_; }

 private:
  template <class T>
  struct Tables {
    // ratio[j][idx(n,m)*(2j+1) + (s+j)] = N_nm * G(n+j, m+s) (see .cpp).
    std::vector<std::vector<T>> ratio;
    std::vector<T> fact;   // (l+t)!/l! at [l*(2*jmax+1) + t]
    std::vector<T> sec, anm, bnm, c, s;
  };
  template <class T>
  void fill(Tables<T>& t) const;
  template <class T>
  std::vector<ShDerivatives> derivatives_impl(const Tables<T>& t, const Vec3& r, int order) const;

  ShCoefficients k_;
  int nmax_, jmax_;
  ShPrecision prec_;
  // Cunningham tables (derivatives(), third()), built on first use.
  mutable std::once_flag tables_once_;
  mutable Tables<long double> tl_;
  mutable Tables<double> td_;
  // Point-synthesis engines for eval() (see src/sh_engine.hpp).
  std::shared_ptr<const detail::ShEngine<long double>> el_;
  std::shared_ptr<const detail::ShEngine<double>> ed_;
  // Dual-number engine (all degrees) for circle()'s dgamma, built on first use.
  mutable std::once_flag dual_once_;
  mutable std::shared_ptr<const detail::ShEngine<detail::Dd>> edd_;
  friend class ShCircle;
};

}  // namespace ggins::gravity
