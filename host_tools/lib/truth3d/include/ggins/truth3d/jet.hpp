// Taylor-mode automatic differentiation in long double: a "jet" holds a
// function of time and its first N derivatives at one instant, as normalised
// Taylor coefficients c[k] = f^(k)(t0) / k!. Arithmetic and the elementary
// functions propagate the coefficients exactly (to rounding) by the standard
// recurrences (Griewank & Walther, "Evaluating Derivatives", 2nd ed. 2008,
// ch. 13, Table 13.1/13.2: products, quotients, exp, log, sin/cos, sqrt), so
// every derivative of a composite expression is the exact derivative of the
// value, not a finite difference.
//
// deriv() shifts a jet (f -> f'); its top coefficient is then unknown and set
// to zero, so a quantity built from k derivatives of the input is valid to
// order N - k. Callers track that (truth3d: positions carry N = 4, the
// attitude (which uses r'') is valid to order 2: enough for omega and omega').
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "ggins/gravity/ldmath.hpp"

namespace ggins::truth3d {

using Real = long double;

template <int N>
struct Jet {
  static_assert(N >= 1 && N <= 8, "jet order 1..8");
  std::array<Real, N + 1> c{};

  Jet() = default;
  Jet(Real v) { c[0] = v; }  // NOLINT: constants convert implicitly
  static Jet variable(Real t0) {  // the independent variable t at t0
    Jet j;
    j.c[0] = t0;
    j.c[1] = 1;
    return j;
  }
  Real val() const { return c[0]; }
  // k-th derivative f^(k)(t0) = k! c[k].
  Real d(int k) const {
    Real f = 1;
    for (int i = 2; i <= k; ++i) f *= static_cast<Real>(i);
    return f * c[static_cast<std::size_t>(k)];
  }
  Jet& operator+=(const Jet& o) {
    for (int k = 0; k <= N; ++k) c[k] += o.c[k];
    return *this;
  }
  Jet& operator-=(const Jet& o) {
    for (int k = 0; k <= N; ++k) c[k] -= o.c[k];
    return *this;
  }
  Jet& operator*=(Real s) {
    for (auto& x : c) x *= s;
    return *this;
  }
};

template <int N> Jet<N> operator+(Jet<N> a, const Jet<N>& b) { return a += b; }
template <int N> Jet<N> operator-(Jet<N> a, const Jet<N>& b) { return a -= b; }
template <int N> Jet<N> operator-(Jet<N> a) {
  for (auto& x : a.c) x = -x;
  return a;
}
template <int N> Jet<N> operator+(Jet<N> a, Real s) { a.c[0] += s; return a; }
template <int N> Jet<N> operator+(Real s, Jet<N> a) { a.c[0] += s; return a; }
template <int N> Jet<N> operator-(Jet<N> a, Real s) { a.c[0] -= s; return a; }
template <int N> Jet<N> operator-(Real s, const Jet<N>& a) { return Jet<N>(s) - a; }
template <int N> Jet<N> operator*(Jet<N> a, Real s) { return a *= s; }
template <int N> Jet<N> operator*(Real s, Jet<N> a) { return a *= s; }
template <int N> Jet<N> operator/(Jet<N> a, Real s) {
  for (auto& x : a.c) x /= s;
  return a;
}

// Cauchy product: c_k = sum_i a_i b_(k-i).
template <int N>
Jet<N> operator*(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> r;
  for (int k = 0; k <= N; ++k) {
    Real s = 0;
    for (int i = 0; i <= k; ++i) s += a.c[i] * b.c[k - i];
    r.c[k] = s;
  }
  return r;
}

// q = a / b: q_k = (a_k - sum_{i=1..k} b_i q_(k-i)) / b_0.
template <int N>
Jet<N> operator/(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> q;
  for (int k = 0; k <= N; ++k) {
    Real s = a.c[k];
    for (int i = 1; i <= k; ++i) s -= b.c[i] * q.c[k - i];
    q.c[k] = s / b.c[0];
  }
  return q;
}
template <int N> Jet<N> operator/(Real s, const Jet<N>& b) { return Jet<N>(s) / b; }

// f' as a jet (top coefficient unknown: 0).
template <int N>
Jet<N> deriv(const Jet<N>& a) {
  Jet<N> r;
  for (int k = 0; k < N; ++k) r.c[k] = static_cast<Real>(k + 1) * a.c[k + 1];
  r.c[N] = 0;
  return r;
}
// Antiderivative with value v0 (used by atan/atan2: theta' known as a jet).
template <int N>
Jet<N> integ(const Jet<N>& d, Real v0) {
  Jet<N> r;
  r.c[0] = v0;
  for (int k = 1; k <= N; ++k) r.c[k] = d.c[k - 1] / static_cast<Real>(k);
  return r;
}

// e = exp(a): e_k = (1/k) sum_{j=1..k} j a_j e_(k-j).
template <int N>
Jet<N> exp(const Jet<N>& a) {
  Jet<N> e;
  e.c[0] = std::exp(a.c[0]);
  for (int k = 1; k <= N; ++k) {
    Real s = 0;
    for (int j = 1; j <= k; ++j) s += static_cast<Real>(j) * a.c[j] * e.c[k - j];
    e.c[k] = s / static_cast<Real>(k);
  }
  return e;
}

// l = log(a): l_k = (a_k - (1/k) sum_{j=1..k-1} j l_j a_(k-j)) / a_0.
template <int N>
Jet<N> log(const Jet<N>& a) {
  Jet<N> l;
  l.c[0] = std::log(a.c[0]);
  for (int k = 1; k <= N; ++k) {
    Real s = 0;
    for (int j = 1; j < k; ++j) s += static_cast<Real>(j) * l.c[j] * a.c[k - j];
    l.c[k] = (a.c[k] - s / static_cast<Real>(k)) / a.c[0];
  }
  return l;
}

// s = sin(a), c = cos(a) together: s_k = (1/k) sum j a_j c_(k-j), c_k = -(1/k) sum j a_j s_(k-j).
template <int N>
void sincos(const Jet<N>& a, Jet<N>& s, Jet<N>& co) {
  gravity::sincos_ld(a.c[0], s.c[0], co.c[0]);
  for (int k = 1; k <= N; ++k) {
    Real ss = 0, cc = 0;
    for (int j = 1; j <= k; ++j) {
      ss += static_cast<Real>(j) * a.c[j] * co.c[k - j];
      cc += static_cast<Real>(j) * a.c[j] * s.c[k - j];
    }
    s.c[k] = ss / static_cast<Real>(k);
    co.c[k] = -cc / static_cast<Real>(k);
  }
}
template <int N> Jet<N> sin(const Jet<N>& a) { Jet<N> s, c; sincos(a, s, c); return s; }
template <int N> Jet<N> cos(const Jet<N>& a) { Jet<N> s, c; sincos(a, s, c); return c; }

// s = sqrt(a): s_k = (a_k - sum_{j=1..k-1} s_j s_(k-j)) / (2 s_0).
template <int N>
Jet<N> sqrt(const Jet<N>& a) {
  Jet<N> s;
  s.c[0] = std::sqrt(a.c[0]);
  for (int k = 1; k <= N; ++k) {
    Real t = a.c[k];
    for (int j = 1; j < k; ++j) t -= s.c[j] * s.c[k - j];
    s.c[k] = t / (2 * s.c[0]);
  }
  return s;
}

// atan2(y, x): theta' = (x y' - y x') / (x^2 + y^2), integrated coefficient-wise.
// (Coefficient k of theta uses coefficient k-1 of theta', which uses only
// coefficients <= k of x and y: exact to order N.)
template <int N>
Jet<N> atan2(const Jet<N>& y, const Jet<N>& x) {
  // derivative jets, valid to order N-1, enough for theta to order N
  const Jet<N> num = x * deriv(y) - y * deriv(x);
  const Jet<N> den = x * x + y * y;
  return integ(num / den, std::atan2(y.c[0], x.c[0]));
}
template <int N>
Jet<N> atan(const Jet<N>& x) {
  return integ(deriv(x) / (1 + x * x), std::atan(x.c[0]));
}

// Logistic sigma(u) = 1/(1+exp(-u)) and softplus(u) = log(1+exp(u)) (so
// softplus' = sigma), each in the branch that cannot overflow; both branches
// are the same analytic function. Far from the transition (|u| > 80) softplus
// is its limit max(u, 0): the neglected log(1 + exp(-|u|)) and its derivatives
// are < exp(-80) = 1.8e-35 times powers of the coefficients of u (long double
// resolves 1 + 5.4e-20), so the limit is exact to far below rounding.
template <int N>
Jet<N> logistic(const Jet<N>& u) {
  if (u.c[0] >= 0) return 1 / (1 + exp(-u));
  const Jet<N> e = exp(u);
  return e / (1 + e);
}
template <int N>
Jet<N> softplus(const Jet<N>& u) {
  constexpr Real kFar = 80;
  if (u.c[0] > kFar) return u;
  if (u.c[0] < -kFar) return Jet<N>(0);
  if (u.c[0] >= 0) return u + log(1 + exp(-u));
  return log(1 + exp(u));
}

// A jet of another order M: the first min(M, N) + 1 coefficients, zeros above
// (unknown). Truncating (M < N) is exact to the bit: coefficient k of every
// operation above is computed from coefficients <= k of its operands by the
// same loop whatever N, so an expression needed only to order M may be
// evaluated on Jet<M> (truth3d: the attitude, order 2).
template <int M, int N>
Jet<M> resize(const Jet<N>& a) {
  Jet<M> r;
  for (int k = 0; k <= (M < N ? M : N); ++k) r.c[static_cast<std::size_t>(k)] = a.c[static_cast<std::size_t>(k)];
  return r;
}

// Vectors and matrices of jets.
template <int N> using JVec3 = std::array<Jet<N>, 3>;
template <int N> using JMat3 = std::array<std::array<Jet<N>, 3>, 3>;  // [row][col]

template <int M, int N>
JVec3<M> resize(const JVec3<N>& a) {
  return {resize<M>(a[0]), resize<M>(a[1]), resize<M>(a[2])};
}
template <int M, int N>
JMat3<M> resize(const JMat3<N>& a) {
  JMat3<M> r;
  for (std::size_t i = 0; i < 3; ++i) r[i] = resize<M>(a[i]);
  return r;
}
template <int N>
Jet<N> dot(const JVec3<N>& a, const JVec3<N>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <int N>
JVec3<N> cross(const JVec3<N>& a, const JVec3<N>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <int N>
JVec3<N> scale(const JVec3<N>& a, const Jet<N>& s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
template <int N>
JVec3<N> normalized(const JVec3<N>& a) {
  const Jet<N> inv = 1 / sqrt(dot(a, a));
  return scale(a, inv);
}
template <int N>
JVec3<N> operator+(const JVec3<N>& a, const JVec3<N>& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
template <int N>
JVec3<N> operator-(const JVec3<N>& a, const JVec3<N>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <int N>
JVec3<N> deriv(const JVec3<N>& a) {
  return {deriv(a[0]), deriv(a[1]), deriv(a[2])};
}
template <int N>
JMat3<N> deriv(const JMat3<N>& m) {
  JMat3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = deriv(m[i][j]);
  return r;
}
template <int N>
JMat3<N> matmul(const JMat3<N>& a, const JMat3<N>& b) {
  JMat3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return r;
}
template <int N>
JVec3<N> matvec(const JMat3<N>& a, const JVec3<N>& v) {
  return {dot(a[0], v), dot(a[1], v), dot(a[2], v)};
}
template <int N>
JMat3<N> transpose(const JMat3<N>& a) {
  JMat3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[j][i];
  return r;
}

}  // namespace ggins::truth3d
