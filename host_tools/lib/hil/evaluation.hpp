// Error metrics of a flight against its truth, shared by the host-in-the-loop
// runner (both tasks), replay and Monte Carlo: the running final / max of one
// error quantity, order statistics of step times, and the errors of one
// navigation output against the truth at the same step.
//
//   2-D (errors2d): the flight's inertial frame, x equatorial, z polar (y
//       out of the flight plane); dr = r(nav) - r(true), dv, dG = G estimated -
//       true gravitation at the TRUE position; the gradient error is the largest
//       |element| of the x/z block (the 2-D firmware measures only that block).
//   3-D (errors3d): NED at the true position; see run3d/compare3d.hpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace ggins::hil {

// Final and largest |value| of one error quantity over a flight. latest: the
// sample belongs to the highest step seen so far (the final value is that of
// the last step flown). A NaN sample makes max NaN (it is never hidden).
struct MaxFinal {
  double max = 0, final = 0;
  void add(double x, bool latest = true) {
    if (latest) final = x;
    const double a = std::fabs(x);
    if (!(a <= max) && !std::isnan(max)) max = a;  // once NaN, max stays NaN
  }
  nlohmann::json json(double scale = 1.0) const { return {{"final", final * scale}, {"max", max * scale}}; }
};

struct Percentiles {
  double median = 0, p99 = 0, max = 0;
};

// Exact order statistics of cycle counts (ns) in bounded memory: one bin per
// tick below kBins (131 us at 1 ns/tick), the rare larger values kept as they are.
class CycleStats {
 public:
  void add(uint32_t c) {
    ++n_;
    if (c < kBins) {
      if (bins_.empty()) bins_.assign(kBins, 0);
      ++bins_[c];
    } else {
      big_.push_back(c);
    }
  }
  uint64_t n() const { return n_; }
  // value of rank round(q (n - 1)), 0-based
  Percentiles percentiles() {
    Percentiles p;
    if (n_ == 0) return p;
    std::sort(big_.begin(), big_.end());
    auto at = [&](double q) {
      uint64_t rank = static_cast<uint64_t>(q * static_cast<double>(n_ - 1) + 0.5);
      for (size_t c = 0; c < bins_.size(); ++c) {
        if (rank < bins_[c]) return static_cast<double>(c);
        rank -= bins_[c];
      }
      return static_cast<double>(big_[static_cast<size_t>(rank)]);
    };
    p.median = at(0.5);
    p.p99 = at(0.99);
    p.max = at(1.0);
    return p;
  }

 private:
  static constexpr uint32_t kBins = 1u << 17;
  std::vector<uint64_t> bins_;
  std::vector<uint32_t> big_;
  uint64_t n_ = 0;
};

// Errors of one 2-D output against the truth at its step. Truth: r, v, g (Vec3 of
// long double) and gamma (3x3); Out: a navigation output with r_i, v_i, g_i
// (double[3]) and gamma_i (double[3][3]): the firmware's gg_nav_output_t or its
// LCM message.
template <class Vec3>
struct Errors2 {
  Vec3 dr, dv, dg;
  typename Vec3::Scalar dgamma = 0;  // max |element| of the x/z block, s^-2
};

template <class Vec3, class Mat3, class Out>
Errors2<Vec3> errors2d(const Vec3& r, const Vec3& v, const Vec3& g, const Mat3& gamma, const Out& m) {
  using Real = typename Vec3::Scalar;
  Errors2<Vec3> e;
  for (int j = 0; j < 3; ++j) {
    e.dr(j) = static_cast<Real>(m.r_i[j]) - r(j);
    e.dv(j) = static_cast<Real>(m.v_i[j]) - v(j);
    e.dg(j) = static_cast<Real>(m.g_i[j]) - g(j);
  }
  for (int j : {0, 2})
    for (int i : {0, 2}) e.dgamma = std::max(e.dgamma, std::fabs(static_cast<Real>(m.gamma_i[j][i]) - gamma(j, i)));
  return e;
}

// Per-axis values as a JSON object {"x": .., "y": .., "z": ..} (or the names given).
inline nlohmann::json axes_json(const std::array<double, 3>& v, const char* a = "x", const char* b = "y",
                                const char* c = "z") {
  return {{a, v[0]}, {b, v[1]}, {c, v[2]}};
}

}  // namespace ggins::hil
