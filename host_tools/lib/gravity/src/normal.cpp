#include "ggins/gravity/normal.hpp"

#include "ggins/gravity/spherical_harmonic.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::gravity {
namespace {

// The potential is axially symmetric: a function of A = x^2 + y^2 + z^2 and
// B = z^2 alone. Forward-mode AD in these two variables: value, gradient and
// Hessian (order 2; h = (AA, AB, BB)) and value and gradient (order 1: the
// same operations on v and d, so G is the same to the bit); the Cartesian G
// and Gamma follow by the chain rule (cartesian() below).
struct Hd {
  Real v = 0;
  Real d[2] = {0, 0};
  Real h[3] = {0, 0, 0};
};
struct Gd {
  Real v = 0;
  Real d[2] = {0, 0};
};

Hd operator+(const Hd& a, const Hd& b) {
  Hd r;
  r.v = a.v + b.v;
  for (int i = 0; i < 2; ++i) r.d[i] = a.d[i] + b.d[i];
  for (int i = 0; i < 3; ++i) r.h[i] = a.h[i] + b.h[i];
  return r;
}
Hd operator*(Real s, const Hd& a) {
  Hd r;
  r.v = s * a.v;
  for (int i = 0; i < 2; ++i) r.d[i] = s * a.d[i];
  for (int i = 0; i < 3; ++i) r.h[i] = s * a.h[i];
  return r;
}
Hd operator+(const Hd& a, Real s) { Hd r = a; r.v += s; return r; }
Hd operator*(const Hd& a, const Hd& b) {
  Hd r;
  r.v = a.v * b.v;
  for (int i = 0; i < 2; ++i) r.d[i] = a.v * b.d[i] + b.v * a.d[i];
  r.h[0] = a.v * b.h[0] + b.v * a.h[0] + 2.0L * (a.d[0] * b.d[0]);
  r.h[1] = a.v * b.h[1] + b.v * a.h[1] + (a.d[0] * b.d[1] + a.d[1] * b.d[0]);
  r.h[2] = a.v * b.h[2] + b.v * a.h[2] + 2.0L * (a.d[1] * b.d[1]);
  return r;
}
// f(a) with f' = f1, f'' = f2 evaluated at a.v (chain rule to second order).
Hd chain(const Hd& a, Real f, Real f1, Real f2) {
  Hd r;
  r.v = f;
  for (int i = 0; i < 2; ++i) r.d[i] = f1 * a.d[i];
  r.h[0] = f1 * a.h[0] + f2 * (a.d[0] * a.d[0]);
  r.h[1] = f1 * a.h[1] + f2 * (a.d[0] * a.d[1]);
  r.h[2] = f1 * a.h[2] + f2 * (a.d[1] * a.d[1]);
  return r;
}
Gd operator+(const Gd& a, const Gd& b) { Gd r; r.v = a.v + b.v; for (int i = 0; i < 2; ++i) r.d[i] = a.d[i] + b.d[i]; return r; }
Gd operator*(Real s, const Gd& a) { Gd r; r.v = s * a.v; for (int i = 0; i < 2; ++i) r.d[i] = s * a.d[i]; return r; }
Gd operator+(const Gd& a, Real s) { Gd r = a; r.v += s; return r; }
Gd operator*(const Gd& a, const Gd& b) {
  Gd r;
  r.v = a.v * b.v;
  for (int i = 0; i < 2; ++i) r.d[i] = a.v * b.d[i] + b.v * a.d[i];
  return r;
}
Gd chain(const Gd& a, Real f, Real f1, Real) {
  Gd r;
  r.v = f;
  for (int i = 0; i < 2; ++i) r.d[i] = f1 * a.d[i];
  return r;
}
// G = grad V(A, B) = (2x V_A, 2y V_A, 2z (V_A + V_B)).
template <class D>
Vec3 cartesian_g(const Vec3& r, const D& v) {
  return Vec3(2.0L * r.x() * v.d[0], 2.0L * r.y() * v.d[0], 2.0L * r.z() * (v.d[0] + v.d[1]));
}
// Gamma_ij = 2 V_A delta_ij + 4 x_i x_j V_AA (i, j horizontal), Gamma_iz = 4 x_i z (V_AA + V_AB),
// Gamma_zz = 2 (V_A + V_B) + 4 z^2 (V_AA + 2 V_AB + V_BB).
Mat3 cartesian_gamma(const Vec3& r, const Hd& v) {
  const Real x = r.x(), y = r.y(), z = r.z(), a = v.h[0], c = v.h[0] + v.h[1];
  Mat3 m;
  m(0, 0) = 2.0L * v.d[0] + 4.0L * (x * x) * a;
  m(1, 1) = 2.0L * v.d[0] + 4.0L * (y * y) * a;
  m(0, 1) = m(1, 0) = 4.0L * (x * y) * a;
  m(0, 2) = m(2, 0) = 4.0L * (x * z) * c;
  m(1, 2) = m(2, 1) = 4.0L * (y * z) * c;
  m(2, 2) = 2.0L * (v.d[0] + v.d[1]) + 4.0L * (z * z) * (v.h[0] + 2.0L * v.h[1] + v.h[2]);
  return m;
}
template <class D>
D inv(const D& a) { const Real i = 1.0L / a.v; return chain(a, i, -i * i, 2.0L * i * i * i); }
template <class D>
D sqrt(const D& a) { const Real s = std::sqrt(a.v); return chain(a, s, 0.5L / s, -0.25L / (s * a.v)); }
template <class D>
D atan(const D& a) {
  const Real d = 1.0L / (1.0L + a.v * a.v);
  return chain(a, std::atan(a.v), d, -2.0L * a.v * d * d);
}


// q(t) = sum_{k>=1} (-1)^(k+1) 2k t^(2k+1) / ((2k+1)(2k+3)), t = E/u < 0.5, with
// q'(t) and q''(t) from the same series differentiated term by term (so the
// AD types pay for one chain rule instead of one product per term).
constexpr int kQTerms = 80;
struct QCoefficients {
  Real c[kQTerms];  // c_k = (-1)^(k+1) 2k / ((2k+1)(2k+3))
  QCoefficients() {
    for (int k = 1; k < kQTerms; ++k) c[k] = ((k % 2) ? 2.0L : -2.0L) * k / ((2.0L * k + 1) * (2.0L * k + 3));
  }
};
void q_series(Real t, Real& q, Real& q1, Real& q2) {
  static const QCoefficients qc;
  const Real t2 = t * t;
  Real p = t2, pm = t;  // t^(2k), t^(2k-1) for k = 1
  q = 0;
  q1 = 0;
  q2 = 0;
  for (int k = 1; k < kQTerms; ++k) {
    const Real c = qc.c[k];
    const Real n = 2.0L * k + 1;  // exponent of t in the term
    q += c * p * t;
    q1 += c * n * p;
    q2 += c * n * (n - 1) * pm;
    if (std::fabs(c * p * t) < 1e-24L * std::fabs(q)) break;
    p *= t2;
    pm *= t2;
  }
}
Real q_value(Real t) {
  Real q, q1, q2;
  q_series(t, q, q1, q2);
  return q;
}

}  // namespace

NormalField::NormalField(const EllipsoidParams& p) : p_(p) {
  b_ = p_.a * (1.0L - p_.f);
  e_lin_ = std::sqrt(p_.a * p_.a - b_ * b_);
  q0_ = q_value(e_lin_ / b_);
  ShCoefficients z;
  z.gm = p_.gm; z.a = p_.a; z.source = "normal-zonal";
  z.resize(20);
  z.c[0] = 1;
  for (int n = 1; n <= 10; ++n) z.c[ShCoefficients::idx(2 * n, 0)] = -j2n(n) / std::sqrt(4.0L * n + 1);
  zonal_ = std::make_shared<SphericalHarmonicField>(z, 20, 3);
}

Real NormalField::j2n(int n) const {
  const Real e2 = p_.f * (2 - p_.f), ep = e_lin_ / b_;
  const Real m = p_.omega * p_.omega * p_.a * p_.a * b_ / p_.gm;
  const Real j2 = e2 / 3 * (1 - 2 * m * ep / (15 * q0_));  // H&M (2-90)
  if (n == 1) return j2;
  return ((n % 2) ? 1 : -1) * 3 * std::pow(e2, static_cast<Real>(n)) / ((2 * n + 1) * (2 * n + 3)) * (1 - n + 5 * n * j2 / e2);  // (2-92)
}

bool NormalField::third(const Vec3& r, Tensor3& t) const { return zonal_->third(r, t); }

template <class D>
D NormalField::potential_ad(const Vec3& r_e) const {
  D r2, z2;  // the variables A = r^2, B = z^2
  r2.v = r_e[0] * r_e[0] + r_e[1] * r_e[1] + r_e[2] * r_e[2];
  r2.d[0] = 1.0L;
  z2.v = r_e[2] * r_e[2];
  z2.d[1] = 1.0L;
  const Real e2 = e_lin_ * e_lin_;
  const D w = r2 + (-e2);
  if (!(w.v > 3.0L * e2) || !std::isfinite(w.v))
    throw std::domain_error("NormalField: point too close to the centre (u < 2E) or not finite");
  // u^2 = w/2 [1 + sqrt(1 + 4 E^2 z^2 / w^2)]
  const D iw = inv(w);
  const D ratio = (4.0L * e2) * (z2 * iw * iw);
  const D u2 = 0.5L * (w * (sqrt(ratio + 1.0L) + 1.0L));
  const D iu = inv(sqrt(u2));
  const D t = e_lin_ * iu;                       // E/u
  const D sin2b = z2 * inv(u2);                  // sin^2(beta) = z^2/u^2
  Real qv, q1, q2;
  q_series(t.v, qv, q1, q2);
  const D q = chain(t, qv, q1, q2);
  const Real k = 0.5L * p_.omega * p_.omega * p_.a * p_.a / q0_;
  return (p_.gm / e_lin_) * atan(t) + k * (q * (sin2b + (-1.0L / 3.0L)));
}

FieldSample NormalField::eval(const Vec3& r_e) const {
  const Hd v = potential_ad<Hd>(r_e);
  FieldSample s;
  s.potential = v.v;
  s.g = cartesian_g(r_e, v);
  s.gamma = cartesian_gamma(r_e, v);
  return s;
}

Vec3 NormalField::gravitation(const Vec3& r_e) const { return cartesian_g(r_e, potential_ad<Gd>(r_e)); }

FieldSample NormalField::eval_pairs(const Vec3& r, const Vec3* d, std::size_t n, Vec3* plus, Vec3* minus) const {
  const FieldSample s = eval(r);
  for (std::size_t k = 0; k < n; ++k) {
    plus[k] = gravitation(r + d[k]);
    minus[k] = plus[k] - 2.0L * (s.gamma * d[k]);
  }
  return s;
}

Real NormalField::pair_truncation_bound(const Vec3& r, Real d_norm) const {
  const Real rn = r.norm();
  return 1.05L * 8.0L * p_.gm * d_norm * d_norm * d_norm / (rn * rn * rn * rn * rn);
}

Real NormalField::centrifugal_potential(const Vec3& r) const {
  return 0.5L * p_.omega * p_.omega * (r.x() * r.x() + r.y() * r.y());
}
Vec3 NormalField::centrifugal_acceleration(const Vec3& r) const {
  return Vec3(p_.omega * p_.omega * r.x(), p_.omega * p_.omega * r.y(), 0.0L);
}

}  // namespace ggins::gravity
