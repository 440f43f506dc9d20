#include "ggins/gravity/lattice.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace ggins::gravity {

std::atomic<std::uint64_t> LatticeField::next_id_{1};

LatticeField::LatticeField(std::shared_ptr<const Field> source, LatticeOptions opt)
    : src_(std::move(source)), opt_(opt), id_(next_id_++) {
  if (!src_) throw std::invalid_argument("LatticeField: null source");
  if (opt_.points < 2 || opt_.points > 16 || opt_.points % 2) throw std::invalid_argument("LatticeField: points must be even, 2..16");
  if (!(opt_.spacing > 0)) throw std::invalid_argument("LatticeField: spacing must be positive");
  const int p = opt_.points;
  denom_.assign(p, 1.0);
  for (int i = 0; i < p; ++i)
    for (int j = 0; j < p; ++j)
      if (j != i) denom_[i] *= static_cast<double>(i - j);
}

std::string LatticeField::name() const {
  return "lattice(" + src_->name() + ", h=" + std::to_string(static_cast<double>(opt_.spacing)) + " m, p=" + std::to_string(opt_.points) + ")";
}

std::size_t LatticeField::nodes_computed() const {
  std::lock_guard<std::mutex> lk(mu_);
  return cache_.size();
}

LatticeField::Node LatticeField::node(const Key& k) const {
  {
    std::lock_guard<std::mutex> lk(mu_);
    const auto it = cache_.find(k);
    if (it != cache_.end()) return it->second;
  }
  const Vec3 r = opt_.origin + opt_.spacing * Vec3(static_cast<Real>(k.i), static_cast<Real>(k.j), static_cast<Real>(k.k));
  const FieldSample s = src_->eval(r);
  const Node n{static_cast<double>(s.potential), static_cast<double>(s.g.x()), static_cast<double>(s.g.y()),
               static_cast<double>(s.g.z()), static_cast<double>(s.gamma(0, 0)), static_cast<double>(s.gamma(0, 1)),
               static_cast<double>(s.gamma(0, 2)), static_cast<double>(s.gamma(1, 1)), static_cast<double>(s.gamma(1, 2)),
               static_cast<double>(s.gamma(2, 2))};
  std::lock_guard<std::mutex> lk(mu_);
  cache_.emplace(k, n);
  return n;
}

FieldSample LatticeField::eval(const Vec3& r) const {
  const int p = opt_.points, half = p / 2;
  const Vec3 u = (r - opt_.origin) / opt_.spacing;
  if (!u.allFinite()) throw std::domain_error("LatticeField: position not finite");
  Key base{};
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const Real fl = std::floor(u[a]);
    const std::int64_t b = static_cast<std::int64_t>(fl) - (half - 1);
    (a == 0 ? base.i : a == 1 ? base.j : base.k) = b;
    t[a] = static_cast<double>(u[a] - static_cast<Real>(b));  // in [half-1, half)
  }
  // Per-thread stencil cache: consecutive queries in one cell reuse it.
  struct Stencil {
    std::uint64_t owner = 0;
    Key base{};
    std::vector<Node> v;
  };
  thread_local Stencil st;
  if (st.owner != id_ || !(st.base == base) || st.v.size() != static_cast<std::size_t>(p * p * p)) {
    st.v.resize(static_cast<std::size_t>(p) * p * p);
    for (int i = 0; i < p; ++i)
      for (int j = 0; j < p; ++j)
        for (int k = 0; k < p; ++k)
          st.v[(static_cast<std::size_t>(i) * p + j) * p + k] = node(Key{base.i + i, base.j + j, base.k + k});
    st.owner = id_;
    st.base = base;
  }
  // Lagrange weights on nodes 0..p-1.
  double w[3][16];
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < p; ++i) {
      double num = 1.0;
      for (int j = 0; j < p; ++j)
        if (j != i) num *= (t[a] - j);
      w[a][i] = num / denom_[i];
    }
  double acc[10] = {0};
  for (int i = 0; i < p; ++i) {
    double accj[10] = {0};
    for (int j = 0; j < p; ++j) {
      double acck[10] = {0};
      const Node* row = &st.v[(static_cast<std::size_t>(i) * p + j) * p];
      for (int k = 0; k < p; ++k) {
        const double wk = w[2][k];
        for (int c = 0; c < 10; ++c) acck[c] += wk * row[k][c];
      }
      for (int c = 0; c < 10; ++c) accj[c] += w[1][j] * acck[c];
    }
    for (int c = 0; c < 10; ++c) acc[c] += w[0][i] * accj[c];
  }
  FieldSample s;
  s.potential = acc[0];
  s.g = Vec3(acc[1], acc[2], acc[3]);
  s.gamma << acc[4], acc[5], acc[6], acc[5], acc[7], acc[8], acc[6], acc[8], acc[9];
  return s;
}

FastField::FastField(std::shared_ptr<const NormalField> normal, std::shared_ptr<const Field> anomaly, LatticeOptions opt)
    : normal_(std::move(normal)), lattice_(std::move(anomaly), opt) {
  if (!normal_) throw std::invalid_argument("FastField: null normal field");
}

FieldSample FastField::eval(const Vec3& r) const {
  FieldSample s = normal_->eval(r);
  const FieldSample a = lattice_.eval(r);
  s.potential += a.potential;
  s.g += a.g;
  s.gamma += a.gamma;
  return s;
}

std::string FastField::name() const { return "fast(" + normal_->name() + " + " + lattice_.name() + ")"; }

}  // namespace ggins::gravity
