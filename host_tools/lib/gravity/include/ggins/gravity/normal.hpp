// WGS-84 normal GRAVITATION field (the level ellipsoid's attraction, NO
// centrifugal term), in closed form in ellipsoidal harmonics.
//
// The normal gravity potential of a level ellipsoid (Heiskanen & Moritz 1967,
// "Physical Geodesy", sec. 2-7 (eq. number quoted from memory: (2-61)); the same expression is the basis
// of NIMA TR8350.2 ch. 4 and of Moritz, "Geodetic Reference System 1980",
// Bull. Geod. 62(3) 1988, sec. 2) is
//   U(u, beta) = (GM/E) atan(E/u) + (1/2) w^2 a^2 (q/q0)(sin^2 beta - 1/3)
//                + (1/2) w^2 (u^2 + E^2) cos^2 beta,
// with ellipsoidal coordinates (u, beta, lambda):
//   x = sqrt(u^2+E^2) cos(beta) cos(lambda), y = ... sin(lambda), z = u sin(beta),
//   u^2 = (r^2 - E^2)/2 [1 + sqrt(1 + 4 E^2 z^2 / (r^2 - E^2)^2)]   (inverting the definition above),
//   q(u) = (1/2)[(1 + 3u^2/E^2) atan(E/u) - 3u/E]  (H&M sec. 2-7), q0 = q(b).
// The last term of U is the centrifugal potential (1/2) w^2 (x^2 + y^2); this
// class returns V = U - that term, i.e. GRAVITATION ONLY, as the Field
// interface requires. g = grad V and Gamma = grad grad V are exact derivatives
// of the closed form, obtained by second-order forward automatic
// differentiation in long double in the two variables r^2 and z^2 (V is
// axially symmetric), then the chain rule to x, y, z (no finite differences,
// no series in r).
// q(u) is evaluated by its power series in t = E/u (derived from the series of
// atan), which avoids the 6-digit cancellation of the closed expression:
//   q = sum_{k>=1} (-1)^(k+1) 2k t^(2k+1) / ((2k+1)(2k+3)).
// Valid for u > 2E (about 1040 km from the centre); throws inside that.
#pragma once

#include "ggins/gravity/field.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <memory>

namespace ggins::gravity {

struct EllipsoidParams {
  Real a = wgs84::kA;        // semi-major axis, m
  Real f = wgs84::kF;        // flattening
  Real gm = wgs84::kGm;      // m^3/s^2
  Real omega = wgs84::kOmega;  // rad/s (enters the flattening part of V)
};

class NormalField final : public Field {
 public:
  explicit NormalField(const EllipsoidParams& p = EllipsoidParams{});
  FieldSample eval(const Vec3& r_e) const override;
  Vec3 gravitation(const Vec3& r_e) const override;  // first-order AD only (same bits as eval().g)
  // gravitation() at r + d[k], the central difference (Field::eval_pairs) at
  // r - d[k]. The dropped term (1/3) D^3G(r)[d, d, d]: for V = GM/r its norm
  // is at most 8 GM |d|^3 / r^5 (the maximum over directions of
  // |grad d_u^3 (1/r)| is 24/r^5, radially), times 1 + 15 J2 (a/r)^2 + ... for
  // the ellipsoid (the fourth derivatives of a degree-n zonal term carry
  // (n+4)!/n! against 4! for the point mass; 1.6 % measured radially):
  // 3.8e-20 m/s^2 for |d| = 0.5 m at r = b, below the long-double rounding of
  // G itself (ulp(9.8) = 8.7e-19). pair_truncation_bound() gives it with a
  // 5 % margin for the flattening; the next term, O(GM |d|^5 / r^7), is ~1e-33.
  FieldSample eval_pairs(const Vec3& r_e, const Vec3* d, std::size_t n, Vec3* plus, Vec3* minus) const override;
  Real pair_truncation_bound(const Vec3& r_e, Real d_norm) const;
  std::string name() const override { return "wgs84-normal"; }
  // Third derivatives from the equivalent zonal series (degree 20, J2n of
  // H&M eqs. (2-90), (2-92); J22 ~ 1e-24), exact to rounding for r > E.
  bool third(const Vec3& r_e, Tensor3& t) const override;
  // J2n of this ellipsoid (n = 1: J2), H&M eqs. (2-90) and (2-92).
  Real j2n(int n) const;
  const EllipsoidParams& params() const { return p_; }
  // Centrifugal potential and acceleration of the rotating frame, for callers
  // (and tests) that want normal GRAVITY = gravitation + centrifugal.
  Real centrifugal_potential(const Vec3& r_e) const;
  Vec3 centrifugal_acceleration(const Vec3& r_e) const;
  Real linear_eccentricity() const { return e_lin_; }

 private:
  template <class D>
  D potential_ad(const Vec3& r_e) const;  // V with its derivatives, forward-mode AD type D
  EllipsoidParams p_;
  Real b_, e_lin_, q0_;
  std::shared_ptr<const Field> zonal_;  // SphericalHarmonicField, max_order 3
};

}  // namespace ggins::gravity
