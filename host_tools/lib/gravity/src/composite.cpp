#include "ggins/gravity/composite.hpp"

#include <stdexcept>

namespace ggins::gravity {

SumField::SumField(std::vector<std::pair<Real, std::shared_ptr<const Field>>> terms, std::string label)
    : terms_(std::move(terms)), label_(std::move(label)) {
  for (const auto& t : terms_)
    if (!t.second) throw std::invalid_argument("SumField: null field");
}

FieldSample SumField::eval(const Vec3& r) const {
  FieldSample s;
  for (const auto& [w, f] : terms_) {
    const FieldSample t = f->eval(r);
    s.potential += w * t.potential;
    s.g += w * t.g;
    s.gamma += w * t.gamma;
  }
  return s;
}

Vec3 SumField::gravitation(const Vec3& r) const {
  Vec3 g = Vec3::Zero();
  for (const auto& [w, f] : terms_) g += w * f->gravitation(r);
  return g;
}

namespace {
class SumCircle final : public FieldCircle {
 public:
  std::vector<std::pair<Real, std::unique_ptr<FieldCircle>>> terms;
  FieldSample eval(Real lon, Mat3* dgamma) const override {
    FieldSample s;
    if (dgamma) dgamma->setZero();
    for (const auto& [w, c] : terms) {
      Mat3 d;
      const FieldSample t = c->eval(lon, dgamma ? &d : nullptr);
      s.potential += w * t.potential;
      s.g += w * t.g;
      s.gamma += w * t.gamma;
      if (dgamma) *dgamma += w * d;
    }
    return s;
  }
};
}  // namespace

std::unique_ptr<FieldCircle> SumField::circle(Real rho, Real z, Real e_rho, Real e_z) const {
  auto c = std::make_unique<SumCircle>();
  for (const auto& [w, f] : terms_) c->terms.emplace_back(w, f->circle(rho, z, e_rho, e_z));
  return c;
}

bool SumField::third(const Vec3& r, Tensor3& t) const {
  Tensor3 acc;
  for (Mat3& m : acc) m.setZero();
  for (const auto& [w, f] : terms_) {
    Tensor3 one;
    if (!f->third(r, one)) return false;
    for (int k = 0; k < 3; ++k) acc[k] += w * one[k];
  }
  t = acc;
  return true;
}

std::string SumField::name() const {
  if (!label_.empty()) return label_;
  std::string n;
  for (const auto& [w, f] : terms_) n += (w < 0 ? " - " : (n.empty() ? "" : " + ")) + f->name();
  return n;
}

}  // namespace ggins::gravity
