// Point synthesis of V, G = grad V and Gamma = grad grad V of a spherical-
// harmonic series (internal to the gravity library; see spherical_harmonic.hpp
// for the series and its conventions).
//
// Variables (Pines 1973, AIAA J. 11(11) 1508, "Uniform representation of the
// gravitational potential and its derivatives"): r = |x|, the direction
// cosines s = x/r treated as three independent variables, w = s1 + i s2,
// t = s3, q = a/r. With Abar_nm(t) = Pbar_nm(t) / u^m (u = cos(latitude),
// u^m e^(i m lambda) = w^m) the series is a polynomial in w:
//   V = F(r, s) = (GM/r) Re sum_m w^m X_m,   X_m = sum_n q^n (C_nm - i S_nm) Abar_nm(t).
// Abar_nm is a polynomial in t, finite at the poles (no 1/cos(latitude)
// anywhere). It is computed by the modified forward column method of Holmes &
// Featherstone 2002 (J. Geod. 76, 279, eqs. (11)-(13) with u^m factored out,
// sec. 2.3): Abar_mm = prod_k s_k, Abar_{m+1,m} = sqrt(2m+3) t Abar_mm,
// Abar_nm = a_nm t Abar_{n-1,m} - b_nm Abar_{n-2,m}, all values carried with the
// factor 1e-280 (H&F sec. 2.3) so that in double Abar_nm (up to 1e458 at the
// pole for n = 2190, 1e564 for n = 2700) neither overflows nor underflows;
// the factor is removed after the sums. The sum over m is Horner's scheme in
// w (the complex form of Clenshaw's sum over cos/sin m lambda), which applies
// u^m progressively as H&F's sec. 2.3 prescribes.
// t-derivatives come from the neighbouring columns (d/dt of d^m P_n/dt^m is
// d^(m+1) P_n/dt^(m+1)), so that
//   dAbar_nm/dt = k_nm Abar_{n,m+1},  k_nm = sqrt((n-m)(n+m+1) / (1 + delta_m0)),
// and the columns are computed from m = N down to 0, keeping the last two.
// Cartesian derivatives of F(r, s): with P = I - s s^T, phi = dF/ds,
// psi = d phi/dr, M = d^2F/ds^2, E = s.phi, phi_p = P phi (derived in
// docs/gravity.md, "Point synthesis"):
//   G     = F_r s + phi_p / r,
//   Gamma = F_rr s s^T + [(P psi) s^T + s (P psi)^T]/r + F_r P/r
//           + [P M P - E P - s phi_p^T - phi_p s^T] / r^2.
// Two stages: column sums (r and t only: shared by every point of a circle
// of latitude) and the sum over m with the Cartesian assembly. The double
// engine runs the columns m0, m0+1 together in the two lanes of a vector (two
// independent recursions fill the pipeline); ShEngine<Dd> (dual numbers)
// gives the derivative of every output along one direction.
#pragma once

#include "ggins/gravity/spherical_harmonic.hpp"

#include <vector>

namespace ggins::gravity::detail {

// A dual number x + d eps (eps^2 = 0): carried through the column sums and
// the sum over m it gives, beside each quantity, its derivative along one
// direction (forward-mode automatic differentiation of the synthesis), e.g.
// d Gamma / dh for map tiles.
struct Dd {
  double x = 0, d = 0;
  Dd() = default;
  Dd(double v) : x(v) {}  // NOLINT: constants convert implicitly
  Dd(long double v) : x(static_cast<double>(v)) {}
  Dd(int v) : x(v) {}
  Dd(double v, double dv) : x(v), d(dv) {}
};
inline Dd operator+(Dd a, Dd b) { return {a.x + b.x, a.d + b.d}; }
inline Dd operator-(Dd a, Dd b) { return {a.x - b.x, a.d - b.d}; }
inline Dd operator-(Dd a) { return {-a.x, -a.d}; }
inline Dd operator*(Dd a, Dd b) { return {a.x * b.x, a.x * b.d + a.d * b.x}; }
inline Dd operator/(Dd a, Dd b) { const double q = a.x / b.x; return {q, (a.d - q * b.d) / b.x}; }
inline Dd& operator+=(Dd& a, Dd b) { return a = a + b; }

template <class T>
struct ShOut {
  T v = 0;
  T g[3] = {0, 0, 0};
  T gamma[6] = {0, 0, 0, 0, 0, 0};  // xx, xy, xz, yy, yz, zz
};

// The column sums of order m (they depend on r and t only, not on longitude):
// sum_n q^n (C_nm, S_nm) x {Abar, (n+1) Abar, (n+1)(n+2) Abar, Abar', (n+1) Abar', Abar''}
// (all carried with the factor 1e-280).
template <class T>
struct ColSums {
  T a0, b0, a0r, b0r, a0rr, b0rr, a1, b1, a1r, b1r, a2, b2;
};

// Position variables of the synthesis (r, 1/r, s = x/r, q = a/r; the polar-cap
// form of t, see sh_engine.cpp).
template <class T>
struct ShGeom {
  T r, ir, s1, s2, t, q, v, sg;
  bool polar;
};

template <class T>
class ShEngine {
 public:
  // Degrees nmin..nmax of k (coefficients of lower degrees taken as zero).
  ShEngine(const ShCoefficients& k, int nmax, int nmin = 0);
  // with_gamma = false skips the second derivatives (about 40 % faster).
  ShOut<T> eval(const Vec3& r, bool with_gamma = true) const;
  int nmax() const { return n_; }
  T gm() const { return gm_; }
  T a() const { return a_; }
  // The two stages of eval: column sums (r, t only; out[m], m = 0..nmax) and
  // the sum over m with the Cartesian derivatives (needs s1, s2 as well).
  // A circle of latitude (fixed r and z) shares the first stage.
  void column_sums(const ShGeom<T>& g, bool with_gamma, ColSums<T>* out) const;
  ShOut<T> assemble(const ColSums<T>* sums, const ShGeom<T>& g, bool with_gamma) const;

 private:
  struct Col {
    T c, s, a, b;
  };
  // Two neighbouring orders (m0, m0 + 1) at one degree n, one per lane, so that
  // the two independent column recursions fill the floating-point pipeline
  // (double only; SSE2 / NEON lanes via the compiler's vector extension).
  typedef double Lane2 __attribute__((vector_size(16)));
  struct PairEntry {
    Lane2 a, b, c, s;
  };
  int n_;
  T gm_, a_;
  std::vector<std::size_t> off_;  // column m starts at off_[m] (entries n = m..N)
  std::vector<Col> col_;
  std::vector<T> sect_;           // Abar_mm * scale (m = 0..N+1)
  std::vector<T> sq_;             // sqrt(k), k = 0..2N+3
  std::vector<double> rsq_;       // sqrt(N + 3 - k) (reversed), double engine only
  std::vector<std::size_t> poff_; // pair j (m0 = 2j) starts at poff_[j] (entries n = m0..N)
  std::vector<PairEntry> pair_;
  template <bool Polar, bool Gamma>
  void pair_sums(const ShGeom<double>& g, ColSums<double>* out) const;
};

template <class T>
ShGeom<T> sh_geometry(const Vec3& r, T a);
// The geometry at r with the derivatives of every variable along e.
ShGeom<Dd> sh_geometry(const Vec3& r, const Vec3& e, double a);

extern template class ShEngine<double>;
extern template class ShEngine<long double>;

}  // namespace ggins::gravity::detail
