// Fast path for long high-rate flights.
//
// LatticeField: a smooth source field (normally an ANOMALY: total minus
// normal) sampled lazily on a regular 3-D lattice in Earth-fixed axes, nodes
// at origin + h (i, j, k), and interpolated by tensor-product Lagrange
// polynomials through the p x p x p nodes around the query point (p even;
// the query lies in the central cell). Potential, the three components of G
// and the six of Gamma are interpolated independently (each from its own node
// values, so Gamma is not a derivative of the G interpolant). Nodes are
// computed on first use and kept (thread-safe cache), so a flight only pays
// for the tube of nodes around its path; consecutive queries in one cell
// reuse the gathered stencil (per thread).
// Error of degree p-1 interpolation: |f - P| <= max|f^(p)| / p! * prod |t - t_i| h^p
// per axis (e.g. Davis 1975, "Interpolation and Approximation", thm 3.1.1);
// tests/gravity/test_fast.cpp measures it against the exact field.
//
// SplitPointMassField: a point-mass anomaly field split as in Ewald summation,
//   1/rho = erfc(rho/sigma)/rho + erf(rho/sigma)/rho:
// the short-range part (erfc) is summed exactly over the masses within
// 6.5 sigma of the query (erfc(6.5) = 4e-20; a spatial hash finds them); the
// long-range part (erf), an entire function with a Gaussian spectrum
// exp(-k^2 sigma^2/4), is smooth on the scale sigma everywhere (also near
// and at the masses) and goes on a LatticeField. So the lattice spacing is
// set by sigma, not by the distance to the nearest mass.
//
// FastField: the WGS-84 normal field evaluated exactly at every call plus a
// fast anomaly field (a LatticeField of a smooth anomaly such as EGM96 minus
// normal, or a SplitPointMassField).
#pragma once

#include "ggins/gravity/field.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/point_anomaly.hpp"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace ggins::gravity {

struct LatticeOptions {
  Real spacing = 2000.0L;        // node spacing h, m
  int points = 8;                // p nodes per axis (even, 2..16)
  Vec3 origin = Vec3::Zero();    // lattice origin, Earth-fixed, m
};

class LatticeField final : public Field {
 public:
  LatticeField(std::shared_ptr<const Field> source, LatticeOptions opt);
  FieldSample eval(const Vec3& r_e) const override;
  Vec3 gravitation(const Vec3& r_e) const override;  // interpolates the three components of G only
  std::string name() const override;
  std::size_t nodes_computed() const;
  const LatticeOptions& options() const { return opt_; }
  const std::shared_ptr<const Field>& source() const { return src_; }  // the field sampled
  using Node = std::array<double, 10>;  // V, gx, gy, gz, xx, xy, xz, yy, yz, zz

 private:
  struct Key {
    std::int64_t i, j, k;
    bool operator==(const Key& o) const { return i == o.i && j == o.j && k == o.k; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = static_cast<std::uint64_t>(k.i) * 0x9E3779B97F4A7C15ull;
      h ^= static_cast<std::uint64_t>(k.j) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
      h ^= static_cast<std::uint64_t>(k.k) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
      return static_cast<std::size_t>(h);
    }
  };
  Node node(const Key& k) const;
  // Gathers the stencil around r_e (per-thread cache) and its Lagrange weights.
  const std::vector<Node>& stencil(const Vec3& r_e, double w[3][16]) const;

  std::shared_ptr<const Field> src_;
  LatticeOptions opt_;
  std::uint64_t id_;
  std::vector<double> denom_;
  mutable std::mutex mu_;
  mutable std::unordered_map<Key, Node, KeyHash> cache_;
  static std::atomic<std::uint64_t> next_id_;
};

// Long-range part sum_i gm_i erf(rho_i/sigma)/rho_i, exact (a lattice source).
class ErfPointMassField final : public Field {
 public:
  ErfPointMassField(std::shared_ptr<const std::vector<PointMass>> masses, Real sigma);
  FieldSample eval(const Vec3& r_e) const override;
  std::string name() const override { return "erf-point-masses"; }

 private:
  std::shared_ptr<const std::vector<PointMass>> masses_;
  Real sigma_;
};

class SplitPointMassField final : public Field {
 public:
  SplitPointMassField(const std::vector<PointMass>& masses, Real sigma, LatticeOptions far);
  FieldSample eval(const Vec3& r_e) const override;
  std::string name() const override;
  const LatticeField& lattice() const { return far_; }
  Real sigma() const { return sigma_; }

 private:
  struct CellHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
      return static_cast<std::size_t>((k[0] * 73856093) ^ (k[1] * 19349663) ^ (k[2] * 83492791));
    }
  };
  std::shared_ptr<const std::vector<PointMass>> masses_;
  Real sigma_, cell_;
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>, CellHash> cells_;
  LatticeField far_;
};

class FastField final : public Field {
 public:
  // fast_anomaly: the field added to the exact normal one.
  FastField(std::shared_ptr<const NormalField> normal, std::shared_ptr<const Field> fast_anomaly);
  // Convenience: smooth anomaly (e.g. SumField{+EGM96, -normal}) on a LatticeField.
  FastField(std::shared_ptr<const NormalField> normal, std::shared_ptr<const Field> smooth_anomaly, LatticeOptions opt);
  FieldSample eval(const Vec3& r_e) const override;
  Vec3 gravitation(const Vec3& r_e) const override;
  // The normal field's eval_pairs (its central difference) plus the anomaly at
  // every point (its own G and Gamma are separate interpolants).
  FieldSample eval_pairs(const Vec3& r_e, const Vec3* d, std::size_t n, Vec3* plus, Vec3* minus) const override;
  std::string name() const override;
  const Field& anomaly() const { return *anomaly_; }
  // The model this fast path approximates, without the lattice: normal + the lattice's
  // source (a SumField, whose circles share the source's work along a row, e.g. the
  // Legendre sums of spherical harmonics), for products that want the model itself (map
  // tiles); nullptr when the anomaly is not a LatticeField (split point masses).
  std::shared_ptr<const Field> exact() const;

 private:
  std::shared_ptr<const NormalField> normal_;
  std::shared_ptr<const Field> anomaly_;
};

}  // namespace ggins::gravity
