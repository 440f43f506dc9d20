// Point synthesis: column recursion, Horner in w, Pines' derivatives (see sh_engine.hpp).
#include "sh_engine.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::gravity::detail {
namespace {

constexpr long double kScale = 1e-280L;  // Holmes & Featherstone 2002, sec. 2.3

// Complex accumulator without std::complex (keeps the arithmetic explicit and
// free of the library's inf/nan recovery in operator*).
template <class T>
struct Cx {
  T re = 0, im = 0;
};
template <class T>
inline void horner(Cx<T>& p, T wr, T wi, T xr, T xi) {  // p = p w + x
  const T r = p.re * wr - p.im * wi + xr;
  p.im = p.re * wi + p.im * wr + xi;
  p.re = r;
}
template <class T>
inline void horner(Cx<T>& p, T wr, T wi, const Cx<T>& x) { horner(p, wr, wi, x.re, x.im); }

}  // namespace

template <class T>
ShEngine<T>::ShEngine(const ShCoefficients& k, int nmax, int nmin)
    : n_(nmax), gm_(static_cast<T>(k.gm)), a_(static_cast<T>(k.a)) {
  if (nmax < 0 || nmax > k.nmax) throw std::invalid_argument("ShEngine: degree out of range");
  const int N = n_;
  off_.assign(N + 2, 0);
  for (int m = 0; m <= N; ++m) off_[m + 1] = off_[m] + static_cast<std::size_t>(N - m + 1);
  col_.assign(off_[N + 1], Col{0, 0, 0, 0});
  for (int m = 0; m <= N; ++m)
    for (int n = m; n <= N; ++n) {
      Col& e = col_[off_[m] + (n - m)];
      if (n >= nmin) {
        e.c = static_cast<T>(k.C(n, m));
        e.s = static_cast<T>(k.S(n, m));
      }
      const long double nn = n, mm = m;
      // Holmes & Featherstone 2002 eqs. (11)-(12)
      if (n >= m + 1) e.a = static_cast<T>(std::sqrt((2 * nn - 1) * (2 * nn + 1) / ((nn - mm) * (nn + mm))));
      if (n >= m + 2)
        e.b = static_cast<T>(std::sqrt((2 * nn + 1) * (nn + mm - 1) * (nn - mm - 1) / ((2 * nn - 3) * (nn + mm) * (nn - mm))));
    }
  // Sectorial start values Abar_mm = sqrt(3) prod_{k=2..m} sqrt((2k+1)/(2k)) (H&F eq. (13) without u^m).
  sect_.assign(N + 1, 0);
  long double s = kScale;
  for (int m = 0; m <= N; ++m) {
    if (m == 1) s *= std::sqrt(3.0L);
    else if (m > 1) s *= std::sqrt((2.0L * m + 1) / (2.0L * m));
    sect_[m] = static_cast<T>(s);
  }
  sq_.assign(2 * N + 4, 0);
  for (std::size_t i = 0; i < sq_.size(); ++i) sq_[i] = static_cast<T>(std::sqrt(static_cast<long double>(i)));
}

template <class T>
ShOut<T> ShEngine<T>::eval(const Vec3& rv, bool with_gamma) const {
  const T x = static_cast<T>(rv.x()), y = static_cast<T>(rv.y()), z = static_cast<T>(rv.z());
  const T r2 = x * x + y * y + z * z;
  if (!(r2 > 0) || !std::isfinite(r2)) throw std::domain_error("SphericalHarmonicField: position at the centre or not finite");
  const T r = std::sqrt(r2), ir = 1 / r;
  const T s1 = x * ir, s2 = y * ir, t = z * ir, q = a_ * ir;
  // In polar caps (|t| > 1/2) the products t Abar are formed as
  // sign(t) (Abar - v Abar), v = 1 - |t| = (s1^2 + s2^2) / (1 + |t|): t = z/r
  // rounded to double is off the unit sphere by ~1e-16, which the steep
  // polynomials Abar_nm(t) near t = +-1 (dAbar/dt ~ n^2 Abar) turn into a
  // systematic error (1e-14 m/s^2 at degree 2190 a few metres off the axis);
  // v carries the distance from the axis to full relative precision.
  const bool polar = std::fabs(t) > T(0.5);
  const T v = polar ? (s1 * s1 + s2 * s2) / (1 + std::fabs(t)) : T(0), sg = t < 0 ? T(-1) : T(1);
  const int N = n_;
  thread_local std::vector<T> buf, qn;
  if (buf.size() < 3 * static_cast<std::size_t>(N + 1)) buf.assign(3 * static_cast<std::size_t>(N + 1), 0);
  if (qn.size() < static_cast<std::size_t>(N + 1)) qn.assign(N + 1, 0);
  qn[0] = 1;
  for (int n = 1; n <= N; ++n) qn[n] = qn[n - 1] * q;
  const T isq2 = 1 / std::sqrt(static_cast<T>(2));
  const T* sq = sq_.data();
  // Horner accumulators: value, first and half second w-derivative of
  // sum_m w^m X_m for X = X0 (Abar), X0r ((n+1) Abar), X0rr ((n+1)(n+2) Abar),
  // X1 (dAbar/dt), X1r ((n+1) dAbar/dt), X2 (d2Abar/dt2).
  Cx<T> h0, h0d, h0dd, hr, hrd, hrr, h1, h1d, h1r, h2;
  for (int m = N; m >= 0; --m) {
    T* c0 = &buf[static_cast<std::size_t>(m % 3) * (N + 1)];
    const T* c1 = &buf[static_cast<std::size_t>((m + 1) % 3) * (N + 1)];
    const T* c2 = &buf[static_cast<std::size_t>((m + 2) % 3) * (N + 1)];
    const Col* col = &col_[off_[m]] - m;  // col[n]
    T a0 = 0, b0 = 0, a0r = 0, b0r = 0, a0rr = 0, b0rr = 0, a1 = 0, b1 = 0, a1r = 0, b1r = 0, a2 = 0, b2 = 0;
    // n = m: its terms are added after the rest of the column (for m = 0 it
    // is the central term, which would otherwise set the rounding of every
    // later addition).
    T p2 = 0, p1 = sect_[m];
    c0[m] = p1;
    const T k0 = (m == 0) ? isq2 : T(1);
    // n = m + 1 (first derivative only: column m+1 starts here)
    if (m + 1 <= N) {
      const int n = m + 1;
      const T p = col[n].a * (polar ? sg * (p1 - v * p1) : t * p1);
      c0[n] = p;
      p2 = p1; p1 = p;
      const T cq = col[n].c * qn[n], sv = col[n].s * qn[n];
      const T w1 = static_cast<T>(n + 1), w2 = static_cast<T>((n + 1) * (n + 2));
      const T cp = cq * p, sp = sv * p;
      a0 += cp; b0 += sp; a0r += w1 * cp; b0r += w1 * sp; a0rr += w2 * cp; b0rr += w2 * sp;
      const T d1 = k0 * sq[n - m] * sq[n + m + 1] * c1[n];
      const T cd = cq * d1, sd = sv * d1;
      a1 += cd; b1 += sd; a1r += w1 * cd; b1r += w1 * sd;
    }
    for (int n = m + 2; n <= N; ++n) {
      const Col& e = col[n];
      const T p = e.a * (polar ? sg * (p1 - v * p1) : t * p1) - e.b * p2;
      c0[n] = p;
      p2 = p1; p1 = p;
      const T cq = e.c * qn[n], sv = e.s * qn[n];
      const T w1 = static_cast<T>(n + 1), w2 = w1 * static_cast<T>(n + 2);
      const T cp = cq * p, sp = sv * p;
      a0 += cp; b0 += sp; a0r += w1 * cp; b0r += w1 * sp; a0rr += w2 * cp; b0rr += w2 * sp;
      const T k1 = k0 * sq[n - m] * sq[n + m + 1];
      const T d1 = k1 * c1[n];
      const T cd = cq * d1, sd = sv * d1;
      a1 += cd; b1 += sd; a1r += w1 * cd; b1r += w1 * sd;
      if (with_gamma) {
        const T d2 = k1 * sq[n - m - 1] * sq[n + m + 2] * c2[n];
        a2 += cq * d2; b2 += sv * d2;
      }
    }
    {
      const T cq = col[m].c * qn[m], sv = col[m].s * qn[m], p = c0[m];
      const T w1 = static_cast<T>(m + 1), w2 = static_cast<T>((m + 1) * (m + 2));
      const T cp = cq * p, sp = sv * p;
      a0 += cp; b0 += sp; a0r += w1 * cp; b0r += w1 * sp; a0rr += w2 * cp; b0rr += w2 * sp;
    }
    // Horner in w (X_m = A_m - i B_m); within a chain the derivative
    // accumulators are updated first (they use the previous values).
    const T wr = s1, wi = s2;
    horner(h0dd, wr, wi, h0d);
    horner(h0d, wr, wi, h0);
    horner(h0, wr, wi, a0, -b0);
    horner(hrd, wr, wi, hr);
    horner(hr, wr, wi, a0r, -b0r);
    horner(hrr, wr, wi, a0rr, -b0rr);
    horner(h1d, wr, wi, h1);
    horner(h1, wr, wi, a1, -b1);
    horner(h1r, wr, wi, a1r, -b1r);
    horner(h2, wr, wi, a2, -b2);
  }
  // Remove the scale; F and its partials in (r, s).
  const T gmr = gm_ * ir / static_cast<T>(kScale), gmr2 = gmr * ir, gmr3 = gmr2 * ir;
  const T F = gmr * h0.re;
  const T Fr = -gmr2 * hr.re, Frr = gmr3 * hrr.re;
  const T ph[3] = {gmr * h0d.re, -gmr * h0d.im, gmr * h1.re};
  const T ps[3] = {-gmr2 * hrd.re, gmr2 * hrd.im, -gmr2 * h1r.re};
  const T sv[3] = {s1, s2, t};
  const T E = sv[0] * ph[0] + sv[1] * ph[1] + sv[2] * ph[2];
  const T Es = sv[0] * ps[0] + sv[1] * ps[1] + sv[2] * ps[2];
  T pp[3], pq[3];  // P phi, P psi
  for (int i = 0; i < 3; ++i) { pp[i] = ph[i] - sv[i] * E; pq[i] = ps[i] - sv[i] * Es; }
  ShOut<T> o;
  o.v = F;
  for (int i = 0; i < 3; ++i) o.g[i] = Fr * sv[i] + pp[i] * ir;
  if (!with_gamma) return o;
  // M = d2F/ds2 (symmetric): w-derivatives of the Horner sums, P'' = 2 h0dd.
  T M[3][3];
  M[0][0] = 2 * gmr * h0dd.re;
  M[0][1] = M[1][0] = -2 * gmr * h0dd.im;
  M[1][1] = -2 * gmr * h0dd.re;
  M[0][2] = M[2][0] = gmr * h1d.re;
  M[1][2] = M[2][1] = -gmr * h1d.im;
  M[2][2] = gmr * h2.re;
  // P M P
  T MP[3][3], PMP[3][3];
  for (int i = 0; i < 3; ++i) {
    const T ms = M[i][0] * sv[0] + M[i][1] * sv[1] + M[i][2] * sv[2];
    for (int j = 0; j < 3; ++j) MP[i][j] = M[i][j] - ms * sv[j];
  }
  for (int j = 0; j < 3; ++j) {
    const T sm = sv[0] * MP[0][j] + sv[1] * MP[1][j] + sv[2] * MP[2][j];
    for (int i = 0; i < 3; ++i) PMP[i][j] = MP[i][j] - sv[i] * sm;
  }
  const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int k = 0; k < 6; ++k) {
    const int i = ij[k][0], j = ij[k][1];
    const T Pij = (i == j ? T(1) : T(0)) - sv[i] * sv[j];
    o.gamma[k] = Frr * sv[i] * sv[j] + (pq[i] * sv[j] + sv[i] * pq[j]) * ir + Fr * Pij * ir +
                 (T(0.5) * (PMP[i][j] + PMP[j][i]) - E * Pij - sv[i] * pp[j] - pp[i] * sv[j]) * ir * ir;
  }
  return o;
}

template class ShEngine<double>;
template class ShEngine<long double>;

}  // namespace ggins::gravity::detail
