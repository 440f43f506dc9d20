// Linear combinations of fields: total = normal + anomaly, anomaly = total - normal.
#pragma once

#include "ggins/gravity/field.hpp"

#include <memory>
#include <utility>
#include <vector>

namespace ggins::gravity {

class SumField final : public Field {
 public:
  // sum_i weight_i * field_i (weights typically +1 / -1)
  SumField(std::vector<std::pair<Real, std::shared_ptr<const Field>>> terms, std::string label = "");
  FieldSample eval(const Vec3& r_e) const override;
  Vec3 gravitation(const Vec3& r_e) const override;
  std::unique_ptr<FieldCircle> circle(Real rho, Real z, Real e_rho = 0, Real e_z = 0) const override;  // the terms' circles
  std::string name() const override;
  bool third(const Vec3& r_e, Tensor3& t) const override;  // when every term provides it

 private:
  std::vector<std::pair<Real, std::shared_ptr<const Field>>> terms_;
  std::string label_;
};

}  // namespace ggins::gravity
