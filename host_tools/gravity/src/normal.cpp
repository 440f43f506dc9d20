#include "ggins/gravity/normal.hpp"

#include "ggins/gravity/spherical_harmonic.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::gravity {
namespace {

// Value, gradient and Hessian of a scalar function of r_e (forward-mode AD,
// order 2), and value and gradient only (order 1: the same operations on
// v and d, so G is the same to the bit).
struct Hd {
  Real v = 0;
  Vec3 d = Vec3::Zero();
  Mat3 h = Mat3::Zero();
};
struct Gd {
  Real v = 0;
  Vec3 d = Vec3::Zero();
};

Hd operator+(const Hd& a, const Hd& b) { Hd r; r.v = a.v + b.v; r.d = a.d + b.d; r.h = a.h + b.h; return r; }
Hd operator*(Real s, const Hd& a) { Hd r; r.v = s * a.v; r.d = s * a.d; r.h = s * a.h; return r; }
Hd operator+(const Hd& a, Real s) { Hd r = a; r.v += s; return r; }
Hd operator*(const Hd& a, const Hd& b) {
  Hd r;
  r.v = a.v * b.v;
  r.d = a.v * b.d + b.v * a.d;
  r.h = a.v * b.h + b.v * a.h + a.d * b.d.transpose() + b.d * a.d.transpose();
  return r;
}
// f(a) with f' = f1, f'' = f2 evaluated at a.v (chain rule to second order).
Hd chain(const Hd& a, Real f, Real f1, Real f2) {
  Hd r;
  r.v = f;
  r.d = f1 * a.d;
  r.h = f1 * a.h + f2 * (a.d * a.d.transpose());
  return r;
}
Gd operator+(const Gd& a, const Gd& b) { Gd r; r.v = a.v + b.v; r.d = a.d + b.d; return r; }
Gd operator*(Real s, const Gd& a) { Gd r; r.v = s * a.v; r.d = s * a.d; return r; }
Gd operator+(const Gd& a, Real s) { Gd r = a; r.v += s; return r; }
Gd operator*(const Gd& a, const Gd& b) {
  Gd r;
  r.v = a.v * b.v;
  r.d = a.v * b.d + b.v * a.d;
  return r;
}
Gd chain(const Gd& a, Real f, Real f1, Real) {
  Gd r;
  r.v = f;
  r.d = f1 * a.d;
  return r;
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
  D x[3];
  for (int i = 0; i < 3; ++i) { x[i].v = r_e[i]; x[i].d[i] = 1.0L; }
  const Real e2 = e_lin_ * e_lin_;
  const D r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
  const D w = r2 + (-e2);
  if (!(w.v > 3.0L * e2) || !std::isfinite(w.v))
    throw std::domain_error("NormalField: point too close to the centre (u < 2E) or not finite");
  // u^2 = w/2 [1 + sqrt(1 + 4 E^2 z^2 / w^2)]
  const D iw = inv(w);
  const D ratio = (4.0L * e2) * (x[2] * x[2] * iw * iw);
  const D u2 = 0.5L * (w * (sqrt(ratio + 1.0L) + 1.0L));
  const D iu = inv(sqrt(u2));
  const D t = e_lin_ * iu;                       // E/u
  const D sin2b = x[2] * x[2] * inv(u2);         // sin^2(beta) = z^2/u^2
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
  s.g = v.d;
  s.gamma = 0.5L * (v.h + v.h.transpose());
  return s;
}

Vec3 NormalField::gravitation(const Vec3& r_e) const { return potential_ad<Gd>(r_e).d; }

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
