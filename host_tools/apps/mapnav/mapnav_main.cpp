// ggins mapnav: the 10 h voyage of Gao et al.: gravity-gradient
// map matching UKF (firmware mmukf) against pure inertial on the same flight,
// direct calls (no LCM). Truth: the firmware's own NED mechanization driven by
// error-free IMU samples computed from the commanded motion (acceleration,
// cruise, deceleration, turns); measured IMU = truth + constant biases + white
// noise; gradiometer = EGM96 (degree 360, total field) at the true position,
// rotated to body axes, + white noise; the map tile = the same model on a
// 0.05 deg grid + seeded database noise (ggins gmap).
// --gradiometer diff3d: the measurement is instead the firmware's own strapdown
// gradiometer: six tri-axis accelerometers at +-a along the body axes read the
// true rigid-body motion and the same EGM96 field at each sensor (+ white
// noise sigma_a = sqrt(2) a sigma_Gamma, see diff3d_sim.hpp), gg_diff3d
// removes [Omega x]^2 with the body rate (true, or the gyro sample with
// --diff3d-omega imu) and its Gamma_b is the filter's measurement.
// --diff3d-omega imu-mean: the readings integrated over the update period with
// each sample's [Omega x]^2 removed by its own gyro sample, emulated as the
// true-rate diff3d tensor at the epoch + the window mean of
// [w_gyro x]^2 - [w_true x]^2 (the field part stays the epoch's point value,
// as the filter models it).
#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "diff3d_sim.hpp"
#include "ggins/cli_checks.hpp"
#include "ggins/gmap_gen.hpp"
#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth/stats.hpp"
#include "hil_common.hpp"
#include "report.hpp"

extern "C" {
#include "ggins/limits.h"
#include "ggins/mmukf.h"
#include "ggins/quat.h"
}

#ifndef GGINS_DATA_DIR
#define GGINS_DATA_DIR "data"
#endif

namespace {

constexpr double kD2R = M_PI / 180.0, kE = 1e-9, kW = static_cast<double>(ggins::gravity::wgs84::kOmega), kG0 = 9.80665;

struct Opt {
  double hours = 10, dt = 0.1, update = 60, meas_e = 0.01, db_e = 0.001, att_deg = 0.5, vel = 1, pos = 10;
  double gyro_dph = 0.01, acc_ug = 10, arw_dprh = 0.001, vrw_ug_rhz = 1;
  double lat0 = 30.0, lon0 = 140.0, depth = 100, speed = 10, spacing = 0.05, lambda = 0, gate = 0;
  int runs = 1, threads = 2, seed = 1, first_run = 0, passes = 40;
  bool fixed_errors = false, plot = true;
  std::string egm = std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt", out = "out/mapnav", tile;
  std::string gradiometer = "direct", diff3d_omega = "true";
  double half_base = 0.5;  // m, the project default (truth3d, nav3d)
  double offdiag_ratio = -1;  // filter's off-diagonal/diagonal noise ratio; < 0: 1/sqrt(2) for diff3d, 1 for direct
  bool gyro_term = true;      // diff3d with the gyro's rate: the filter models the [w x]^2 removal (mmukf gyro_term)
};

// the filter's off-diagonal/diagonal noise ratio in use: the option, else 1/sqrt(2) for diff3d
// (an off-diagonal element averages four readings, a diagonal one differences two), 1 for direct
static double offdiag_ratio(const Opt& o) {
  return o.offdiag_ratio >= 0 ? o.offdiag_ratio : (o.gradiometer == "diff3d" ? 1.0 / std::sqrt(2.0) : 1.0);
}

// commanded motion: speed (m/s) and heading rate (rad/s) at t
struct Cmd { double speed, accel, yaw_rate; };
Cmd command(double t, double v) {
  // 0-300 s accelerate to v; cruise; 2 h: 90 deg right turn (300 s); 4 h: decelerate to v/2 (300 s);
  // 5 h: 90 deg left turn; 6 h: accelerate back to v; 8 h: 180 deg turn (600 s); cruise to the end
  const double a = v / 300.0, turn = 0.3 * kD2R;
  Cmd c{v, 0, 0};
  if (t < 300) c = {a * t, a, 0};
  if (t >= 7200 && t < 7500) c.yaw_rate = turn;
  if (t >= 14400 && t < 14700) c = {v - 0.5 * a * (t - 14400), -0.5 * a, 0};
  if (t >= 14700 && t < 21600) c.speed = 0.5 * v;
  if (t >= 18000 && t < 18300) c.yaw_rate = -turn;
  if (t >= 21600 && t < 21900) c = {0.5 * v + 0.5 * a * (t - 21600), 0.5 * a, 0};
  if (t >= 28800 && t < 29400) c.yaw_rate = turn;
  return c;
}

// C_b_n of the mechanization's q_b_n (firmware quat.h, in gg_real_t as the filter forms it)
void dcm(const double q[4], Eigen::Matrix3d& C) {
  const gg_real_t ql[4] = {q[0], q[1], q[2], q[3]};
  gg_real_t c[3][3];
  gg_quat_to_dcm(ql, c);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = static_cast<double>(c[i][j]);
}

// ideal IMU that makes the mechanization follow the command from state x
gg_mm_imu_t ideal_imu(const gg_mm_nav_t& x, const Cmd& c) {
  const double s = std::sin(x.lat), co = std::cos(x.lat);
  ggins::gravity::Real rm_l, rn_l;  // meridian, prime-vertical radius (WGS-84)
  ggins::gravity::wgs84::radii(x.lat, rm_l, rn_l);
  const double rn = static_cast<double>(rn_l), rm = static_cast<double>(rm_l);
  double g;
  gg_mm_normal_gravity(x.lat, x.h, &g);
  Eigen::Vector3d v(x.v[0], x.v[1], x.v[2]);
  const Eigen::Vector3d wie(kW * co, 0, -kW * s);
  const Eigen::Vector3d wen(x.v[1] / (rn + x.h), -x.v[0] / (rm + x.h), -x.v[1] * s / (co * (rn + x.h)));
  const double psi = std::atan2(x.v[1], x.v[0]);
  const double hdg = (std::hypot(x.v[0], x.v[1]) > 0.01) ? psi : 0.0;
  Eigen::Matrix3d C;  // C_b_n
  dcm(x.q, C);
  // desired acceleration along the current heading of the body x axis
  const double yaw = std::atan2(C(1, 0), C(0, 0));
  (void)hdg;
  const Eigen::Vector3d dir(std::cos(yaw), std::sin(yaw), 0), side(-std::sin(yaw), std::cos(yaw), 0);
  const double sp = std::hypot(x.v[0], x.v[1]);
  // speed loop (1/20 s) so the truth follows the command, centripetal for the turn
  const Eigen::Vector3d acc = dir * (c.accel + (c.speed - sp) / 20.0) + side * (sp * c.yaw_rate) - v * 0 +
                              Eigen::Vector3d(0, 0, -x.v[2] / 20.0);
  const Eigen::Vector3d fn = acc + (2 * wie + wen).cross(v) - Eigen::Vector3d(0, 0, g);
  const Eigen::Vector3d fb = C.transpose() * fn;
  const Eigen::Vector3d wb = Eigen::Vector3d(0, 0, c.yaw_rate) + C.transpose() * (wie + wen);
  gg_mm_imu_t m;
  for (int k = 0; k < 3; ++k) {
    m.f_b[k] = fb(k);
    m.omega_b[k] = wb(k);
  }
  return m;
}

void euler(const double q[4], double e[3]) {  // roll, pitch, yaw of C_b_n
  Eigen::Matrix3d C;
  dcm(q, C);
  e[0] = std::atan2(C(2, 1), C(2, 2));
  e[1] = -std::asin(std::max(-1.0, std::min(1.0, C(2, 0))));
  e[2] = std::atan2(C(1, 0), C(0, 0));
}
double wrap(double a) { return std::remainder(a, 2 * M_PI); }

// errors of a vs truth t: pitch, roll, yaw (arcmin), vE vN vU (m/s), lat lon h (m)
std::array<double, 9> table_errors(const gg_mm_nav_t& a, const gg_mm_nav_t& t) {
  double ea[3], et[3], d[GG_MM_NX];
  euler(a.q, ea);
  euler(t.q, et);
  gg_mm_error(&a, &t, d);
  const double am = 180.0 * 60.0 / M_PI;
  return {wrap(ea[1] - et[1]) * am, wrap(ea[0] - et[0]) * am, wrap(ea[2] - et[2]) * am, d[4], d[3], -d[5], d[6], d[7], d[8]};
}

struct RunResult {
  std::array<double, 9> ggan_final{}, ins_final{}, ins0_final{}, ggan_rms2h{}, ins_rms2h{};
  std::vector<double> nees, nees_pos, nis;  // per update epoch
  std::vector<std::array<double, 5>> nees_blk;  // per 3-state block: att, vel, pos, bg, ba
  std::vector<std::array<double, 24>> series;  // t, 9 ggan, 9 ins, 3 pos sigma, nis, nees
  uint32_t n_updates = 0, n_gated = 0, n_offmap = 0, n_fail = 0;
  double step_ns_median = 0, update_us_median = 0;
  std::array<double, 6> d3_err_sum{}, d3_err_sq{};  // diff3d Gamma_b minus the field's Gamma_b at the centre
  long d3_n = 0;
  long steps_expected = 0, steps_flown = 0;  // IMU steps of the voyage, and those flown (fewer: interrupted)
  bool started = false;                       // false: never started (interrupted before)
};

RunResult run_one(const Opt& o, int run, const gg_gmap_t* map, const ggins::gravity::Field& truth_field,
                  const gg_mm_nav_t& start) {
  std::mt19937_64 rng(1000003ull * static_cast<unsigned>(o.seed) + static_cast<unsigned>(run));
  std::normal_distribution<double> N(0, 1);
  const double dt = o.dt;
  const long steps = std::lround(o.hours * 3600 / dt);
  // sensor errors: constant biases (random sign, Gao Table 1 magnitude) and white noise
  double bg[3], ba[3];
  for (int k = 0; k < 3; ++k) {
    bg[k] = o.gyro_dph * kD2R / 3600.0 * (o.fixed_errors ? 1.0 : N(rng));
    ba[k] = o.acc_ug * 1e-6 * kG0 * (o.fixed_errors ? 1.0 : N(rng));
  }
  const double arw = o.arw_dprh * kD2R / 60.0, vrw = o.vrw_ug_rhz * 1e-6 * kG0;
  // initial estimate = truth (+) initial error
  double d0[GG_MM_NX] = {0};
  for (int k = 0; k < 3; ++k) {
    d0[k] = o.att_deg * kD2R * (o.fixed_errors ? 1.0 : N(rng));
    d0[3 + k] = o.vel * (o.fixed_errors ? 1.0 : N(rng));
    d0[6 + k] = o.pos * (o.fixed_errors ? 1.0 : N(rng));
  }
  gg_mm_nav_t est0;
  if (gg_mm_apply(&start, d0, &est0) != GG_OK) throw std::runtime_error("initial error");
  gg_mm_config_t cfg{};
  cfg.dt_s = dt;
  cfg.update_period_s = o.update;
  cfg.sigma_meas_s2 = o.meas_e * kE;
  cfg.sigma_db_s2 = o.db_e * kE;
  cfg.sig0_att_rad = o.att_deg * kD2R;
  cfg.sig0_vel_mps = o.vel;
  cfg.sig0_pos_m = o.pos;
  cfg.sig0_bg_rps = std::max(o.gyro_dph, 1e-4) * kD2R / 3600.0;
  cfg.sig0_ba_mps2 = std::max(o.acc_ug, 0.1) * 1e-6 * kG0;
  cfg.arw_rad_rts = arw;
  cfg.vrw_mps_rts = vrw;
  cfg.bg_rw = 1e-4 * kD2R / 3600.0 / 60.0;  // small bias instability
  cfg.ba_rw = 1e-9;
  cfg.lambda = o.lambda;
  cfg.gate_nis = o.gate;
  cfg.max_passes = o.passes;
  cfg.offdiag_ratio = offdiag_ratio(o);
  cfg.init = est0;
  auto mm = std::make_unique<gg_mm_t>();
  if (gg_mm_init(mm.get(), &cfg, map) != GG_OK) throw std::runtime_error("gg_mm_init failed");
  gg_mm_nav_t truth = start, ins = est0, ins0 = start;  // ins0: pure inertial without initial errors
  RunResult R;
  std::vector<double> step_ns, upd_us;
  const long per_upd = std::lround(o.update / dt);
  std::vector<std::array<double, 9>> last2h_g, last2h_i;
  // diff3d mode: its 18 accelerometer noises come from a second stream, so the IMU noise
  // and initial errors are the same draws as in the direct mode (paired comparison)
  const bool use_diff3d = o.gradiometer == "diff3d";
  std::mt19937_64 rng_acc(0x9e3779b97f4a7c15ull ^ (1000003ull * static_cast<unsigned>(o.seed) + static_cast<unsigned>(run)));
  const double sigma_a = std::sqrt(2.0) * o.half_base * o.meas_e * kE;  // per reading, m/s^2
  double w_prev[3] = {0, 0, 0};
  Eigen::Matrix3d w2_err_sum = Eigen::Matrix3d::Zero();  // imu-mean: sum of [w_gyro x]^2 - [w_true x]^2
  long w2_n = 0;
  Eigen::Vector3d wg_sum = Eigen::Vector3d::Zero();  // imu-mean: sum of the gyro samples over the window
  auto w2 = [](const double* w) {
    const Eigen::Vector3d v(w[0], w[1], w[2]);
    return Eigen::Matrix3d(v * v.transpose() - v.squaredNorm() * Eigen::Matrix3d::Identity());
  };
  R.started = true;
  R.steps_expected = steps;
  for (long k = 1; k <= steps; ++k) {
    // SIGINT/SIGTERM: the voyage stops here, its steps so far counted as flown
    if ((k & 1023) == 0 && ggins::hil::interrupted()) break;
    R.steps_flown = k;
    const double t = (k - 1) * dt;
    const gg_mm_imu_t ideal = ideal_imu(truth, command(t, o.speed));
    double w_dot[3];
    for (int j = 0; j < 3; ++j) { w_dot[j] = k > 1 ? (ideal.omega_b[j] - w_prev[j]) / dt : 0.0; w_prev[j] = ideal.omega_b[j]; }
    gg_mm_imu_t meas = ideal;
    for (int j = 0; j < 3; ++j) {
      meas.omega_b[j] += bg[j] + arw / std::sqrt(dt) * N(rng);
      meas.f_b[j] += ba[j] + vrw / std::sqrt(dt) * N(rng);
    }
    if (use_diff3d && o.diff3d_omega == "imu-mean") {
      w2_err_sum += w2(meas.omega_b) - w2(ideal.omega_b);
      wg_sum += Eigen::Vector3d(meas.omega_b[0], meas.omega_b[1], meas.omega_b[2]);
      ++w2_n;
    }
    if (gg_mm_mech(&truth, &ideal, dt, 0, 0, 0) != GG_OK) throw std::runtime_error("truth mech");
    if (gg_mm_mech(&ins, &meas, dt, 1, est0.h, 0.0) != GG_OK) throw std::runtime_error("ins mech");
    if (gg_mm_mech(&ins0, &meas, dt, 1, start.h, 0.0) != GG_OK) throw std::runtime_error("ins mech");
    gg_mm_meas_t gm{};
    const bool have = (k % per_upd) == 0;
    if (have) {  // gradiometer at the true position, body axes, + noise
      double v[GG_GMAP_NVAL];
      ggins::gmap::node_values(truth_field, truth.lat, truth.lon, truth.h, v);
      Eigen::Matrix3d Gn;
      Gn << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
      Eigen::Matrix3d C;
      dcm(truth.q, C);
      const Eigen::Matrix3d Gb = C.transpose() * Gn * C;
      const double g6[6] = {Gb(0, 0), Gb(1, 1), Gb(2, 2), Gb(0, 1), Gb(0, 2), Gb(1, 2)};
      for (int j = 0; j < 6; ++j) gm.gamma_b[j] = g6[j] + o.meas_e * kE * N(rng);
      if (use_diff3d) {  // replace by the six-accelerometer gradiometer through gg_diff3d
        ggins::mapnav::Diff3dTruth tr;
        tr.lat = truth.lat; tr.lon = truth.lon; tr.h = truth.h;
        for (int j = 0; j < 4; ++j) tr.q_b_n[j] = truth.q[j];
        for (int j = 0; j < 3; ++j) { tr.f_c[j] = ideal.f_b[j]; tr.omega_b[j] = ideal.omega_b[j]; tr.omega_dot_b[j] = w_dot[j]; }
        double nz[6][3];
        for (auto& row : nz) for (double& v : row) v = sigma_a * N(rng_acc);
        gg_diff3d_input_t din{};
        ggins::mapnav::diff3d_readings(truth_field, tr, o.half_base, nz,
                                       o.diff3d_omega == "imu" ? meas.omega_b : ideal.omega_b, din);
        gg_diff3d_output_t dout;
        double d6[6];
        if (ggins::mapnav::diff3d_gamma6(din, o.half_base, d6, &dout) != GG_OK) throw std::runtime_error("gg_diff3d failed");
        if (o.diff3d_omega == "imu" && o.gyro_term) {  // the filter models the removal with this sample
          gm.gyro_term = 1;
          for (int j = 0; j < 3; ++j) gm.omega_b[j] = meas.omega_b[j];
          gm.sigma_omega_rps = arw / std::sqrt(dt);
        }
        if (o.diff3d_omega == "imu-mean" && w2_n > 0) {  // gg_diff3d subtracts [w x]^2: Gamma = [w x]^2 - sym(M)
          const Eigen::Matrix3d m = w2_err_sum / static_cast<double>(w2_n);
          const double c6[6] = {m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(0, 2), m(1, 2)};
          for (int j = 0; j < 6; ++j) d6[j] += c6[j];
          if (o.gyro_term) {  // modelled with the window's mean gyro rate and the mean's noise
            gm.gyro_term = 1;
            for (int j = 0; j < 3; ++j) gm.omega_b[j] = wg_sum(j) / static_cast<double>(w2_n);
            gm.sigma_omega_rps = arw / std::sqrt(dt * static_cast<double>(w2_n));
          }
          w2_err_sum.setZero();
          wg_sum.setZero();
          w2_n = 0;
        }
        for (int j = 0; j < 6; ++j) {
          R.d3_err_sum[j] += d6[j] - g6[j];
          R.d3_err_sq[j] += (d6[j] - g6[j]) * (d6[j] - g6[j]);
          gm.gamma_b[j] = d6[j];
        }
        ++R.d3_n;
      }
    }
    gg_mm_output_t out;
    const auto c0 = std::chrono::steady_clock::now();
    const gg_status_t s = gg_mm_step(mm.get(), &meas, have ? &gm : nullptr, &out);
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - c0).count();
    if (s != GG_OK) throw std::runtime_error("gg_mm_step failed: status " + std::to_string(s) + " health " + std::to_string(mm->health) + " t " + std::to_string(t));
    if (have) upd_us.push_back(ns * 1e-3); else if (k % 97 == 0) step_ns.push_back(ns);
    if (have) {
      gg_mm_nav_t tb = truth;  // truth with the actual sensor biases in the bias fields
      for (int j = 0; j < 3; ++j) { tb.bg[j] = bg[j]; tb.ba[j] = ba[j]; }
      double d[GG_MM_NX];
      gg_mm_error(&tb, &out.nav, d);  // truth (-) estimate, the filter's error coordinates
      Eigen::Matrix<double, GG_MM_NX, GG_MM_NX> P;
      for (int i = 0; i < GG_MM_NX; ++i)
        for (int j = 0; j < GG_MM_NX; ++j) P(i, j) = out.P[i][j];
      Eigen::Matrix<double, GG_MM_NX, 1> e;
      for (int i = 0; i < GG_MM_NX; ++i) e(i) = d[i];
      const double nees = e.dot(P.ldlt().solve(e));
      const Eigen::Vector3d ep = e.segment<3>(6);
      const double nees_pos = ep.dot(P.block<3, 3>(6, 6).ldlt().solve(ep));
      std::array<double, 5> blk{};
      for (int b = 0; b < 5; ++b) {
        const Eigen::Vector3d eb = e.segment<3>(3 * b);
        blk[b] = eb.dot(P.block<3, 3>(3 * b, 3 * b).ldlt().solve(eb));
      }
      R.nees_blk.push_back(blk);
      R.nees.push_back(nees);
      R.nees_pos.push_back(nees_pos);
      if (out.updated) R.nis.push_back(out.nis);
      const auto eg = table_errors(out.nav, truth), ei = table_errors(ins, truth);
      std::array<double, 24> row{};
      row[0] = t + dt;
      for (int j = 0; j < 9; ++j) { row[1 + j] = eg[j]; row[10 + j] = ei[j]; }
      row[19] = out.sigma[6]; row[20] = out.sigma[7]; row[21] = out.sigma[8];
      row[22] = out.nis; row[23] = nees;
      R.series.push_back(row);
      if (t + dt > (o.hours - 2) * 3600) { last2h_g.push_back(eg); last2h_i.push_back(ei); }
      R.ggan_final = eg;
      R.ins_final = ei;
      R.ins0_final = table_errors(ins0, truth);
    }
    R.n_updates = out.n_updates; R.n_gated = out.n_gated; R.n_offmap = out.n_offmap; R.n_fail = out.n_fail;
  }
  for (int j = 0; j < 9; ++j) {
    double sg = 0, si = 0;
    for (std::size_t i = 0; i < last2h_g.size(); ++i) { sg += last2h_g[i][j] * last2h_g[i][j]; si += last2h_i[i][j] * last2h_i[i][j]; }
    R.ggan_rms2h[j] = last2h_g.empty() ? 0 : std::sqrt(sg / last2h_g.size());
    R.ins_rms2h[j] = last2h_i.empty() ? 0 : std::sqrt(si / last2h_i.size());
  }
  auto med = [](std::vector<double> v) { if (v.empty()) return 0.0; std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end()); return v[v.size() / 2]; };
  R.step_ns_median = med(step_ns);
  R.update_us_median = med(upd_us);
  return R;
}

// The report (summary.json, report.hpp): the runs as an ensemble of flights whose steps are
// the IMU steps; errors are the map-matching filter's (GGAN) and the pure inertial solution's
// against truth at the update epochs; consistency: the final position error over the runs
// against the filter's own one-sigma; the filter's counters in `aids`; the Table 2 statistics,
// NEES/NIS and the voyage's options in the ensemble block (results, filter_per_run, voyage).
nlohmann::json mapnav_report(const Opt& o, const std::vector<RunResult>& res, const std::vector<int>& done,
                             const RunResult& first, const nlohmann::json& J, const nlohmann::json& V, double t_tile,
                             double wall) {
  namespace H = ggins::hil;
  using nlohmann::json;
  const double am2rad = M_PI / (180.0 * 60.0);
  auto norm3 = [](const std::array<double, 24>& row, int c0, double scale) {
    return scale * std::sqrt(row[c0] * row[c0] + row[c0 + 1] * row[c0 + 1] + row[c0 + 2] * row[c0 + 2]);
  };
  std::vector<H::EnsembleRun> runs;
  int stopped = 0, unflown = 0;
  for (int r = 0; r < o.runs; ++r) {
    const RunResult& x = res[r];
    H::EnsembleRun e;
    e.index = o.first_run + r;
    e.seed = 1000003ull * static_cast<unsigned>(o.seed) + static_cast<unsigned>(o.first_run + r);
    e.counts.steps_expected = std::lround(o.hours * 3600 / o.dt);
    e.counts.steps_flown = x.started ? x.steps_flown : 0;
    e.counts.final_seq = e.counts.steps_flown > 0 ? e.counts.steps_flown : -1;  // step k ends at k dt
    e.counts.dt_s = o.dt;
    const bool full = x.started && x.steps_flown == x.steps_expected;
    e.status = full ? "completed" : "interrupted";
    if (!full) ++(x.steps_flown > 0 ? stopped : unflown);
    if (!x.series.empty()) {
      // {final, max} of GGAN (columns 1-9) and of pure inertial (10-18): attitude, velocity, position norms
      const struct { const char* key; int c0; double scale; } q[6] = {
          {"attitude_error_rad", 1, am2rad},          {"velocity_error_mps", 4, 1.0},
          {"position_error_m", 7, 1.0},               {"inertial_attitude_error_rad", 10, am2rad},
          {"inertial_velocity_error_mps", 13, 1.0},   {"inertial_position_error_m", 16, 1.0}};
      for (const auto& k : q) {
        double mx = 0;
        for (const auto& row : x.series) mx = std::max(mx, norm3(row, k.c0, k.scale));
        e.errors[k.key] = {{"final", norm3(x.series.back(), k.c0, k.scale)}, {"max", mx}};
      }
      e.errors["position_error_final_m"] = {{"lat", x.ggan_final[6]}, {"lon", x.ggan_final[7]}, {"h", x.ggan_final[8]}};
      e.errors["inertial_position_error_final_m"] = {{"lat", x.ins_final[6]}, {"lon", x.ins_final[7]}, {"h", x.ins_final[8]}};
    }
    runs.push_back(std::move(e));
  }
  H::FlightEnd end;
  if (stopped + unflown > 0) {
    end.error = "interrupted: " + std::to_string(stopped) + " run(s) stopped, " + std::to_string(unflown) + " of " +
                std::to_string(o.runs) + " not flown";
    end.code = 130;
  }
  // consistency: the final position error of the runs flown to the end against the filter's
  // one-sigma there (RMS over the same runs), north/east/down; N runs, N degrees of freedom
  json cons(nullptr);
  const int n = static_cast<int>(done.size());
  if (n > 0) {
    const char* keys[3] = {"position_lat_m", "position_lon_m", "position_h_m"};
    std::vector<H::ConsistencyState> cs;
    for (int a = 0; a < 3; ++a) {
      double se = 0, ss = 0;
      for (int r : done) {
        const double ev = res[r].ggan_final[6 + a], sg = res[r].series.back()[19 + a];
        se += ev * ev;
        ss += sg * sg;
      }
      cs.push_back({keys[a], std::sqrt(se / n), std::sqrt(ss / n)});
    }
    const double z = 3.0;
    const ggins::truth::Chi2Band band = ggins::truth::chi2_band(n, z);
    cons = H::consistency_block(cs, n, z, band.rms_lo, band.rms_hi,
                                "s/sigma, s = sqrt(sum e^2/N) over the runs of the final position error (lat north, lon "
                                "east, h vertical), sigma = the filter's own final one-sigma, RMS over the same runs");
  }
  json extra = {{"seed0", o.seed},
                {"seeds", "run i: IMU, initial-error and gradiometer noise seed 1000003 seed + i"},
                {"results", J},
                {"voyage", V}};
  extra["results"].erase("per_run");
  extra["filter_per_run"] = J["per_run"];
  json rep = H::ensemble_report(
      "ggins mapnav", "3-D", "gao-voyage", "built in (Gao et al. voyage; the options in scenario.toml)",
      "gravity-gradient map matching UKF (firmware mmukf) against pure inertial on the same voyage, direct calls",
      "direct", 1.0 / o.dt, o.hours * 3600.0, runs, o.runs, end,
      "local level: position lat (north), lon (east), h (vertical) in m; attitude pitch, roll, yaw",
      "estimate minus truth at the update epochs; final: the last epoch flown, max: the largest over the epochs; "
      "position, velocity, attitude: the norm of the three components; inertial_*: the pure inertial solution",
      cons, extra);
  rep["aids"] = json::array({{{"name", "mmukf"},
                              {"updates", first.n_updates},
                              {"gated", first.n_gated},
                              {"offmap", first.n_offmap},
                              {"fail", first.n_fail},
                              {"step_ns_median", first.step_ns_median},
                              {"update_step_us_median", first.update_us_median},
                              {"counted_over", "the first run flown"}}});
  rep["setup_s"] = t_tile;
  rep["wall_s"] = wall;
  rep["files"] = {{"summary", "summary.json"}, {"scenario", "scenario.toml"}, {"timeseries", "timeseries.csv"}};
  if (o.tile.empty()) rep["files"]["tile"] = "tile.bin";
  rep["output_dir"] = std::filesystem::absolute(o.out).string();
  return rep;
}

}  // namespace

int main(int argc, char** argv) {
  namespace C = ggins::cli;
  Opt o;
  CLI::App app{"ggins mapnav - gravity-gradient map matching UKF (Gao et al.) vs pure inertial on a voyage with\n"
               "acceleration, cruise, deceleration and turns; Monte Carlo with NEES/NIS. Defaults = Gao's Table 1."};
  app.add_option("--hours", o.hours, "voyage length, h")->capture_default_str()->check(C::FiniteRange(0, 1000, C::kOpenLow));
  app.add_option("--dt", o.dt, "IMU / mechanization step, s")->capture_default_str()->check(C::FiniteRange(0, GG_LIM_MM_DT_MAX_S, C::kOpenLow));
  app.add_option("--update", o.update, "measurement update period, s")->capture_default_str()->check(C::FiniteRange(0, 1e5, C::kOpenLow));
  app.add_option("--meas-noise-e", o.meas_e, "gradiometer noise, E")->capture_default_str()->check(C::FiniteRange(0, 1e5, C::kOpenLow));
  app.add_option("--db-noise-e", o.db_e, "map database noise, E")->capture_default_str()->check(C::FiniteRange(0, 1e5));
  app.add_option("--att0-deg", o.att_deg, "initial attitude error (one sigma per axis), deg")->capture_default_str()->check(C::FiniteRange(0, 0.5 / kD2R, C::kOpenLow));
  app.add_option("--vel0", o.vel, "initial velocity error, m/s")->capture_default_str()->check(C::FiniteRange(0, 1e3, C::kOpenLow));
  app.add_option("--pos0", o.pos, "initial position error, m")->capture_default_str()->check(C::FiniteRange(0, 1e5, C::kOpenLow));
  app.add_option("--gyro-bias-dph", o.gyro_dph, "gyro bias, deg/h")->capture_default_str()->check(C::FiniteRange(0, 1e3));
  app.add_option("--acc-bias-ug", o.acc_ug, "accelerometer bias, micro-g")->capture_default_str()->check(C::FiniteRange(0, 1e5));
  app.add_option("--arw", o.arw_dprh, "gyro angle random walk, deg/sqrt(h)")->capture_default_str()->check(C::FiniteRange(0, 1e2));
  app.add_option("--vrw", o.vrw_ug_rhz, "accelerometer noise, micro-g/sqrt(Hz)")->capture_default_str()->check(C::FiniteRange(0, 1e5));
  app.add_option("--lat0", o.lat0, "start latitude, deg")->capture_default_str()->check(C::FiniteRange(-85, 85));
  app.add_option("--lon0", o.lon0, "start longitude, deg")->capture_default_str()->check(C::FiniteRange(-180, 360));
  app.add_option("--depth", o.depth, "depth below the ellipsoid, m")->capture_default_str()->check(C::FiniteRange(-1e4, 1.1e4));
  app.add_option("--speed", o.speed, "cruise speed, m/s")->capture_default_str()->check(C::FiniteRange(0, 300));
  app.add_option("--spacing", o.spacing, "map node spacing, deg")->capture_default_str()->check(C::FiniteRange(1e-3, 1));
  app.add_option("--lambda", o.lambda, "UT spread (0 = Gao)")->capture_default_str()->check(C::FiniteRange(0, 100));
  app.add_option("--gate", o.gate, "NIS gate (0 = none)")->capture_default_str()->check(C::NonNegativeFinite());
  app.add_option("--passes", o.passes, "max progressive update passes (1 = Gao's single UKF update)")->capture_default_str()->check(C::IntRange(1, GG_MM_MAX_PASSES));
  app.add_option("--runs", o.runs, "Monte Carlo runs")->capture_default_str()->check(C::IntRange(1, 100000));
  app.add_option("--threads", o.threads, "parallel runs")->capture_default_str()->check(C::IntRange(1, 256));
  app.add_option("--seed", o.seed, "seed")->capture_default_str()->check(C::Seed(2147483647));
  app.add_option("--first-run", o.first_run, "index of the first run (to repeat one run of a Monte Carlo set)")->capture_default_str()->check(C::IntRange(0, 2147483647));
  app.add_flag("--fixed-errors", o.fixed_errors, "initial errors and biases = +1 sigma on every axis (no draw)");
  app.add_flag("!--no-plot", o.plot, "skip the plots");
  app.add_option("--egm96", o.egm, "EGM96 coefficients")->capture_default_str();
  app.add_option("--gradiometer", o.gradiometer,
                 "direct: Gamma_b = field + white noise; diff3d: six accelerometers at +-a through the firmware's gg_diff3d")
      ->check(CLI::IsMember({"direct", "diff3d"}))
      ->capture_default_str();
  app.add_option("--half-base", o.half_base, "diff3d: half-baseline a = b = c, m")->capture_default_str()->check(C::FiniteRange(0, 10, C::kOpenLow));
  app.add_flag("!--no-gyro-term", o.gyro_term,
               "diff3d with --diff3d-omega imu/imu-mean: do not tell the filter that the gyro's rate removed [Omega x]^2 "
               "(by default it predicts [w x]^2 - [(w - b_g) x]^2 and adds the rate noise's share to R)");
  app.add_option("--offdiag-ratio", o.offdiag_ratio,
                 "filter's noise of the off-diagonal components relative to the diagonal ones "
                 "(< 0: 1/sqrt(2) with --gradiometer diff3d, whose off-diagonal elements average four readings->check(C::FiniteRange(-1, GG_LIM_MM_OFFDIAG_MAX)); 1 with direct)")
      ->capture_default_str();
  app.add_option("--diff3d-omega", o.diff3d_omega, "diff3d: rate removing [Omega x]^2: true; imu (the epoch's noisy, biased gyro sample); "
                 "imu-mean (each sample's gyro, averaged over the update period)")
      ->check(CLI::IsMember({"true", "imu", "imu-mean"}))
      ->capture_default_str();
  app.add_option("--tile", o.tile, "use this map tile (.bin/.json) instead of generating one");
  app.add_option("--out", o.out, "output folder")->capture_default_str()->check(C::OutputDir());
  return C::run("ggins mapnav", app, argc, argv, [&]() -> int {
    namespace fs = std::filesystem;
    // combinations: at least one update in the voyage, an update period of whole steps
    if (o.update < o.dt)
      throw C::BadArgument("--update " + std::to_string(o.update) + " s is shorter than --dt " + std::to_string(o.dt) +
                           " s (allowed: --update >= --dt)");
    if (o.hours * 3600.0 < o.update)
      throw C::BadArgument("--hours " + std::to_string(o.hours) + " is shorter than one update period (--update " +
                           std::to_string(o.update) + " s): no measurement would be used (allowed: --hours * 3600 >= --update)");
    if (o.hours * 3600.0 / o.dt > 1e9)
      throw C::BadArgument("--hours " + std::to_string(o.hours) + " with --dt " + std::to_string(o.dt) +
                           " s is more than 1e9 steps (allowed: hours * 3600 / dt <= 1e9)");
    fs::create_directories(o.out);
    // Ctrl-C / SIGTERM: no further run starts, the runs under way stop at their next check,
    // and the report says which flew (status interrupted, exit 130)
    ggins::hil::install_interrupt_handlers();
    const auto t0 = std::chrono::steady_clock::now();
    gg_mm_nav_t start{};
    start.q[0] = std::cos(M_PI / 8); start.q[3] = std::sin(M_PI / 8);  // heading 45 deg, level
    start.lat = o.lat0 * kD2R; start.lon = o.lon0 * kD2R; start.h = -o.depth;
    // the route's extent (truth with the commanded motion only), for the tile
    double lat_min = start.lat, lat_max = start.lat, lon_min = start.lon, lon_max = start.lon;
    {
      gg_mm_nav_t x = start;
      const long steps = std::lround(o.hours * 3600 / 1.0);
      for (long k = 0; k < steps; ++k) {
        const gg_mm_imu_t m = ideal_imu(x, command(k * 1.0, o.speed));
        gg_mm_mech(&x, &m, 1.0, 0, 0, 0);
        lat_min = std::min(lat_min, x.lat); lat_max = std::max(lat_max, x.lat);
        lon_min = std::min(lon_min, x.lon); lon_max = std::max(lon_max, x.lon);
      }
    }
    auto truth_field = ggins::gmap::make_egm96_field(o.egm, 360, false);
    std::unique_ptr<gg_gmap_t> map;
    if (!o.tile.empty()) {
      map = ggins::gmap::read_tile_file(o.tile);
    } else {
      ggins::gmap::TileSpec sp;
      const double m = 0.2;  // margin, deg
      sp.lat_min_deg = lat_min / kD2R - m; sp.lat_max_deg = lat_max / kD2R + m;
      sp.lon_min_deg = lon_min / kD2R - m; sp.lon_max_deg = lon_max / kD2R + m;
      sp.spacing_deg = o.spacing; sp.alt_m = -o.depth; sp.h_range_m = 300;
      sp.noise_e = o.db_e; sp.seed = static_cast<std::uint64_t>(o.seed); sp.threads = o.threads;
      auto tile = ggins::gmap::make_tile(*truth_field, sp);
      map = std::make_unique<gg_gmap_t>();
      if (gg_gmap_init(map.get(), tile.get()) != GG_OK) throw std::runtime_error("tile rejected");
      const auto b = ggins::gmap::encode(*tile);
      C::write_file(o.out + "/tile.bin", std::string(reinterpret_cast<const char*>(b.data()), b.size()), true);
    }
    const double t_tile = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<RunResult> res(o.runs);
    std::mutex mu;
    int next = 0;
    std::exception_ptr failure;
    std::vector<std::thread> pool;
    for (int w = 0; w < std::max(1, o.threads); ++w)
      pool.emplace_back([&] {
        for (;;) {
          int r;
          { std::lock_guard<std::mutex> l(mu); r = next++; }
          if (r >= o.runs || ggins::hil::interrupted()) return;
          try {
            res[r] = run_one(o, o.first_run + r, map.get(), *truth_field, start);
          } catch (...) {  // handed to the main thread (an exception must not leave a worker)
            std::lock_guard<std::mutex> l(mu);
            if (!failure) failure = std::current_exception();
            next = o.runs;
            return;
          }
        }
      });
    for (auto& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // the statistics are over the runs flown to the end (all of them, unless interrupted)
    std::vector<int> done;
    for (int r = 0; r < o.runs; ++r)
      if (res[r].started && res[r].steps_flown == res[r].steps_expected) done.push_back(r);
    const int n_done = static_cast<int>(done.size());
    const RunResult& first = n_done > 0 ? res[done[0]] : res[0];  // the run of the counters and the time series
    // Table 2 style: mean and spread (sd over runs) of |final error| and of the 2 h RMS
    nlohmann::json J;
    const char* names[9] = {"pitch_arcmin", "roll_arcmin", "yaw_arcmin", "vE_mps", "vN_mps", "vU_mps", "lat_m", "lon_m", "h_m"};
    auto stats = [&](auto get) {
      nlohmann::json j;
      for (int c = 0; c < 9; ++c) {
        double s = 0, s2 = 0;
        for (int r : done) { const double v = std::fabs(get(res[r])[c]); s += v; s2 += v * v; }
        const double m = n_done > 0 ? s / n_done : std::nan("");
        j[names[c]] = {{"mean_abs", m}, {"sd", n_done > 1 ? std::sqrt(std::max(0.0, s2 / n_done - m * m)) : 0.0}};
      }
      return j;
    };
    J["ggan_final"] = stats([](const RunResult& r) { return r.ggan_final; });
    J["ins_final"] = stats([](const RunResult& r) { return r.ins_final; });
    J["ins_sensor_errors_only_final"] = stats([](const RunResult& r) { return r.ins0_final; });
    J["ggan_rms_last2h"] = stats([](const RunResult& r) { return r.ggan_rms2h; });
    J["ins_rms_last2h"] = stats([](const RunResult& r) { return r.ins_rms2h; });
    // consistency: NEES (15 states) and position NEES (3) averaged over runs and epochs after the first hour,
    // NIS (6) over all accepted updates
    double sn = 0, snp = 0, sni = 0; long cn = 0, cni = 0;
    std::array<double, 5> sb{};
    for (int ri : done) {
      const RunResult& r = res[ri];
      for (std::size_t i = 0; i < r.nees.size(); ++i)
        if (r.series[i][0] > 3600 || o.hours <= 1) {
          sn += r.nees[i]; snp += r.nees_pos[i]; ++cn;
          for (int b = 0; b < 5; ++b) sb[b] += r.nees_blk[i][b];
        }
      for (double v : r.nis) { sni += v; ++cni; }
    }
    // a mean over no sample is no number: null (a flight too short for an update, or a first hour not over)
    auto mean_or_null = [](double sum, long n) { return n > 0 ? nlohmann::json(sum / double(n)) : nlohmann::json(nullptr); };
    for (int b = 0; b < 5; ++b)
      J["nees_block_mean"][std::vector<std::string>{"att", "vel", "pos", "bg", "ba"}[b]] = mean_or_null(sb[b], cn);
    J["per_run"] = nlohmann::json::array();
    for (int r : done) {
      const auto& x = res[r];
      double a = 0, b = 0, c2 = 0; long n = 0;
      for (std::size_t i = 0; i < x.nees.size(); ++i) if (x.series[i][0] > 3600 || o.hours <= 1) { a += x.nees[i]; b += x.nees_pos[i]; ++n; }
      for (double v : x.nis) c2 += v;
      J["per_run"].push_back({{"run", o.first_run + r}, {"nees_mean", mean_or_null(a, n)}, {"nees_pos_mean", mean_or_null(b, n)},
                              {"nis_mean", mean_or_null(c2, long(x.nis.size()))}, {"final", x.ggan_final}, {"rms_last2h", x.ggan_rms2h}});
    }
    J["nees_mean"] = mean_or_null(sn, cn); J["nees_dof"] = GG_MM_NX;
    J["nees_pos_mean"] = mean_or_null(snp, cn); J["nees_pos_dof"] = 3;
    J["nis_mean"] = mean_or_null(sni, cni); J["nis_dof"] = 6; J["nees_samples"] = cn; J["nis_samples"] = cni;
    // the voyage as flown (the options in effect)
    nlohmann::json V;
    V["runs"] = o.runs; V["first_run"] = o.first_run; V["voyage_h"] = o.hours; V["dt_s"] = o.dt; V["update_s"] = o.update;
    V["passes"] = o.passes; V["meas_noise_E"] = o.meas_e; V["db_noise_E"] = o.db_e; V["att0_deg"] = o.att_deg;
    V["vel0_mps"] = o.vel; V["pos0_m"] = o.pos; V["gyro_bias_dph"] = o.gyro_dph; V["acc_bias_ug"] = o.acc_ug;
    V["arw_deg_per_rth"] = o.arw_dprh; V["vrw_ug_per_rthz"] = o.vrw_ug_rhz; V["lat0_deg"] = o.lat0; V["lon0_deg"] = o.lon0;
    V["depth_m"] = o.depth; V["speed_mps"] = o.speed; V["spacing_deg"] = o.spacing; V["lambda"] = o.lambda;
    V["gate_nis"] = o.gate; V["seed"] = o.seed; V["fixed_errors"] = o.fixed_errors;
    V["gradiometer"] = o.gradiometer;
    V["gyro_term"] = o.gyro_term && o.gradiometer == "diff3d" && o.diff3d_omega != "true";
    V["offdiag_ratio"] = offdiag_ratio(o);
    V["tile_nodes"] = map->tile.nlat * map->tile.nlon;
    V["tile"] = o.tile.empty() ? std::string("generated: tile.bin") : o.tile;
    if (o.gradiometer == "diff3d") {
      // measured diff3d error against the field's Gamma_b at the centre (noise + finite baseline + omega removal)
      std::array<double, 6> s{}, s2{};
      long n = 0;
      for (int ri : done) { const RunResult& r = res[ri]; for (int j = 0; j < 6; ++j) { s[j] += r.d3_err_sum[j]; s2[j] += r.d3_err_sq[j]; } n += r.d3_n; }
      nlohmann::json d;
      const char* cn[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
      for (int j = 0; j < 6; ++j) {
        const double m = n ? s[j] / n : 0;
        d[cn[j]] = {{"mean_e", m / kE}, {"sd_e", n ? std::sqrt(std::max(0.0, s2[j] / n - m * m)) / kE : 0}};
      }
      J["diff3d"] = {{"half_base_m", o.half_base}, {"omega", o.diff3d_omega},
                     {"sigma_acc_mps2", std::sqrt(2.0) * o.half_base * o.meas_e * kE}, {"samples", n}, {"gamma_minus_field", d}};
    }
    const nlohmann::json rep = mapnav_report(o, res, done, first, J, V, t_tile, wall);
    {  // the options as flown, in scenario form
      nlohmann::json set;
      for (const auto& [k, v] : V.items())
        if (!v.is_object()) set["voyage." + k] = v;
      ggins::hil::write_effective_scenario(o.out + "/scenario.toml", "gao-voyage", "ggins mapnav options", "", set);
    }
    C::write_file(o.out + "/summary.json", rep.dump(2) + "\n");
    {
      // errors: attitude in arcmin (am), velocity east/north/up in m/s, position in m; sig_*: the
      // filter's position one-sigma (north, east, down), m; nis, nees: dimensionless (_1)
      std::ofstream f(o.out + "/timeseries.csv");
      f << "t_s,ggan_pitch_am,ggan_roll_am,ggan_yaw_am,ggan_vE_mps,ggan_vN_mps,ggan_vU_mps,ggan_lat_m,ggan_lon_m,ggan_h_m,"
           "ins_pitch_am,ins_roll_am,ins_yaw_am,ins_vE_mps,ins_vN_mps,ins_vU_mps,ins_lat_m,ins_lon_m,ins_h_m,"
           "sig_N_m,sig_E_m,sig_D_m,nis_1,nees_1\n";
      for (auto& row : first.series) {
        for (int j = 0; j < 24; ++j) f << (j ? "," : "") << row[j];
        f << "\n";
      }
      f.close();
      if (!f) throw std::runtime_error("cannot write " + o.out + "/timeseries.csv");
    }
    std::printf("mapnav: %d run(s), %.1f h, update %.0f s, meas %.3g E, db %.3g E; wall %.1f s (tile %.1f s, %d nodes)\n",
                o.runs, o.hours, o.update, o.meas_e, o.db_e, wall, t_tile, map->tile.nlat * map->tile.nlon);
    std::printf("%-28s %8s %8s %8s | %7s %7s %7s | %8s %8s %8s\n", "mean |error| at end", "pitch'", "roll'", "yaw'", "vE", "vN",
                "vU", "lat m", "lon m", "h m");
    for (const char* k : {"ins_final", "ins_sensor_errors_only_final", "ggan_final", "ggan_rms_last2h"}) {
      std::printf("%-28s", k);
      for (int c = 0; c < 9; ++c) std::printf(c == 3 || c == 6 ? " | %7.3g" : " %8.3g", J[k][names[c]]["mean_abs"].get<double>());
      std::printf("\n");
    }
    auto num_or_none = [](const nlohmann::json& v) {
      char b[32];
      if (v.is_null()) return std::string("none (no sample)");
      std::snprintf(b, sizeof b, "%.2f", v.get<double>());
      return std::string(b);
    };
    std::printf("NEES %s (dof 15), position NEES %s (dof 3), NIS %s (dof 6); updates %u gated %u off-map %u fail %u\n",
                num_or_none(J["nees_mean"]).c_str(), num_or_none(J["nees_pos_mean"]).c_str(),
                num_or_none(J["nis_mean"]).c_str(), first.n_updates, first.n_gated, first.n_offmap, first.n_fail);
    std::printf("NEES per block (dof 3 each): %s\n", J["nees_block_mean"].dump().c_str());
    if (J.contains("diff3d"))
      std::printf("diff3d (a = %.3g m, sigma_a = %.3g m/s^2, omega %s): Gamma_b - field, sd per component (E): %s\n", o.half_base,
                  J["diff3d"]["sigma_acc_mps2"].get<double>(), o.diff3d_omega.c_str(), J["diff3d"]["gamma_minus_field"].dump().c_str());
    std::printf("filter step %.0f ns (median, no update), update step %.0f us (median, host)\n", first.step_ns_median,
                first.update_us_median);
#ifdef GGINS_PLOT_SCRIPT
    if (o.plot && !ggins::hil::interrupted()) {
      const std::string cmd = std::string("/usr/bin/python3 ") + GGINS_PLOT_SCRIPT + " '" + o.out + "' > /dev/null 2>&1";
      if (std::system(cmd.c_str()) != 0) std::printf("(plot failed: %s)\n", cmd.c_str());
    }
#endif
    std::printf("report: %s\n", o.out.c_str());
    if (rep["status"] == "interrupted") std::fprintf(stderr, "ggins mapnav: %s\n", rep["error"].get<std::string>().c_str());
    return ggins::hil::exit_status(rep);
  });
}
