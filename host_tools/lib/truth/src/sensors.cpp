#include "ggins/truth/sensors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ggins::truth {

namespace {

// barometer streams (keyed by the [baro] seed and the sample index)
constexpr uint64_t kStreamBaroGm = 20, kStreamBaroNoise = 21, kStreamBaroDrop = 22, kStreamBaroOutlier = 23,
                   kStreamBaroInvalid = 24;

uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

uint64_t key(uint64_t seed, uint64_t stream, uint64_t k, uint64_t i, uint64_t j) {
  uint64_t h = splitmix64(seed);
  h = splitmix64(h ^ stream);
  h = splitmix64(h ^ k);
  h = splitmix64(h ^ (i << 8 | j));
  return h;
}

double to_unit(uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }  // [0, 1)

}  // namespace

double counter_uniform(uint64_t seed, uint64_t stream, uint64_t k, uint64_t i, uint64_t j) {
  return to_unit(key(seed, stream, k, i, j));
}

double counter_normal(uint64_t seed, uint64_t stream, uint64_t k, uint64_t i, uint64_t j) {
  const uint64_t h = key(seed, stream, k, i, j);
  const double u1 = 1.0 - to_unit(h);  // (0, 1]
  const double u2 = to_unit(splitmix64(h ^ 0x5bd1e995ULL));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

// ---- accelerometers ----------------------------------------------------------------------

AccelModel::AccelModel(const AccelErrorParams& p, int n_sensors, std::array<bool, 3> measured, SensorStreams streams)
    : p_(p), st_(streams) {
  for (int i = 0; i < n_sensors && i < kMaxAcc; ++i)
    for (int j = 0; j < 3; ++j) {
      const auto ui = static_cast<uint64_t>(i), uj = static_cast<uint64_t>(j);
      const auto si = static_cast<size_t>(i), sj = static_cast<size_t>(j);
      double b = 0, s = 0;
      if (measured[sj]) {
        b = p.bias_mps2[si][sj];
        s = p.scale[si][sj];
        if (p.bias_sigma_mps2 > 0) b += p.bias_sigma_mps2 * counter_normal(p.seed, st_.bias, 0, ui, uj);
        if (p.scale_sigma > 0) s += p.scale_sigma * counter_normal(p.seed, st_.scale, 0, ui, uj);
      }
      bias_[si][sj] = b;
      scale_[si][sj] = s;
    }
}

Real AccelModel::read(int64_t k, int i, int j, Real f) const {
  const auto si = static_cast<size_t>(i), sj = static_cast<size_t>(j);
  Real m = f * (1.0L + static_cast<Real>(scale_[si][sj])) + static_cast<Real>(bias_[si][sj]);
  if (p_.noise_sigma_mps2 > 0)
    m += static_cast<Real>(p_.noise_sigma_mps2 * counter_normal(p_.seed, st_.noise, static_cast<uint64_t>(k),
                                                                static_cast<uint64_t>(i), static_cast<uint64_t>(j)));
  return m;
}

// ---- gyros -------------------------------------------------------------------------------

GyroModel::GyroModel(const GyroErrorParams& p, SensorStreams streams) : p_(p), st_(streams) {
  for (size_t j = 0; j < 3; ++j) {
    bias_[j] = p.bias_radps[j];
    scale_[j] = p.scale[j];
    if (p.bias_sigma_radps > 0) bias_[j] += p.bias_sigma_radps * counter_normal(p.seed, st_.bias, 0, 0, j);
    if (p.scale_sigma > 0) scale_[j] += p.scale_sigma * counter_normal(p.seed, st_.scale, 0, 0, j);
  }
}

Real GyroModel::read(int64_t k, int j, Real w) const {
  const auto sj = static_cast<size_t>(j);
  Real m = w * (1.0L + static_cast<Real>(scale_[sj])) + static_cast<Real>(bias_[sj]);
  if (p_.noise_sigma_radps > 0)
    m += static_cast<Real>(p_.noise_sigma_radps * counter_normal(p_.seed, st_.noise, static_cast<uint64_t>(k), 0, sj));
  return m;
}

// ---- barometer ---------------------------------------------------------------------------

BaroModel::BaroModel(const BaroParams& p, int64_t every, int64_t n_steps, int64_t dt_us) : p_(p), every_(every) {
  if (!p.enable) return;
  const int64_t n = (n_steps - 1) / every_ + 1;
  const double T = static_cast<double>(every_ * dt_us) * 1e-6;
  const double phi = std::exp(-T / p.gm_tau_s), q = std::sqrt(1.0 - phi * phi);
  gm_.resize(static_cast<size_t>(std::max<int64_t>(n, 1)));
  double m = p.gm_sigma_m * counter_normal(p.seed, kStreamBaroGm, 0, 0, 0);
  for (int64_t j = 0; j < n; ++j) {
    if (j > 0) m = phi * m + p.gm_sigma_m * q * counter_normal(p.seed, kStreamBaroGm, static_cast<uint64_t>(j), 0, 0);
    gm_[static_cast<size_t>(j)] = m;
  }
}

BaroSample BaroModel::sample(int64_t k, double t_s, double true_alt_m) const {
  BaroSample b;
  b.true_alt_m = true_alt_m;
  if (!p_.enable || k % every_ != 0) return b;
  const auto j = static_cast<uint64_t>(k / every_);
  if (j >= gm_.size()) return b;  // beyond the run the sequence was drawn for
  b.due = true;
  for (const auto& w : p_.dropouts)
    if (t_s >= w[0] && t_s < w[1]) b.dropped = true;
  if (p_.dropout_prob > 0 && counter_uniform(p_.seed, kStreamBaroDrop, j, 0, 0) < p_.dropout_prob) b.dropped = true;
  b.gm_m = gm_[static_cast<size_t>(j)];
  b.error_m = p_.bias_m + b.gm_m;
  if (p_.noise_sigma_m > 0) b.error_m += p_.noise_sigma_m * counter_normal(p_.seed, kStreamBaroNoise, j, 0, 0);
  if (p_.outlier_prob > 0) {
    const double u = counter_uniform(p_.seed, kStreamBaroOutlier, j, 0, 0);
    if (u < p_.outlier_prob) {
      b.outlier = true;
      b.error_m += (u < 0.5 * p_.outlier_prob ? p_.outlier_m : -p_.outlier_m);
    }
  }
  if (p_.invalid_prob > 0 && counter_uniform(p_.seed, kStreamBaroInvalid, j, 0, 0) < p_.invalid_prob) b.invalid = true;
  if (b.dropped) return b;
  b.status = GG_SENSOR_OK;
  b.alt_m = b.invalid ? std::numeric_limits<double>::quiet_NaN() : b.true_alt_m + b.error_m;
  return b;
}

}  // namespace ggins::truth
