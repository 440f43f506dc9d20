// Point synthesis: column recursion, Horner in w, Pines' derivatives (see sh_engine.hpp).
#include "sh_engine.hpp"

#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>

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
  sect_.assign(N + 2, 0);
  long double s = kScale;
  for (int m = 0; m <= N + 1; ++m) {
    if (m == 1) s *= std::sqrt(3.0L);
    else if (m > 1) s *= std::sqrt((2.0L * m + 1) / (2.0L * m));
    sect_[m] = static_cast<T>(s);
  }
  sq_.assign(2 * N + 4, 0);
  for (std::size_t i = 0; i < sq_.size(); ++i) sq_[i] = static_cast<T>(std::sqrt(static_cast<long double>(i)));
  if constexpr (std::is_same_v<T, double>) {
    const int K = N + 3;
    rsq_.assign(K + 1, 0);
    for (int i = 0; i <= K; ++i) rsq_[i] = static_cast<double>(std::sqrt(static_cast<long double>(K - i)));
    const int J = N / 2 + 1;
    poff_.assign(J + 1, 0);
    for (int j = 0; j < J; ++j) poff_[j + 1] = poff_[j] + static_cast<std::size_t>(N - 2 * j + 1);
    pair_.assign(poff_[J], PairEntry{});
    for (int j = 0; j < J; ++j)
      for (int n = 2 * j; n <= N; ++n) {
        PairEntry& e = pair_[poff_[j] + (n - 2 * j)];
        for (int l = 0; l < 2; ++l) {
          const int m = 2 * j + l;
          if (m > n) {
            e.a[l] = e.b[l] = e.c[l] = e.s[l] = 0;
            continue;
          }
          const Col& c = col_[off_[m] + (n - m)];
          e.a[l] = c.a; e.b[l] = c.b; e.c[l] = c.c; e.s[l] = c.s;
        }
      }
  }
}

template <class T>
ShGeom<T> sh_geometry(const Vec3& rv, T a) {
  const T x = static_cast<T>(rv.x()), y = static_cast<T>(rv.y()), z = static_cast<T>(rv.z());
  const T r2 = x * x + y * y + z * z;
  if (!(r2 > 0) || !std::isfinite(r2)) throw std::domain_error("SphericalHarmonicField: position at the centre or not finite");
  ShGeom<T> g;
  g.r = std::sqrt(r2);
  g.ir = 1 / g.r;
  g.s1 = x * g.ir; g.s2 = y * g.ir; g.t = z * g.ir; g.q = a * g.ir;
  // In polar caps (|t| > 1/2) the products t Abar are formed as
  // sign(t) (Abar - v Abar), v = 1 - |t| = (s1^2 + s2^2) / (1 + |t|): t = z/r
  // rounded to double is off the unit sphere by ~1e-16, which the steep
  // polynomials Abar_nm(t) near t = +-1 (dAbar/dt ~ n^2 Abar) turn into a
  // systematic error (1e-14 m/s^2 at degree 2190 a few metres off the axis);
  // v carries the distance from the axis to full relative precision.
  g.polar = std::fabs(g.t) > T(0.5);
  g.v = g.polar ? (g.s1 * g.s1 + g.s2 * g.s2) / (1 + std::fabs(g.t)) : T(0);
  g.sg = g.t < 0 ? T(-1) : T(1);
  return g;
}

ShGeom<Dd> sh_geometry(const Vec3& rv, const Vec3& ev, double a) {
  const ShGeom<double> g0 = sh_geometry<double>(rv, a);
  const double e[3] = {static_cast<double>(ev.x()), static_cast<double>(ev.y()), static_cast<double>(ev.z())};
  const double s[3] = {g0.s1, g0.s2, g0.t};
  const double dr = s[0] * e[0] + s[1] * e[1] + s[2] * e[2];  // dr/de
  ShGeom<Dd> g;
  g.r = Dd(g0.r, dr);
  g.ir = Dd(g0.ir, -dr * g0.ir * g0.ir);
  g.s1 = Dd(s[0], (e[0] - s[0] * dr) * g0.ir);  // ds/de = (e - s dr)/r
  g.s2 = Dd(s[1], (e[1] - s[1] * dr) * g0.ir);
  g.t = Dd(s[2], (e[2] - s[2] * dr) * g0.ir);
  g.q = Dd(g0.q, -g0.q * g0.ir * dr);
  g.polar = g0.polar;
  g.sg = Dd(g0.sg);
  g.v = g.polar ? (g.s1 * g.s1 + g.s2 * g.s2) / (Dd(1.0) + g.sg * g.t) : Dd(0.0);
  return g;
}

namespace {
template <class T>
const T* powers(T q, int N) {
  thread_local std::vector<T> qn;
  if (qn.size() < static_cast<std::size_t>(N + 1)) qn.assign(N + 1, 0);
  qn[0] = 1;
  for (int n = 1; n <= N; ++n) qn[n] = qn[n - 1] * q;
  return qn.data();
}
}  // namespace

// Two orders per pass (lanes m0, m0 + 1), columns from the top down. At degree
// n, lane 0 needs Abar_{n,m0+1} (lane 1 of the same pass) for its t-derivative
// and lanes (0, 1) need Abar_{n,m0+2}, Abar_{n,m0+3} (the previous pass) for
// the second; the pass above is kept in `prev`.
template <class T>
template <bool Polar, bool Gamma>
void ShEngine<T>::pair_sums(const ShGeom<double>& g, ColSums<double>* out) const {
  using L = Lane2;
  const int N = n_, K = N + 3;
  const double* qn = powers(g.q, N);
  thread_local std::vector<L> bufa, bufb;
  if (bufa.size() < static_cast<std::size_t>(N + 1)) { bufa.assign(N + 1, L{0, 0}); bufb.assign(N + 1, L{0, 0}); }
  L* prev = bufa.data();
  L* cur = bufb.data();
  for (int n = 0; n <= N; ++n) prev[n] = L{0, 0};
  const double* sq = sq_.data();
  const double* rsq = rsq_.data();
  const double t = g.t, v = g.v, sg = g.sg;
  const L tv = {t, t}, sgv = {sg, sg}, vv = {v, v};
  const double isq2 = 1 / std::sqrt(2.0);
  for (int j = N / 2; j >= 0; --j) {
    const int m0 = 2 * j;
    const bool two = m0 + 1 <= N;
    const PairEntry* e = pair_.data() + poff_[j] - m0;  // e[n], n = m0..N
    L A0 = {0, 0}, B0 = A0, A0r = A0, B0r = A0, A0rr = A0, B0rr = A0, A1 = A0, B1 = A0, A1r = A0, B1r = A0, A2 = A0, B2 = A0;
    if (m0 >= 2) { cur[m0 - 2] = L{0, 0}; cur[m0 - 1] = L{0, 0}; }
    const double s0 = static_cast<double>(sect_[m0]), s1 = two ? static_cast<double>(sect_[m0 + 1]) : 0.0;
    cur[m0] = L{s0, 0};
    L p2 = {0, 0}, p1 = {s0, 0};
    if (two) {  // n = m0 + 1: lane 0's first step, lane 1's sectorial value (its terms come last)
      const int n = m0 + 1;
      const double pl = e[n].a[0] * (Polar ? sg * (s0 - v * s0) : t * s0);
      const L p = {pl, s1};
      cur[n] = p;
      p2 = p1; p1 = p;
      const double cq = e[n].c[0] * qn[n], sv = e[n].s[0] * qn[n];
      const double w1 = n + 1, w2 = (n + 1.0) * (n + 2.0);
      const double cp = cq * pl, sp = sv * pl;
      const double d1 = sq[1] * sq[2 * m0 + 2] * s1, cd = cq * d1, sd = sv * d1;
      A0 = L{cp, 0}; B0 = L{sp, 0}; A0r = L{w1 * cp, 0}; B0r = L{w1 * sp, 0}; A0rr = L{w2 * cp, 0}; B0rr = L{w2 * sp, 0};
      A1 = L{cd, 0}; B1 = L{sd, 0}; A1r = L{w1 * cd, 0}; B1r = L{w1 * sd, 0};
    }
    for (int n = m0 + 2; n <= N; ++n) {
      const PairEntry& E = e[n];
      L p;
      if constexpr (Polar) {
        const L as = E.a * sgv;
        p = (as * p1 - E.b * p2) - (as * vv) * p1;
      } else {
        p = (E.a * tv) * p1 - E.b * p2;
      }
      cur[n] = p;
      p2 = p1; p1 = p;
      const L q = {qn[n], qn[n]};
      const L cq = E.c * q, sv = E.s * q;
      const double fw1 = n + 1.0;
      const L w1 = {fw1, fw1}, w2 = w1 * L{fw1 + 1, fw1 + 1};
      const L cp = cq * p, sp = sv * p;
      A0 += cp; B0 += sp; A0r += w1 * cp; B0r += w1 * sp; A0rr += w2 * cp; B0rr += w2 * sp;
      // k_nm = sqrt(n - m) sqrt(n + m + 1) for the lanes m0, m0 + 1
      const int i = K - (n - m0);
      const L k1 = L{rsq[i], rsq[i + 1]} * L{sq[n + m0 + 1], sq[n + m0 + 2]};
      const L d1 = k1 * L{p[1], prev[n][0]};
      const L cd = cq * d1, sd = sv * d1;
      A1 += cd; B1 += sd; A1r += w1 * cd; B1r += w1 * sd;
      if constexpr (Gamma) {
        const L d2 = (k1 * (L{rsq[i + 1], rsq[i + 2]} * L{sq[n + m0 + 2], sq[n + m0 + 3]})) * prev[n];
        A2 += cq * d2; B2 += sv * d2;
      }
    }
    {  // the central terms n = m0 (lane 0) and n = m0 + 1 (lane 1), added last
      const double q0 = qn[m0], q1 = two ? qn[m0 + 1] : 0.0;
      const L pc = {s0, s1};
      const L cq = L{e[m0].c[0] * q0, two ? e[m0 + 1].c[1] * q1 : 0.0}, sv = L{e[m0].s[0] * q0, two ? e[m0 + 1].s[1] * q1 : 0.0};
      const L w1 = {m0 + 1.0, m0 + 2.0}, w2 = w1 * L{m0 + 2.0, m0 + 3.0};
      const L cp = cq * pc, sp = sv * pc;
      A0 += cp; B0 += sp; A0r += w1 * cp; B0r += w1 * sp; A0rr += w2 * cp; B0rr += w2 * sp;
    }
    if (m0 == 0) {  // k_n0 carries 1/sqrt(2) (N_n0 has no factor 2)
      const L h = {isq2, 1.0};
      A1 *= h; B1 *= h; A1r *= h; B1r *= h; A2 *= h; B2 *= h;
    }
    for (int l = 0; l < (two ? 2 : 1); ++l)
      out[m0 + l] = ColSums<double>{A0[l], B0[l], A0r[l], B0r[l], A0rr[l], B0rr[l], A1[l], B1[l], A1r[l], B1r[l], A2[l], B2[l]};
    std::swap(prev, cur);
  }
}

template <class T>
void ShEngine<T>::column_sums(const ShGeom<T>& g, bool with_gamma, ColSums<T>* out) const {
  if constexpr (std::is_same_v<T, double>) {
    if (g.polar) with_gamma ? pair_sums<true, true>(g, out) : pair_sums<true, false>(g, out);
    else with_gamma ? pair_sums<false, true>(g, out) : pair_sums<false, false>(g, out);
    return;
  } else {
    const int N = n_;
    const T t = g.t, v = g.v, sg = g.sg;
    const bool polar = g.polar;
    const T* qn = powers(g.q, N);
    thread_local std::vector<T> buf;
    if (buf.size() < 3 * static_cast<std::size_t>(N + 1)) buf.assign(3 * static_cast<std::size_t>(N + 1), 0);
    for (T& b : buf) b = 0;
    const T isq2 = static_cast<T>(1 / std::sqrt(2.0L));
    const T* sq = sq_.data();
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
      if (m >= 1) c0[m - 1] = 0;
      c0[m] = p1;
      const T k0 = (m == 0) ? isq2 : T(1);
      if (m + 1 <= N) {  // n = m + 1 (first derivative only: column m+1 starts here)
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
      out[m] = ColSums<T>{a0, b0, a0r, b0r, a0rr, b0rr, a1, b1, a1r, b1r, a2, b2};
    }
  }
}

template <class T>
ShOut<T> ShEngine<T>::assemble(const ColSums<T>* S, const ShGeom<T>& g, bool with_gamma) const {
  // Horner accumulators: value, first and half second w-derivative of
  // sum_m w^m X_m for X = X0 (Abar), X0r ((n+1) Abar), X0rr ((n+1)(n+2) Abar),
  // X1 (dAbar/dt), X1r ((n+1) dAbar/dt), X2 (d2Abar/dt2).
  Cx<T> h0, h0d, h0dd, hr, hrd, hrr, h1, h1d, h1r, h2;
  const T wr = g.s1, wi = g.s2;
  for (int m = n_; m >= 0; --m) {
    // Horner in w (X_m = A_m - i B_m); within a chain the derivative
    // accumulators are updated first (they use the previous values).
    const ColSums<T>& c = S[m];
    horner(h0dd, wr, wi, h0d);
    horner(h0d, wr, wi, h0);
    horner(h0, wr, wi, c.a0, -c.b0);
    horner(hrd, wr, wi, hr);
    horner(hr, wr, wi, c.a0r, -c.b0r);
    horner(hrr, wr, wi, c.a0rr, -c.b0rr);
    horner(h1d, wr, wi, h1);
    horner(h1, wr, wi, c.a1, -c.b1);
    horner(h1r, wr, wi, c.a1r, -c.b1r);
    horner(h2, wr, wi, c.a2, -c.b2);
  }
  // Remove the scale; F and its partials in (r, s).
  const T ir = g.ir;
  const T gmr = gm_ * ir / static_cast<T>(kScale), gmr2 = gmr * ir, gmr3 = gmr2 * ir;
  const T F = gmr * h0.re;
  const T Fr = -gmr2 * hr.re, Frr = gmr3 * hrr.re;
  const T ph[3] = {gmr * h0d.re, -gmr * h0d.im, gmr * h1.re};
  const T ps[3] = {-gmr2 * hrd.re, gmr2 * hrd.im, -gmr2 * h1r.re};
  const T sv[3] = {g.s1, g.s2, g.t};
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

template <class T>
ShOut<T> ShEngine<T>::eval(const Vec3& rv, bool with_gamma) const {
  const ShGeom<T> g = sh_geometry<T>(rv, a_);
  thread_local std::vector<ColSums<T>> sums;
  if (sums.size() < static_cast<std::size_t>(n_ + 1)) sums.resize(n_ + 1);
  column_sums(g, with_gamma, sums.data());
  return assemble(sums.data(), g, with_gamma);
}

template ShGeom<double> sh_geometry<double>(const Vec3&, double);
template ShGeom<long double> sh_geometry<long double>(const Vec3&, long double);
template class ShEngine<double>;
template class ShEngine<long double>;
// dual numbers: tables, column sums and the sum over m (the geometry has its own overload)
template ShEngine<Dd>::ShEngine(const ShCoefficients&, int, int);
template void ShEngine<Dd>::column_sums(const ShGeom<Dd>&, bool, ColSums<Dd>*) const;
template ShOut<Dd> ShEngine<Dd>::assemble(const ColSums<Dd>*, const ShGeom<Dd>&, bool) const;

}  // namespace ggins::gravity::detail
