#include "ggins/gravity/field.hpp"

#include "detail.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::gravity {

namespace {
class PointByPointCircle final : public FieldCircle {
 public:
  PointByPointCircle(const Field& f, Real rho, Real z, Real e_rho, Real e_z) : f_(f), rho_(rho), z_(z), er_(e_rho), ez_(e_z) {}
  FieldSample eval(Real lon, Mat3* dgamma) const override {
    const Real c = std::cos(lon), s = std::sin(lon);
    const Vec3 p(rho_ * c, rho_ * s, z_);
    if (dgamma) {
      dgamma->setZero();
      if (er_ != 0 || ez_ != 0) {
        Tensor3 t;
        if (!f_.third(p, t)) throw std::logic_error("FieldCircle: " + f_.name() + " has no third derivatives");
        *dgamma = t[0] * (er_ * c) + t[1] * (er_ * s) + t[2] * ez_;
      }
    }
    return f_.eval(p);
  }

 private:
  const Field& f_;
  Real rho_, z_, er_, ez_;
};
}  // namespace

FieldSample Field::eval_pairs(const Vec3& r, const Vec3* d, std::size_t n, Vec3* plus, Vec3* minus) const {
  for (std::size_t k = 0; k < n; ++k) {
    plus[k] = gravitation(r + d[k]);
    minus[k] = gravitation(r - d[k]);
  }
  return eval(r);
}

std::unique_ptr<FieldCircle> Field::circle(Real rho, Real z, Real e_rho, Real e_z) const {
  return std::make_unique<PointByPointCircle>(*this, rho, z, e_rho, e_z);
}

FieldSample PointMassField::eval(const Vec3& r_e) const {
  const Real r2 = r_e.squaredNorm();
  if (!(r2 > 0) || !std::isfinite(r2)) throw std::domain_error("PointMassField: position at the centre or not finite");
  const Real r = std::sqrt(r2);
  const Real gm_r3 = gm_ / (r2 * r);
  const Vec3 u = r_e / r;
  FieldSample s;
  s.potential = gm_ / r;
  s.g = -gm_r3 * r_e;
  s.gamma = gm_r3 * (3.0L * u * u.transpose() - Mat3::Identity());
  return s;
}

// d^3(1/r)/dx_i dx_j dx_k = 3 (delta_ij x_k + delta_ik x_j + delta_jk x_i)/r^5 - 15 x_i x_j x_k / r^7
void add_point_mass_third(Real gm, const Vec3& d, Tensor3& t) {
  const Real r2 = d.squaredNorm(), r = std::sqrt(r2), i5 = gm / (r2 * r2 * r), i7 = i5 / r2;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real dd = (i == j ? d[k] : 0) + (i == k ? d[j] : 0) + (j == k ? d[i] : 0);
        t[k](i, j) += 3 * dd * i5 - 15 * d[i] * d[j] * d[k] * i7;
      }
}

bool PointMassField::third(const Vec3& r_e, Tensor3& t) const {
  const Real r2 = r_e.squaredNorm();
  if (!(r2 > 0) || !std::isfinite(r2)) throw std::domain_error("PointMassField: position at the centre or not finite");
  for (Mat3& m : t) m.setZero();
  add_point_mass_third(gm_, r_e, t);
  return true;
}

}  // namespace ggins::gravity
