#include "ggins/gravity/lattice.hpp"

#include "ggins/gravity/composite.hpp"

#include <array>
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

const std::vector<LatticeField::Node>& LatticeField::stencil(const Vec3& r, double w[3][16]) const {
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
  // Per-thread stencil cache (4 slots keyed by lattice and cell, round robin):
  // consecutive queries in one cell reuse the gathered node values, also when
  // the accelerometers straddle a cell face or two lattices are in use.
  struct Stencil {
    std::uint64_t owner = 0;
    Key base{};
    std::vector<Node> v;
  };
  thread_local Stencil slots[4];
  thread_local unsigned next_slot = 0;
  Stencil* found = nullptr;
  for (Stencil& c : slots)
    if (c.owner == id_ && c.base == base) { found = &c; break; }
  if (!found) { found = &slots[next_slot++ % 4]; found->owner = 0; }
  Stencil& st = *found;
  if (st.owner != id_ || !(st.base == base) || st.v.size() != static_cast<std::size_t>(p * p * p)) {
    st.owner = 0;  // invalid until fully gathered (node() may throw)
    st.v.resize(static_cast<std::size_t>(p) * p * p);
    for (int i = 0; i < p; ++i)
      for (int j = 0; j < p; ++j)
        for (int k = 0; k < p; ++k)
          st.v[(static_cast<std::size_t>(i) * p + j) * p + k] = node(Key{base.i + i, base.j + j, base.k + k});
    st.owner = id_;
    st.base = base;
  }
  // Lagrange weights on nodes 0..p-1.
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < p; ++i) {
      double num = 1.0;
      for (int j = 0; j < p; ++j)
        if (j != i) num *= (t[a] - j);
      w[a][i] = num / denom_[i];
    }
  return st.v;
}

namespace {
// Tensor-product contraction of node components C0 .. C0+NC-1 with the weights
// (the same loops for every component count, so each component gets the same bits).
template <int C0, int NC>
void contract(const std::vector<LatticeField::Node>& v, const double w[3][16], int p, double acc[NC]) {
  for (int c = 0; c < NC; ++c) acc[c] = 0;
  for (int i = 0; i < p; ++i) {
    double accj[NC] = {0};
    for (int j = 0; j < p; ++j) {
      double acck[NC] = {0};
      const LatticeField::Node* row = &v[(static_cast<std::size_t>(i) * p + j) * p];
      for (int k = 0; k < p; ++k) {
        const double wk = w[2][k];
        for (int c = 0; c < NC; ++c) acck[c] += wk * row[k][C0 + c];
      }
      for (int c = 0; c < NC; ++c) accj[c] += w[1][j] * acck[c];
    }
    for (int c = 0; c < NC; ++c) acc[c] += w[0][i] * accj[c];
  }
}
}  // namespace

FieldSample LatticeField::eval(const Vec3& r) const {
  double w[3][16], acc[10];
  contract<0, 10>(stencil(r, w), w, opt_.points, acc);
  FieldSample s;
  s.potential = acc[0];
  s.g = Vec3(acc[1], acc[2], acc[3]);
  s.gamma << acc[4], acc[5], acc[6], acc[5], acc[7], acc[8], acc[6], acc[8], acc[9];
  return s;
}

Vec3 LatticeField::gravitation(const Vec3& r) const {
  double w[3][16], acc[3];
  contract<1, 3>(stencil(r, w), w, opt_.points, acc);
  return Vec3(acc[0], acc[1], acc[2]);
}

FastField::FastField(std::shared_ptr<const NormalField> normal, std::shared_ptr<const Field> fast_anomaly)
    : normal_(std::move(normal)), anomaly_(std::move(fast_anomaly)) {
  if (!normal_ || !anomaly_) throw std::invalid_argument("FastField: null field");
}

FastField::FastField(std::shared_ptr<const NormalField> normal, std::shared_ptr<const Field> smooth_anomaly, LatticeOptions opt)
    : FastField(std::move(normal), std::make_shared<LatticeField>(std::move(smooth_anomaly), opt)) {}

FieldSample FastField::eval(const Vec3& r) const {
  FieldSample s = normal_->eval(r);
  const FieldSample a = anomaly_->eval(r);
  s.potential += a.potential;
  s.g += a.g;
  s.gamma += a.gamma;
  return s;
}

Vec3 FastField::gravitation(const Vec3& r) const { return normal_->gravitation(r) + anomaly_->gravitation(r); }

FieldSample FastField::eval_pairs(const Vec3& r, const Vec3* d, std::size_t n, Vec3* plus, Vec3* minus) const {
  FieldSample s = normal_->eval_pairs(r, d, n, plus, minus);
  for (std::size_t k = 0; k < n; ++k) {
    plus[k] += anomaly_->gravitation(r + d[k]);
    minus[k] += anomaly_->gravitation(r - d[k]);
  }
  const FieldSample a = anomaly_->eval(r);
  s.potential += a.potential;
  s.g += a.g;
  s.gamma += a.gamma;
  return s;
}

std::shared_ptr<const Field> FastField::exact() const {
  const auto* l = dynamic_cast<const LatticeField*>(anomaly_.get());
  if (l == nullptr) return nullptr;
  return std::make_shared<SumField>(
      std::vector<std::pair<Real, std::shared_ptr<const Field>>>{{1.0L, normal_}, {1.0L, l->source()}},
      normal_->name() + " + " + l->source()->name());
}

std::string FastField::name() const { return "fast(" + normal_->name() + " + " + anomaly_->name() + ")"; }

// ---- Ewald-split point masses ----------------------------------------------

namespace {

// Long-range kernel f(rho) = erf(rho/sigma)/rho written as f = c S(y),
// y = rho^2/sigma^2, c = 2/(sqrt(pi) sigma), S(y) = sum_n (-1)^n y^n / (n! (2n+1))
// (series of erf, Abramowitz & Stegun 7.1.5). With d = r - r_i:
//   grad f = c S'(y) 2d/sigma^2,   grad grad f = c [S''(y) 4 d d^T/sigma^4 + S'(y) 2I/sigma^2].
// For y < 1 S, S', S'' by the series (no cancellation); beyond, by the closed forms
//   f' = G/rho - erf/rho^2, f'' = -2G/sigma^2 - 2G/rho^2 + 2 erf/rho^3, G = c e^{-y},
//   grad f = f' u, grad grad f = f'' u u^T + f'/rho (I - u u^T).
// Evaluated in double: the anomaly sums are < 1e-2 m/s^2, so double rounding
// (~1e-18 m/s^2 per term) is far below the 1e-13 m/s^2 budget.
struct Kernel { double f, a, b; };  // f, grad f = a d, grad grad f = b d d^T + a I
inline Kernel erf_kernel(double dx, double dy, double dz, double sigma) {
  const double c = 2.0 / (std::sqrt(M_PI) * sigma);
  const double r2 = dx * dx + dy * dy + dz * dz, is2 = 1.0 / (sigma * sigma), y = r2 * is2;
  Kernel k{};
  if (y < 1) {
    // S(y) = sum_{n<=22} a_n y^n, a_n = (-1)^n / (n! (2n+1)) (term < 1e-23 for y < 1);
    // S' and S'' by Horner on n a_n and n(n-1) a_n.
    static const auto an = [] {
      std::array<double, 23> t{};
      double fact = 1;
      for (int n = 0; n < 23; ++n) {
        if (n > 1) fact *= n;
        t[n] = ((n % 2) ? -1.0 : 1.0) / (fact * (2 * n + 1));
      }
      return t;
    }();
    double s0 = 0, s1 = 0, s2 = 0;
    for (int n = 22; n >= 0; --n) s0 = s0 * y + an[n];
    for (int n = 22; n >= 1; --n) s1 = s1 * y + n * an[n];
    for (int n = 22; n >= 2; --n) s2 = s2 * y + n * (n - 1) * an[n];
    k.f = c * s0;
    k.a = c * s1 * 2 * is2;
    k.b = c * s2 * 4 * is2 * is2;
    return k;
  }
  if (y > 42.25) {  // rho > 6.5 sigma: erf = 1 - 4e-20, exp(-y) < 5e-19: plain 1/rho
    const double ir2 = 1.0 / r2, ir = std::sqrt(ir2);
    k.f = ir;
    k.a = -ir * ir2;
    k.b = 3 * ir * ir2 * ir2;
    return k;
  }
  const double rho = std::sqrt(r2), e = std::erf(rho / sigma), G = c * std::exp(-y);
  const double f1 = G / rho - e / r2;
  const double f2 = -2 * G * is2 - 2 * G / r2 + 2 * e / (r2 * rho);
  k.f = e / rho;
  k.a = f1 / rho;                  // grad f = (f'/rho) d
  k.b = (f2 - f1 / rho) / r2;      // grad grad f = (f'' - f'/rho) u u^T + f'/rho I
  return k;
}

struct Acc {
  double v = 0, gx = 0, gy = 0, gz = 0, xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  void add(double gm, double dx, double dy, double dz, double f, double a, double b) {
    v += gm * f;
    gx += gm * a * dx; gy += gm * a * dy; gz += gm * a * dz;  // G = grad V = gm (f'/rho) d
    const double gb = gm * b, ga = gm * a;
    xx += gb * dx * dx + ga; yy += gb * dy * dy + ga; zz += gb * dz * dz + ga;
    xy += gb * dx * dy; xz += gb * dx * dz; yz += gb * dy * dz;
  }
  FieldSample sample() const {
    FieldSample s;
    s.potential = v;
    s.g = Vec3(gx, gy, gz);
    s.gamma << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return s;
  }
};

}  // namespace

ErfPointMassField::ErfPointMassField(std::shared_ptr<const std::vector<PointMass>> masses, Real sigma)
    : masses_(std::move(masses)), sigma_(sigma) {}

FieldSample ErfPointMassField::eval(const Vec3& r) const {
  Acc acc;
  const double sg = static_cast<double>(sigma_);
  for (const PointMass& m : *masses_) {
    const double dx = static_cast<double>(r.x() - m.r_e.x()), dy = static_cast<double>(r.y() - m.r_e.y()),
                 dz = static_cast<double>(r.z() - m.r_e.z());
    const Kernel k = erf_kernel(dx, dy, dz, sg);
    acc.add(static_cast<double>(m.gm), dx, dy, dz, k.f, k.a, k.b);
  }
  return acc.sample();
}

}  // namespace ggins::gravity

namespace ggins::gravity {

SplitPointMassField::SplitPointMassField(const std::vector<PointMass>& masses, Real sigma, LatticeOptions far)
    : masses_(std::make_shared<const std::vector<PointMass>>(masses)),
      sigma_(sigma),
      cell_(6.5L * sigma),
      far_(std::make_shared<ErfPointMassField>(masses_, sigma), far) {
  if (!(sigma > 0)) throw std::invalid_argument("SplitPointMassField: sigma must be positive");
  for (std::uint32_t i = 0; i < masses_->size(); ++i) {
    const Vec3& p = (*masses_)[i].r_e;
    cells_[{static_cast<std::int64_t>(std::floor(p.x() / cell_)), static_cast<std::int64_t>(std::floor(p.y() / cell_)),
            static_cast<std::int64_t>(std::floor(p.z() / cell_))}]
        .push_back(i);
  }
}

std::string SplitPointMassField::name() const {
  return "split-point-masses(n=" + std::to_string(masses_->size()) + ", sigma=" + std::to_string(static_cast<double>(sigma_)) +
         " m, far: " + far_.name() + ")";
}

FieldSample SplitPointMassField::eval(const Vec3& r) const {
  Acc acc;
  const std::int64_t c[3] = {static_cast<std::int64_t>(std::floor(r.x() / cell_)), static_cast<std::int64_t>(std::floor(r.y() / cell_)),
                             static_cast<std::int64_t>(std::floor(r.z() / cell_))};
  const double cut2 = static_cast<double>(cell_ * cell_), sg = static_cast<double>(sigma_);
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k) {
        const auto it = cells_.find({c[0] + i, c[1] + j, c[2] + k});
        if (it == cells_.end()) continue;
        for (std::uint32_t idx : it->second) {
          const PointMass& m = (*masses_)[idx];
          const double dx = static_cast<double>(r.x() - m.r_e.x()), dy = static_cast<double>(r.y() - m.r_e.y()),
                       dz = static_cast<double>(r.z() - m.r_e.z());
          const double r2 = dx * dx + dy * dy + dz * dz;
          if (r2 >= cut2) continue;
          if (!(r2 > 0)) throw std::domain_error("SplitPointMassField: evaluation at a mass");
          // short range = exact point mass - erf kernel (= gm erfc(rho/sigma)/rho)
          const double ir2 = 1.0 / r2, ir = std::sqrt(ir2);
          const Kernel e = erf_kernel(dx, dy, dz, sg);
          // 1/rho: f = ir, a = -ir^3, b = 3 ir^5
          acc.add(static_cast<double>(m.gm), dx, dy, dz, ir - e.f, -ir * ir2 - e.a, 3 * ir * ir2 * ir2 - e.b);
        }
      }
  FieldSample s = far_.eval(r);
  const FieldSample n = acc.sample();
  s.potential += n.potential;
  s.g += n.g;
  s.gamma += n.gamma;
  return s;
}

}  // namespace ggins::gravity
