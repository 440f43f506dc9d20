// The flight's along-track gravimetry record (gravimetry_raw.csv), written by ggins run3d
// beside timeseries.csv and read by ggins gravimetry (ggins/gravimetry/survey.hpp).
//
// The gravity the navigation carries, as a disturbance, NED at the nav position (m/s^2):
//   gradiometer mode  dg_nav = C_e_n (G_e - gamma(r_nav)), G_e (hi + lo) dead-reckoned from
//                     the measured gradient. The barometer loop's integral state a_c is left
//                     out: here it absorbs the barometer's own slow errors (d^2 h_baro/dt^2 of
//                     its Gauss-Markov part), not gravity (vchan.h);
//   model mode        dg_nav = C_e_n (G_e - a_c u - gamma(r_nav)), G_e the onboard normal model
//                     and -a_c u Rubenstein & Winter's airborne-gravimeter estimate of the
//                     vertical disturbance (the loop's integral state, vchan.h: r'' = f + G_e - a_c u),
// u the ellipsoid normal (up) at the nav position, gamma the WGS-84 normal gravitation
// (gravity/normal.hpp; the centrifugal part is common to gravity and normal gravity, so the
// disturbance of gravitation is that of gravity).
//
// * the vertical channel: the barometer loop moves the nav's height by the barometer's errors
//   (vchan.h) and G with it by the MEASURED gradient (G_e += Gamma_e dr_e), so the anomaly's
//   share of G follows the nav height: component j gains integral Gamma_anom,jD d(dh), dh the
//   height error. Its constant part (the bias sigma_bh, taken up by the loop in the first
//   minutes) gives a step of variance (Gamma_anom,jD(0) sigma_bh)^2 at the start; its first-order
//   Gauss-Markov part (sigma_gm, tau) has increments of variance 2 sigma_gm^2 h / tau per step,
//   so tau_j grows by Gamma_anom,jD^2 2 sigma_gm^2 h / tau (Gamma_anom from the task's own
//   measured gradient). The loop's filtering of the barometer's white
//   noise is left out (it leaves centimetres in the height).
//
// The measured gradient's disturbance Gamma_e(nav) - Gamma_normal(r_nav) in NED (E): what
// carries a value from one point to a nearby one (closing point, crossovers).
// Truth for the same row, from the scenario's field (never seen by the task):
//   at the nav position   C_e_n(nav) (G(r_nav) - gamma(r_nav))     (what a map made of
//                         the navigation's positions should read there)
//   at the true position  C_e_n(true) (G(r_true) - gamma(r_true))
//
// The predicted error of the dead-reckoned G (gradiometer mode), per NED component j:
//   dG(t) = integral dGamma dr,  so for white gradient noise a random walk in the
//   accumulated variance tau_j(t) = sum over steps of var((dGamma dr)_j), dr = v_n h:
//   * accelerometer noise sigma_n per reading: a diagonal tensor entry is the difference of
//     two readings over 2 d (diff3d.h), variance s^2 = sigma_n^2 / (2 d^2) (d_min, the
//     shortest half-baseline, bounds every entry), an off-diagonal one the mean of two such
//     differences, s^2 / 2; that structure is the same in every frame, so
//       var((dGamma dr)_j) = s^2 / 2 (|dr|^2 + dr_j^2);
//   * gyro noise sigma_w per sample (strapdown): the [w x]^2 removal with a rate error dw
//     moves the tensor by sum_i dw_i S_i, S_i = e_i w^T + w e_i^T - 2 w_i I (body axes; Gao
//     et al. eqs. 26-30, aid_mmukf.h), so with dr_b the step in body axes
//       var((dGamma dr)_j) = sigma_w^2 sum_i (C_b_n (e_i (w . dr_b) + w dr_b,i - 2 w_i dr_b))_j^2;
//   and for constant reading errors (random biases sigma_b, scale sigma_s on a ~10 m/s^2
//   reading, the fixed biases' largest pair difference) a constant gradient error
//   sigma_Gb = sqrt(sigma_b^2 + (10 sigma_s)^2) / (sqrt(2) d_min) + max fixed difference / (2 d_min),
//   held in BODY axes: its share of component j is sum_kl dGamma_b,kl B_j,kl(t) with
//     B_j,kl(t) = integral (C_b_n)_jk (dr_b)_l          (dr_b = C_n_b dr, m)
//   (on a strapdown body flying forward the down component grows with the path length,
//   whatever the turns, while north and east follow the displacement). Written per row:
//   var_rw_*_mps2sq, the 27 B_j,kl (bias_<j>_<kl>_m), and sigma_Gb in summary.json.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "compare3d.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/truth3d/scenario3d.hpp"
#include "ggins/truth3d/trajectory3d.hpp"

namespace ggins::run3d {

struct GravimetryModel {  // the error model's constants (above), from the scenario's sensors
  double sigma_gamma_noise_ps2 = 0;  // per step, accelerometer white noise
  double sigma_w_radps = 0;          // gyro white noise per step (strapdown; 0 stabilized)
  double sigma_gamma_bias_ps2 = 0;   // constant gradient error
  double baro_bias_m = 0, baro_gm_m = 0, baro_tau_s = 600;  // the vertical channel (barometer loop on)
};

inline GravimetryModel gravimetry_model(const truth3d::Scenario3& sc) {
  GravimetryModel m;
  const auto a = sc.accel_flown();
  const auto g = sc.gyro_flown();
  const double d = std::min({sc.a_m, sc.b_m, sc.c_m});
  m.sigma_gamma_noise_ps2 = a.noise_sigma_mps2 / (std::sqrt(2.0) * d);
  m.sigma_w_radps = sc.strapdown() ? g.noise_sigma_radps : 0.0;
  double fixed = 0;  // the fixed biases' largest difference between opposite readings
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      fixed = std::max(fixed, std::fabs(a.bias_mps2[static_cast<size_t>(k)][static_cast<size_t>(j)] -
                                        a.bias_mps2[static_cast<size_t>(k + 3)][static_cast<size_t>(j)]));
  const double sp = std::hypot(a.bias_sigma_mps2, 10.0 * a.scale_sigma);
  m.sigma_gamma_bias_ps2 = sp / (std::sqrt(2.0) * d) + fixed / (2 * d);
  if (sc.baro_loop_enabled() && sc.nav_gravity != "model") {
    m.baro_bias_m = sc.baro.bias_m;
    m.baro_gm_m = sc.baro.gm_sigma_m;
    m.baro_tau_s = sc.baro.gm_tau_s;
  }
  return m;
}

class GravimetryRecord {
 public:
  GravimetryRecord(const gravity::Field& field, GravimetryModel model, double h_s, bool model_mode)
      : field_(field), model_(model), h_(h_s), model_mode_(model_mode) {}

  bool open(const std::string& path) {
    f_.open(path);
    if (!f_) return false;
    f_ << "t_s,seq,nav_lat_deg,nav_lon_deg,nav_h_m,true_lat_deg,true_lon_deg,true_h_m,speed_mps,"
          "est_dg_n_mps2,est_dg_e_mps2,est_dg_d_mps2,truth_nav_dg_n_mps2,truth_nav_dg_e_mps2,truth_nav_dg_d_mps2,"
          "truth_true_dg_n_mps2,truth_true_dg_e_mps2,truth_true_dg_d_mps2,loop_a_c_mps2,var_rw_n_mps2sq,"
          "var_rw_e_mps2sq,var_rw_d_mps2sq,"
          "est_gam_nn_E,est_gam_ee_E,est_gam_dd_E,est_gam_ne_E,est_gam_nd_E,est_gam_ed_E,health";
    for (const char* j : {"n", "e", "d"})
      for (const char* kl : {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"}) f_ << ",bias_" << j << "_" << kl << "_m";
    f_ << "\n";
    return true;
  }
  // Every step (the variance accumulates per step); a row when `write`.
  void step(const truth3d::Truth3& t, const gg_nav3d_output_t& o, bool write) {
    using truth3d::Real;
    truth3d::Vec3 r, g;
    for (int i = 0; i < 3; ++i) {
      r(i) = static_cast<Real>(o.r_e[i]) + static_cast<Real>(o.r_e_lo[i]);
      g(i) = static_cast<Real>(o.g_e[i]) + static_cast<Real>(o.g_e_lo[i]);
    }
    const double v = std::sqrt(o.v_n[0] * o.v_n[0] + o.v_n[1] * o.v_n[1] + o.v_n[2] * o.v_n[2]);
    const bool acc = steps_ % kEvery == 0;
    if (!acc && !(write && f_)) {
      ++steps_;
      return;
    }
    const truth3d::Mat3 C_n_e = truth3d::ned_to_ecef(static_cast<Real>(o.lat_rad), static_cast<Real>(o.lon_rad));
    if (acc) {
      // once every kEvery steps for the kEvery steps that follow (the motion and the gradient
      // change little in kEvery / rate_hz = 0.1 s): per-step variances times kEvery, the
      // integrals over kEvery steps
      const Eigen::Vector3d dr(o.v_n[0] * h_, o.v_n[1] * h_, o.v_n[2] * h_);
      const double s2 = model_.sigma_gamma_noise_ps2 * model_.sigma_gamma_noise_ps2;
      Eigen::Vector3d inc = s2 / 2 * (Eigen::Vector3d::Constant(dr.squaredNorm()) + dr.cwiseAbs2());
      const Eigen::Matrix3d C_b_n = (C_n_e.transpose() * dcm_from_quat(o.q_b_e)).cast<double>();
      const Eigen::Vector3d db = C_b_n.transpose() * dr;
      if (C_b_n.allFinite() && db.allFinite())
        for (int j = 0; j < 3; ++j)
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l)
              bias_[static_cast<size_t>(j)][static_cast<size_t>(3 * k + l)] += C_b_n(j, k) * db(l) * kEvery;
      if (model_.sigma_w_radps > 0) {
        const Eigen::Vector3d w(o.omega_b[0], o.omega_b[1], o.omega_b[2]);
        for (int i = 0; i < 3; ++i) {
          const Eigen::Vector3d u = C_b_n * (Eigen::Vector3d::Unit(i) * w.dot(db) + w * db(i) - 2 * w(i) * db);
          inc += model_.sigma_w_radps * model_.sigma_w_radps * u.cwiseAbs2();
        }
      }
      if (model_.baro_bias_m != 0 || model_.baro_gm_m != 0) {
        truth3d::Vec3 r0;
        for (int i = 0; i < 3; ++i) r0(i) = static_cast<Real>(o.r_e[i]);
        truth3d::Mat3 ge;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) ge(i, j) = static_cast<Real>(o.gamma_e[i][j]);
        const truth3d::Mat3 ga = C_n_e.transpose() * (ge - normal_.eval(r0).gamma) * C_n_e;
        for (int j = 0; j < 3; ++j) gam_d_[static_cast<size_t>(j)] = static_cast<double>(ga(j, 2));
        if (steps_ == kEvery && std::isfinite(gam_d_[0] + gam_d_[1] + gam_d_[2]))  // the bias, taken up at the start
          for (int j = 0; j < 3; ++j)
            inc(j) += std::pow(gam_d_[static_cast<size_t>(j)] * model_.baro_bias_m, 2) / kEvery;
      }
      if (model_.baro_gm_m != 0 && model_.baro_tau_s > 0)
        for (int j = 0; j < 3; ++j)
          inc(j) += gam_d_[static_cast<size_t>(j)] * gam_d_[static_cast<size_t>(j)] * 2 * model_.baro_gm_m *
                    model_.baro_gm_m * h_ / model_.baro_tau_s;
      if (inc.allFinite() && std::isfinite(v))
        for (int j = 0; j < 3; ++j) tau_[static_cast<size_t>(j)] += inc(j) * kEvery;
    }
    ++steps_;
    if (!write || !f_) return;
    const truth3d::Vec3 up = -C_n_e.col(2);
    const truth3d::Vec3 g_nav = model_mode_ ? truth3d::Vec3(g - static_cast<Real>(o.g_up_corr) * up) : g;
    const truth3d::Vec3 est = C_n_e.transpose() * (g_nav - normal_.gravitation(r));
    const truth3d::Vec3 tn = C_n_e.transpose() * (field_.gravitation(r) - normal_.gravitation(r));
    truth3d::Mat3 gam;  // the measured gradient's disturbance at the nav position, NED (s^-2)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) gam(i, j) = static_cast<Real>(o.gamma_e[i][j]);
    gam = C_n_e.transpose() * (gam - normal_.eval(r).gamma) * C_n_e;
    const truth3d::Mat3 C_t = truth3d::ned_to_ecef(t.s.lat, t.s.lon);
    const truth3d::Vec3 tt = C_t.transpose() * (t.g_e - normal_.gravitation(t.s.r_e));
    const double deg = 180.0 / M_PI;
    char line[1024];
    std::snprintf(line, sizeof line,
                  "%.3f,%lld,%.10f,%.10f,%.4f,%.10f,%.10f,%.4f,%.4f,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,"
                  "%.9e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%u",
                  static_cast<double>(t.t_s), static_cast<long long>(t.seq), o.lat_rad * deg, o.lon_rad * deg, o.h_m,
                  static_cast<double>(t.s.lat) * deg, static_cast<double>(t.s.lon) * deg, static_cast<double>(t.s.h), v,
                  static_cast<double>(est(0)), static_cast<double>(est(1)), static_cast<double>(est(2)),
                  static_cast<double>(tn(0)), static_cast<double>(tn(1)), static_cast<double>(tn(2)),
                  static_cast<double>(tt(0)), static_cast<double>(tt(1)), static_cast<double>(tt(2)), o.g_up_corr, tau_[0],
                  tau_[1], tau_[2],
                  static_cast<double>(gam(0, 0)) * 1e9,
                  static_cast<double>(gam(1, 1)) * 1e9, static_cast<double>(gam(2, 2)) * 1e9,
                  static_cast<double>(gam(0, 1)) * 1e9, static_cast<double>(gam(0, 2)) * 1e9,
                  static_cast<double>(gam(1, 2)) * 1e9, o.health);
    f_ << line;
    for (const auto& b : bias_)
      for (double x : b) {
        std::snprintf(line, sizeof line, ",%.6e", x);
        f_ << line;
      }
    f_ << "\n";
  }
  void close() {
    if (f_.is_open()) f_.close();
  }

 private:
  const gravity::Field& field_;
  gravity::NormalField normal_;
  GravimetryModel model_;
  double h_ = 0.01;
  bool model_mode_ = false;
  std::array<double, 3> tau_{};  // accumulated random-walk variance per NED component
  std::array<double, 3> gam_d_{};  // Gamma_anom,jD of the last refresh, s^-2
  int64_t steps_ = 0;
  static constexpr int kEvery = 10;  // the error model accumulated once every kEvery steps
  std::array<std::array<double, 9>, 3> bias_{};  // B_j,kl: a body-axis constant gradient error's coefficients
  std::ofstream f_;
};

}  // namespace ggins::run3d
