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
