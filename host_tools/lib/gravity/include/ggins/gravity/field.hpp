// Gravitation field models for the host tools (truth generator, error
// analysis). One interface; every model gives the potential, the
// gravitation vector and the full gradient tensor at any point.
//
// Conventions (docs/design.md):
//   - positions in an Earth-fixed frame (_e) centred on the Earth's centre of
//     mass, metres; in the 2-D non-rotating case of Welker et al. this frame
//     is also the inertial frame (x equatorial, z polar);
//   - potential V > 0 (V = GM/r for a point mass), G = grad V (points toward
//     the mass), Gamma_jk = dG_j/dx_k (s^-2), symmetric, trace 0 outside masses;
//   - gravitation only: no centrifugal term (the rotating-Earth mechanization
//     adds it where it needs it).
// Evaluated in long double: the truth generator differences accelerometers
// 1 m apart at the 1e-12 m/s^2 level.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstddef>
#include <memory>
#include <string>
extern "C" {
#include "ggins/geo.h"  // the WGS-84 defining constants
}

namespace ggins::gravity {

using Real = long double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;

// Third derivatives of V: t[k](i, j) = d^3 V / dx_i dx_j dx_k = dGamma_ij/dx_k (s^-2 m^-1).
using Tensor3 = std::array<Mat3, 3>;

struct FieldSample {
  Real potential = 0;          // m^2/s^2
  Vec3 g = Vec3::Zero();       // gravitation, m/s^2
  Mat3 gamma = Mat3::Zero();   // gradient dG_j/dx_k, s^-2
};

// A field along a circle of latitude: the points
// p(lon) = (rho cos lon, rho sin lon, z) (Earth-fixed, m).
class FieldCircle {
 public:
  virtual ~FieldCircle() = default;
  // V, G, Gamma at p(lon). When dgamma is given, also the derivative of Gamma
  // along the direction e(lon) = e_rho (cos lon, sin lon, 0) + e_z (0, 0, 1)
  // fixed when the circle was made: sum_k T_k e_k (s^-2 per metre along e;
  // throws std::logic_error when the model has no third derivatives).
  virtual FieldSample eval(Real lon, Mat3* dgamma = nullptr) const = 0;
};

class Field {
 public:
  virtual ~Field() = default;
  // Field at r_e (m). Implementations must be thread-safe for concurrent const calls.
  virtual FieldSample eval(const Vec3& r_e) const = 0;
  virtual std::string name() const = 0;
  // Gravitation alone, eval(r_e).g; models for which G costs less than
  // (V, G, Gamma) override it (the normal field, lattices, sums, spherical
  // harmonics give the same bits as eval(r_e).g; PointMassAnomalyField its
  // double-precision sum, equal to rounding).
  virtual Vec3 gravitation(const Vec3& r_e) const { return eval(r_e).g; }
  // The field at r_e (as eval(r_e)) and the gravitation at the n pairs of
  // points r_e + d[k] (plus[k]) and r_e - d[k] (minus[k]): a rigid cluster of
  // sensors around r_e. This default calls gravitation() at every point. A
  // model whose G and Gamma are exact derivatives of one potential may take
  // the second point of a pair from the first by the central difference
  //   G(r - d) = G(r + d) - 2 Gamma(r) d - (1/3) D^3G(r)[d, d, d] - O(|d|^5)
  // (D^3G the fourth derivatives of V), dropping the cubic term; it then
  // documents its bound (NormalField).
  virtual FieldSample eval_pairs(const Vec3& r_e, const Vec3* d, std::size_t n, Vec3* plus, Vec3* minus) const;
  // The field on the circle of latitude through (rho, 0, z), with the
  // direction (e_rho, e_z) for FieldCircle::eval's dgamma (e.g. the ellipsoid
  // normal: e_rho = cos(geodetic latitude), e_z = sin). Models that share work
  // between the points of a circle override it; this default evaluates point
  // by point (eval(), and third() for dgamma). The circle refers to this
  // field: use it while the field lives; eval() is thread-safe like Field::eval.
  virtual std::unique_ptr<FieldCircle> circle(Real rho, Real z, Real e_rho = 0, Real e_z = 0) const;
  // Optional: third derivatives at r_e. Returns false (t untouched) when the
  // model does not provide them.
  virtual bool third(const Vec3& r_e, Tensor3& t) const {
    (void)r_e;
    (void)t;
    return false;
  }
};

// Spherical point-mass Earth: V = GM/r, G = -GM r/r^3,
// Gamma = (GM/r^3)(3 r^ r^T - I).
class PointMassField final : public Field {
 public:
  explicit PointMassField(Real gm = kGmWgs84) : gm_(gm) {}
  FieldSample eval(const Vec3& r_e) const override;
  std::string name() const override { return "point-mass"; }
  bool third(const Vec3& r_e, Tensor3& t) const override;
  Real gm() const { return gm_; }

  static constexpr Real kGmWgs84 = GG_WGS84_GM_M3PS2;  // m^3/s^2 (WGS-84, NIMA TR8350.2)
 private:
  Real gm_;
};

}  // namespace ggins::gravity
