#include "ggins/truth/generator.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "ggins/gravity/lattice.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/wgs84.hpp"
extern "C" {
#include "ggins/gmodel.h"
}

namespace ggins::truth {

namespace {

constexpr uint64_t kStreamBias = 1, kStreamScale = 2, kStreamNoise = 3;
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
  if (s.gravity.model == "wgs84-normal") return std::make_unique<gravity::NormalField>();
  if (s.gravity.model == "rw-anomaly") {
    // WGS-84 normal field exactly + Rubenstein & Winter point masses on the
    // fast path (Ewald split: short range exact, long range on a lattice;
    // docs/gravity.md), region centred on the flight (longitude 0 = the x-z plane)
    const auto& a = s.gravity.anomaly;
    const Real deg = 3.14159265358979323846264338327950288L / 180.0L;
    gravity::RwAnomalyConfig cfg;
    const double lat_mid = s.trajectory.lat0_deg + 0.5 * s.trajectory.speed_mps * s.duration_s /
                                                      (s.trajectory.radius_m + s.trajectory.height_m) / static_cast<double>(deg);
    cfg.lat0 = static_cast<Real>(std::isnan(a.lat_deg) ? lat_mid : a.lat_deg) * deg;
    cfg.lon0 = static_cast<Real>(a.lon_deg) * deg;
    cfg.half_size = a.half_size_m;
    cfg.ref_height = std::isnan(a.ref_height_m) ? s.trajectory.height_m : a.ref_height_m;
    cfg.rms_deflection = static_cast<Real>(a.rms_arcsec) / 206264.80624709636L;
    cfg.corr_length = a.corr_length_m;
    cfg.seed = a.seed;
    const gravity::PointMassAnomalyField masses = gravity::make_rubenstein_winter_field(cfg);
    gravity::LatticeOptions o;
    o.spacing = a.lattice_spacing_m;
    o.points = static_cast<int>(a.lattice_points);
    o.origin = gravity::wgs84::geodetic_to_ecef(cfg.lat0, cfg.lon0, cfg.ref_height);
    auto normal = std::make_shared<gravity::NormalField>();
    auto fast = std::make_shared<gravity::SplitPointMassField>(masses.masses(), static_cast<Real>(a.ewald_sigma_m), o);
    return std::make_unique<gravity::FastField>(normal, fast);
  }
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
  {  // the onboard zonal model (Scenario::nav_model), for the gravimeter's truth
    const NavModelParams m = s.nav_model();
    auto c = std::make_shared<gg_gmodel_config_t>();
    std::memset(c.get(), 0, sizeof *c);
    c->gm = m.gm_m3ps2;
    c->a_m = m.a_m;
    for (size_t n = 0; n <= GG_GMODEL_MAX_DEGREE && n < m.j.size(); ++n) c->j[n] = m.j[n];
    model_ = std::make_shared<gg_gmodel_t>();
    if (gg_gmodel_init(model_.get(), c.get()) != GG_OK) model_.reset();
    model_cfg_ = c;
  }
  if (s.baro.enable) {  // the Gauss-Markov sequence of every sample of the run (exact discrete recursion)
    baro_every_ = s.baro_every();
    const int64_t n = (n_steps_ - 1) / baro_every_ + 1;
    const double T = static_cast<double>(baro_every_ * dt_us_) * 1e-6;
    const double phi = std::exp(-T / s.baro.gm_tau_s), q = std::sqrt(1.0 - phi * phi);
    baro_gm_.resize(static_cast<size_t>(n));
    double m = s.baro.gm_sigma_m * counter_normal(s.baro.seed, kStreamBaroGm, 0, 0, 0);
    for (int64_t j = 0; j < n; ++j) {
      if (j > 0) m = phi * m + s.baro.gm_sigma_m * q * counter_normal(s.baro.seed, kStreamBaroGm, static_cast<uint64_t>(j), 0, 0);
      baro_gm_[static_cast<size_t>(j)] = m;
    }
  }
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

Real Generator::altitude(const Vec3& r) const { return r.norm() - static_cast<Real>(sc_.r_ref_m()); }

Vec3 Generator::model_g(const Vec3& r) const {
  gg_real_t rr[3] = {r(0), r(1), r(2)}, gg[3] = {0, 0, 0};
  if (!model_ || gg_gmodel_eval(model_.get(), model_cfg_.get(), rr, gg, nullptr) != GG_OK)
    return Vec3::Constant(std::numeric_limits<Real>::quiet_NaN());
  return Vec3(gg[0], gg[1], gg[2]);
}

BaroSample Generator::baro(int64_t k, const TruthState& t) const {
  BaroSample b;
  const BaroParams& p = sc_.baro;
  // the altitude at the sample's own time (latency_s before the frame)
  b.true_alt_m = static_cast<double>(
      p.latency_s > 0 ? altitude(traj_->at(t.t_s - static_cast<Real>(p.latency_s)).r) : altitude(t.kin.r));
  if (!p.enable || k % baro_every_ != 0) return b;
  const auto j = static_cast<uint64_t>(k / baro_every_);
  b.due = true;
  const double ts = static_cast<double>(t.t_s);
  for (const auto& w : p.dropouts)
    if (ts >= w[0] && ts < w[1]) b.dropped = true;
  if (p.dropout_prob > 0 && counter_uniform(p.seed, kStreamBaroDrop, j, 0, 0) < p.dropout_prob) b.dropped = true;
  b.gm_m = baro_gm_[static_cast<size_t>(j)];
  b.error_m = p.bias_m + b.gm_m;
  if (p.noise_sigma_m > 0) b.error_m += p.noise_sigma_m * counter_normal(p.seed, kStreamBaroNoise, j, 0, 0);
  if (p.outlier_prob > 0) {
    const double u = counter_uniform(p.seed, kStreamBaroOutlier, j, 0, 0);
    if (u < p.outlier_prob) {
      b.outlier = true;
      b.error_m += (u < 0.5 * p.outlier_prob ? p.outlier_m : -p.outlier_m);
    }
  }
  if (p.invalid_prob > 0 && counter_uniform(p.seed, kStreamBaroInvalid, j, 0, 0) < p.invalid_prob) b.invalid = true;
  if (b.dropped) return b;
  b.status = GG_SENSOR_OK;
  b.alt_m = b.invalid ? std::numeric_limits<double>::quiet_NaN() : b.true_alt_m + b.error_m;
  return b;
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
    const Vec3 gi = field_->gravitation(t.kin.r + offsets_[si]);
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
  if (sc_.baro.enable) {
    const BaroSample b = baro(k, t);
    if (b.status == GG_SENSOR_OK) {
      out.baro_alt_m = b.alt_m;
      out.baro_utime = t.utime - std::llround(sc_.baro.latency_s * 1e6);
      out.baro_status = GG_SENSOR_OK;
    }
  }
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
