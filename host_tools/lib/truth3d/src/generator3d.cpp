#include "ggins/truth3d/generator3d.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "ggins/gravity/lattice.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth3d/route3d.hpp"

namespace ggins::truth3d {

namespace {
constexpr Real kDeg = kPi / 180.0L;
}  // namespace

std::unique_ptr<Trajectory3> make_trajectory3(const Scenario3& s) {
  const auto& t = s.trajectory;
  const Attitude att = s.strapdown() ? Attitude::Coordinated : Attitude::Stabilized;
  if (t.type == "flight") {
    FlightParams p;
    p.lat0 = static_cast<Real>(t.lat_deg) * kDeg;
    p.lon0 = static_cast<Real>(t.lon_deg) * kDeg;
    p.h0 = t.height_m;
    for (int i = 0; i < 3; ++i) p.v_ned0[i] = t.velocity_ned_mps[static_cast<size_t>(i)];
    for (const auto& m : t.maneuvers) {
      Maneuver x;
      x.t_s = m.t_s;
      x.duration_s = m.duration_s;
      for (int i = 0; i < 3; ++i) x.dv_ned[i] = m.dv_ned_mps[static_cast<size_t>(i)];
      p.maneuvers.push_back(x);
    }
    return std::make_unique<Flight3>(p, att);
  }
  if (t.type == "circle") {
    CircleParams p;
    p.lat_c = static_cast<Real>(t.lat_deg) * kDeg;
    p.lon_c = static_cast<Real>(t.lon_deg) * kDeg;
    p.h = t.height_m;
    p.radius_m = t.radius_m;
    p.speed_mps = t.speed_mps;
    return std::make_unique<Circle3>(p, att);
  }
  if (t.type == "route") return make_route3(s);
  if (t.type == "tumble") {
    TumbleParams p;
    p.lat = static_cast<Real>(t.lat_deg) * kDeg;
    p.lon = static_cast<Real>(t.lon_deg) * kDeg;
    p.h = t.height_m;
    p.spin_radps = t.spin_radps;
    p.precession_radps = t.precession_radps;
    p.nutation0 = static_cast<Real>(t.nutation_deg) * kDeg;
    p.nutation_amp = static_cast<Real>(t.nutation_amp_deg) * kDeg;
    p.nutation_radps = t.nutation_radps;
    p.psi0 = static_cast<Real>(t.psi0_deg) * kDeg;
    p.phi0 = static_cast<Real>(t.phi0_deg) * kDeg;
    return std::make_unique<Tumble3>(p);
  }
  throw std::invalid_argument("unknown 3-D trajectory type " + t.type);
}

std::string egm96_path(const Scenario3& s) {
  return s.sh.path.empty() ? std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt" : s.sh.path;
}

std::unique_ptr<gravity::Field> make_field3(const Scenario3& s) {
  if (s.gravity.model == "egm96") {
    // WGS-84 normal field exactly + the EGM96 disturbing field (coefficients minus
    // the normal zonal series, double-precision synthesis) on a lattice centred
    // on the trajectory's start point (the 2-D fast path, gravity/lattice.hpp)
    const std::string path = egm96_path(s);
    const int n = static_cast<int>(s.sh.nmax);
    const gravity::ShCoefficients c = gravity::read_nasa_ascii(path, gravity::kEgm96Gm, gravity::kEgm96A, n);
    auto anomaly = std::make_shared<gravity::SphericalHarmonicField>(gravity::subtract_normal(c), n, 2,
                                                                     gravity::ShPrecision::Double);
    gravity::LatticeOptions o;
    o.spacing = s.sh.lattice_spacing_m;
    o.points = static_cast<int>(s.sh.lattice_points);
    o.origin = gravity::wgs84::geodetic_to_ecef(static_cast<Real>(s.trajectory.lat_deg) * kDeg,
                                                static_cast<Real>(s.trajectory.lon_deg) * kDeg, s.trajectory.height_m);
    return std::make_unique<gravity::FastField>(std::make_shared<gravity::NormalField>(), anomaly, o);
  }
  // the 2-D generator's field factory (normal field, point mass, R&W anomalies
  // on the fast path); the anomaly region is centred on the 3-D trajectory
  truth::Scenario s2;
  s2.gravity = s.gravity;
  s2.trajectory.lat0_deg = s.trajectory.lat_deg;
  s2.trajectory.height_m = s.trajectory.height_m;
  s2.duration_s = s.duration_s;
  return truth::make_field(s2);
}

std::array<Real, 4> quat_from_dcm(const Mat3& C) {
  // Shepperd (1978): pick the largest of 4w^2, 4x^2, 4y^2, 4z^2
  const Real tr = C.trace();
  const Real v[4] = {1 + tr, 1 + 2 * C(0, 0) - tr, 1 + 2 * C(1, 1) - tr, 1 + 2 * C(2, 2) - tr};
  int k = 0;
  for (int i = 1; i < 4; ++i)
    if (v[i] > v[k]) k = i;
  const Real s = 2 * std::sqrt(v[k]);  // 4 * component k
  std::array<Real, 4> q{};
  switch (k) {
    case 0:
      q = {s / 4, (C(2, 1) - C(1, 2)) / s, (C(0, 2) - C(2, 0)) / s, (C(1, 0) - C(0, 1)) / s};
      break;
    case 1:
      q = {(C(2, 1) - C(1, 2)) / s, s / 4, (C(0, 1) + C(1, 0)) / s, (C(0, 2) + C(2, 0)) / s};
      break;
    case 2:
      q = {(C(0, 2) - C(2, 0)) / s, (C(0, 1) + C(1, 0)) / s, s / 4, (C(1, 2) + C(2, 1)) / s};
      break;
    default:
      q = {(C(1, 0) - C(0, 1)) / s, (C(0, 2) + C(2, 0)) / s, (C(1, 2) + C(2, 1)) / s, s / 4};
      break;
  }
  if (q[0] < 0)
    for (auto& x : q) x = -x;
  return q;
}

Generator3::Generator3(const Scenario3& s) : traj_(make_trajectory3(s)), field_(make_field3(s)) {
  opt_.half_base = {static_cast<Real>(s.a_m), static_cast<Real>(s.b_m), static_cast<Real>(s.c_m)};
  opt_.dt_us = s.dt_us();
  opt_.n_steps = s.n_steps();
  opt_.accel = s.accel_flown();  // the fixed errors plus the run's [draw]
  opt_.gyro = s.gyro_flown();
  opt_.baro = s.baro;
  opt_.faults = s.sensor_faults;
  if (s.coldatom.enabled) ca_ = std::make_shared<const ColdAtomSensor3>(s.coldatom, opt_.dt_us);
  init_errors();
}

Generator3::Generator3(std::shared_ptr<const Trajectory3> traj, std::shared_ptr<const gravity::Field> field,
                       const Generator3Options& opt)
    : traj_(std::move(traj)), field_(std::move(field)), opt_(opt) {
  init_errors();
}

void Generator3::init_errors() {
  const auto& hb = opt_.half_base;
  d_[0] = Vec3(hb[0], 0, 0);
  d_[1] = Vec3(0, hb[1], 0);
  d_[2] = Vec3(0, 0, hb[2]);
  d_[3] = Vec3(-hb[0], 0, 0);
  d_[4] = Vec3(0, -hb[1], 0);
  d_[5] = Vec3(0, 0, -hb[2]);
  // the sensor error models (truth/sensors.hpp): all three axes of the six accelerometers
  accel_ = truth::AccelModel(opt_.accel, 6, {true, true, true}, truth::kAccelStreams3D);
  gyro_ = truth::GyroModel(opt_.gyro, truth::kGyroStreams3D);
  if (opt_.baro.enable) {
    const int64_t every = std::max<int64_t>(1, std::llround(1e6 / opt_.baro.rate_hz / static_cast<double>(opt_.dt_us)));
    baro_ = truth::BaroModel(opt_.baro, every, opt_.n_steps, opt_.dt_us);
  }
}

Truth3 Generator3::make_truth(Real t, const State3& s, const gravity::FieldSample& c) {
  Truth3 r;
  r.t_s = t;
  r.s = s;
  r.g_e = c.g;
  r.g_i = s.C_e_i * c.g;
  r.gamma_e = c.gamma;
  r.gamma_b = s.C_b_e.transpose() * c.gamma * s.C_b_e;
  r.f_b = s.C_b_i.transpose() * s.a_i - s.C_b_e.transpose() * c.g;
  return r;
}

Truth3 Generator3::truth_at(Real t) const {
  const State3 s = traj_->at(t);
  return make_truth(t, s, field_->eval(s.r_e));
}

Truth3 Generator3::truth(int64_t k) const {
  Truth3 r = truth_at(time_of(k));
  r.seq = k;
  r.utime = k * opt_.dt_us;
  return r;
}

Vec3 Generator3::specific_force(const State3& s, size_t j, const Vec3& g_j) const {
  const Vec3 a_j = s.a_i + s.C_b_i_ddot * d_[j];
  return s.C_b_i.transpose() * a_j - s.C_b_e.transpose() * g_j;
}

std::array<Vec3, 6> Generator3::specific_forces(const State3& s, const Vec3 g_plus[3], const Vec3 g_minus[3]) const {
  std::array<Vec3, 6> f;
  for (size_t j = 0; j < 6; ++j) f[j] = specific_force(s, j, j < 3 ? g_plus[j] : g_minus[j - 3]);
  return f;
}

Truth3 Generator3::sensors_at(Real t, std::array<Vec3, 6>& f) const {
  const State3 s = traj_->at(t);
  Vec3 d_e[3], gp[3], gm[3];  // d_[j + 3] = -d_[j] (init_errors)
  for (size_t k = 0; k < 3; ++k) d_e[k] = s.C_b_e * d_[k];
  const Truth3 r = make_truth(t, s, field_->eval_pairs(s.r_e, d_e, 3, gp, gm));
  f = specific_forces(s, gp, gm);
  return r;
}

std::array<Vec3, 6> Generator3::accel_true(const Truth3& t) const {
  Vec3 d_e[3], gp[3], gm[3];
  for (size_t k = 0; k < 3; ++k) d_e[k] = t.s.C_b_e * d_[k];
  (void)field_->eval_pairs(t.s.r_e, d_e, 3, gp, gm);
  return specific_forces(t.s, gp, gm);
}

Vec3 Generator3::accel_reference(const Truth3& t, int j) const {
  const auto sj = static_cast<size_t>(j);
  return specific_force(t.s, sj, field_->gravitation(t.s.r_e + t.s.C_b_e * d_[sj]));
}

truth::BaroSample Generator3::baro(int64_t k, const Truth3& t) const {
  return baro_.sample(k, static_cast<double>(t.t_s), static_cast<double>(t.s.h));
}

void Generator3::frame(int64_t k, gg_frame_t& out, Truth3* truth_out) const {
  std::memset(&out, 0, sizeof out);
  std::array<Vec3, 6> fs;
  Truth3 t = sensors_at(time_of(k), fs);
  t.seq = k;
  t.utime = k * opt_.dt_us;
  out.utime = t.utime;
  out.seq = k;
  out.n_acc = 6;
  for (int i = 0; i < 6; ++i) {
    const Vec3& fi = fs[static_cast<size_t>(i)];
    for (int j = 0; j < 3; ++j) truth::encode_hilo(accel_.read(k, i, j, fi(j)), out.f[i][j], out.f_lo[i][j]);
    out.acc_status[i] = GG_SENSOR_OK;
  }
  for (int j = 0; j < 3; ++j) out.omega_b[j] = static_cast<double>(gyro_.read(k, j, t.s.omega_b(j)));
  out.gyro_status = GG_SENSOR_OK;
  out.baro_status = GG_SENSOR_ABSENT;
  out.baro_alt_m = 0;
  if (opt_.baro.enable) {
    const truth::BaroSample b = baro(k, t);
    if (b.status == GG_SENSOR_OK) {
      out.baro_alt_m = b.alt_m;
      out.baro_utime = t.utime;
      out.baro_status = GG_SENSOR_OK;
    }
  }
  out.ca_status = GG_SENSOR_ABSENT;
  if (ca_) {
    double gzz = 0;  // gzz_map "field": the truth field's Gamma_DD, d^T Gamma_e d with d the geodetic down
    if (ca_->samples_field()) {
      const Vec3 d(-std::cos(t.s.lat) * std::cos(t.s.lon), -std::cos(t.s.lat) * std::sin(t.s.lon), -std::sin(t.s.lat));
      gzz = static_cast<double>(d.dot(t.gamma_e * d));
    }
    ca_->frame(k, static_cast<double>(t.s.lat), static_cast<double>(t.s.lon), static_cast<double>(t.s.h), out, gzz);
  }
  apply_sensor_faults3(opt_.faults, *this, k, out);
  if (truth_out) *truth_out = t;
}

}  // namespace ggins::truth3d
