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

Generator::Generator(const Scenario& s) : Generator(s, std::shared_ptr<const gravity::Field>(make_field(s))) {}

Generator::Generator(const Scenario& s, std::shared_ptr<const gravity::Field> field)
    : sc_(s), traj_(make_trajectory(s)), field_(std::move(field)), dt_us_(s.dt_us()), n_steps_(s.n_steps()),
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
  // the sensor error models (sensors.hpp): x and z measured, y reads 0
  accel_ = AccelModel(s.accel, n_acc_, {true, false, true}, kAccelStreams2D);
  if (s.baro.enable) baro_ = BaroModel(s.baro, s.baro_every(), n_steps_, dt_us_);
}

Real Generator::altitude(const Vec3& r) const { return r.norm() - static_cast<Real>(sc_.r_ref_m()); }

Vec3 Generator::model_g(const Vec3& r) const {
  gg_real_t rr[3] = {r(0), r(1), r(2)}, gg[3] = {0, 0, 0};
  if (!model_ || gg_gmodel_eval(model_.get(), model_cfg_.get(), rr, gg, nullptr) != GG_OK)
    return Vec3::Constant(std::numeric_limits<Real>::quiet_NaN());
  return Vec3(gg[0], gg[1], gg[2]);
}

BaroSample Generator::baro(int64_t k, const TruthState& t) const {
  const BaroParams& p = sc_.baro;
  // the altitude at the sample's own time (latency_s before the frame)
  const double h = static_cast<double>(
      p.latency_s > 0 ? altitude(traj_->at(t.t_s - static_cast<Real>(p.latency_s)).r) : altitude(t.kin.r));
  return baro_.sample(k, static_cast<double>(t.t_s), h);
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
      encode_hilo(accel_.read(k, i, j, fi(j)), out.f[i][j], out.f_lo[i][j]);
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
      Generator(clean, field_).frame(k0, f0);
      hi = f0.f[s][j];
      lo = f0.f_lo[s][j];
    });
  }
  if (truth_out) *truth_out = t;
}

}  // namespace ggins::truth
