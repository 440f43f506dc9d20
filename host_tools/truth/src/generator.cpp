#include "ggins/truth/generator.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace ggins::truth {

namespace {

constexpr uint64_t kStreamBias = 1, kStreamScale = 2, kStreamNoise = 3;

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
  const double u1 = 1.0 - to_unit(h);             // (0, 1]
  const double u2 = to_unit(splitmix64(h ^ 0x5bd1e995ULL));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

std::unique_ptr<Trajectory> make_trajectory(const Scenario& s) {
  if (s.trajectory.type == "north-flight") {
    const Real deg = 3.14159265358979323846264338327950288L / 180.0L;
    return std::make_unique<NorthFlight>(s.trajectory.speed_mps, s.trajectory.height_m,
                                         static_cast<Real>(s.trajectory.lat0_deg) * deg, s.trajectory.radius_m);
  }
  throw std::invalid_argument("unknown trajectory type " + s.trajectory.type);
}

std::unique_ptr<gravity::Field> make_field(const Scenario& s) {
  if (s.gravity.model == "point-mass") return std::make_unique<gravity::PointMassField>(s.gravity.gm_m3ps2);
  throw std::invalid_argument("unknown gravity model " + s.gravity.model);
}

Generator::Generator(const Scenario& s)
    : sc_(s), traj_(make_trajectory(s)), field_(make_field(s)), dt_us_(s.dt_us()), n_steps_(s.n_steps()),
      n_acc_(s.n_acc()) {
  const Real a = s.a_m, b = s.b_m;
  offsets_[0] = Vec3(a, 0, 0);
  offsets_[1] = Vec3(0, 0, b);
  offsets_[2] = Vec3(-a, 0, 0);
  offsets_[3] = Vec3(0, 0, -b);
  axes_ = {0, 2, -1};
  n_axes_ = 2;
  for (int i = 0; i < n_acc_; ++i) {
    for (int j = 0; j < 3; ++j) {
      auto ui = static_cast<uint64_t>(i), uj = static_cast<uint64_t>(j);
      double bias = s.accel.bias_mps2[static_cast<size_t>(i)][static_cast<size_t>(j)];
      double scale = s.accel.scale[static_cast<size_t>(i)][static_cast<size_t>(j)];
      const bool measured = (j == axes_[0] || j == axes_[1]);
      if (measured) {
        if (s.accel.bias_sigma_mps2 > 0)
          bias += s.accel.bias_sigma_mps2 * counter_normal(s.accel.seed, kStreamBias, 0, ui, uj);
        if (s.accel.scale_sigma > 0)
          scale += s.accel.scale_sigma * counter_normal(s.accel.seed, kStreamScale, 0, ui, uj);
      } else {
        bias = 0;
        scale = 0;
      }
      bias_[static_cast<size_t>(i)][static_cast<size_t>(j)] = bias;
      scale_[static_cast<size_t>(i)][static_cast<size_t>(j)] = scale;
    }
  }
}

Real Generator::time_of(int64_t k) const {
  return static_cast<Real>(k) * static_cast<Real>(dt_us_) * 1e-6L;
}

TruthState Generator::truth(int64_t k) const {
  TruthState t;
  t.seq = k;
  t.utime = k * dt_us_;
  t.t_s = time_of(k);
  t.kin = traj_->at(t.t_s);
  const gravity::FieldSample c = field_->eval(t.kin.r);
  t.g = c.g;
  t.gamma = c.gamma;
  t.f_c = t.kin.a - c.g;
  return t;
}

void Generator::frame(int64_t k, gg_frame_t& out, TruthState* truth_out) const {
  std::memset(&out, 0, sizeof out);
  const TruthState t = truth(k);
  out.utime = t.utime;
  out.seq = k;
  out.n_acc = n_acc_;
  const bool noise = sc_.accel.noise_sigma_mps2 > 0;
  for (int i = 0; i < GG_MAX_ACC; ++i) {
    if (i >= n_acc_) {
      out.acc_status[i] = GG_SENSOR_ABSENT;
      continue;
    }
    const auto si = static_cast<size_t>(i);
    const Vec3 gi = field_->eval(t.kin.r + offsets_[si]).g;
    const Vec3 fi = t.kin.a - gi;  // error-free specific force at the sensor
    for (int n = 0; n < n_axes_; ++n) {
      const int j = axes_[static_cast<size_t>(n)];
      const auto sj = static_cast<size_t>(j);
      Real f = fi(j) * (1.0L + static_cast<Real>(scale_[si][sj])) + static_cast<Real>(bias_[si][sj]);
      if (noise)
        f += static_cast<Real>(sc_.accel.noise_sigma_mps2 *
                               counter_normal(sc_.accel.seed, kStreamNoise, static_cast<uint64_t>(k),
                                              static_cast<uint64_t>(i), static_cast<uint64_t>(j)));
      out.f[i][j] = static_cast<double>(f);
      out.f_lo[i][j] = static_cast<double>(f - static_cast<Real>(out.f[i][j]));
    }
    out.acc_status[i] = GG_SENSOR_OK;
  }
  out.gyro_status = GG_SENSOR_ABSENT;
  out.baro_status = GG_SENSOR_ABSENT;
  out.baro_utime = 0;
  if (!sc_.sensor_faults.faults.empty()) {  // injected sensor faults (sensor_faults.cpp), last
    apply_sensor_faults(sc_.sensor_faults, k, dt_us_, out, [&](int64_t k0, int s, int j, double& hi, double& lo) {
      Scenario clean = sc_;
      clean.sensor_faults.faults.clear();
      gg_frame_t f0;
      Generator(clean).frame(k0, f0);
      hi = f0.f[s][j];
      lo = f0.f_lo[s][j];
    });
  }
  if (truth_out) *truth_out = t;
}

}  // namespace ggins::truth
