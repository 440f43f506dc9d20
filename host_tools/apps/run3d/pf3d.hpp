// The cold-atom particle-filter aid of a 3-D flight (aid_pf.h) on the host side of
// run3d: its configuration (truth3d::apply_aid_pf) onto the LCM message, its output fields from it, and the
// report block: counters and the filter's consistency (err / spread)^2 per shot, err
// the horizontal error of the filter's estimate (state + pf_mean_m) and spread^2 the
// sum of the cloud's variances along north and east (1 = consistent; Gaussian: the
// mean of a chi-square with 2 dof over 2).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

extern "C" {
#include "ggins/nav3d.h"
}
#include "ggins/nav3d_config_t.hpp"
#include "ggins/nav3d_output_t.hpp"
#include "ggins/coldatom/ellipse_fit.hpp"
#include "ggins/coldatom/gradiometer.hpp"
#include "ggins/truth3d/coldatom3d.hpp"

namespace ggins::run3d {

inline void aid_pf_config_to_lcm(const gg_aid_pf_config_t& a, ggins::nav3d_config_t& m) {
  const gg_pf_config_t& p = a.pf;
  m.aid_pf_enable = static_cast<int8_t>(a.enable);
  m.aid_pf_chunk = a.chunk;
  m.aid_pf_end_chunk = a.end_chunk;
  m.aid_pf_feedback = a.feedback;
  m.aid_pf_n = p.n;
  m.aid_pf_seed = static_cast<int64_t>(p.seed);
  m.aid_pf_model = p.model;
  m.aid_pf_k_eff = p.k_eff;
  m.aid_pf_T = p.T;
  m.aid_pf_dz = p.dz;
  m.aid_pf_contrast = p.contrast;
  m.aid_pf_c0 = p.c0;
  m.aid_pf_c1 = p.c1;
  m.aid_pf_sigma = p.sigma;
  m.aid_pf_sigma0_pos = p.sigma0_pos;
  m.aid_pf_sigma0_vel = p.sigma0_vel;
  m.aid_pf_sigma0_acc = p.sigma0_acc;
  m.aid_pf_sigma0_jerk = p.sigma0_jerk;
  m.aid_pf_sigma0_bias = p.sigma0_bias;
  m.aid_pf_q_pos = p.q_pos;
  m.aid_pf_q_vel = p.q_vel;
  m.aid_pf_q_acc = p.q_acc;
  m.aid_pf_q_jerk = p.q_jerk;
  m.aid_pf_q_bias = p.q_bias;
  m.aid_pf_reg_bw = p.reg_bw;
  m.aid_pf_dt = p.dt;
  m.aid_pf_gain = p.gain;
  m.aid_pf_ess_frac = p.ess_frac;
  m.aid_pf_integ_enable = static_cast<int8_t>(a.integ.enable);
  m.aid_pf_integ_window = a.integ.window;
  m.aid_pf_integ_z = a.integ.z;
  m.aid_pf_integ_isolate = a.integ.isolate_after;
  m.aid_pf_integ_recover = a.integ.recover_after;
  m.aid_pf_info_min = a.info_min;
}

inline void aid_pf_output_from_lcm(const ggins::nav3d_output_t& m, gg_nav3d_output_t& o) {
  o.pf_phase = m.pf_phase;
  o.pf_corrected = m.pf_corrected;
  o.pf_shots = static_cast<uint32_t>(m.pf_shots);
  o.pf_updates = static_cast<uint32_t>(m.pf_updates);
  o.pf_failed = static_cast<uint32_t>(m.pf_failed);
  o.pf_invalid = static_cast<uint32_t>(m.pf_invalid);
  o.pf_dropped = static_cast<uint32_t>(m.pf_dropped);
  o.pf_no_map = static_cast<uint32_t>(m.pf_no_map);
  o.pf_map_miss = static_cast<uint32_t>(m.pf_map_miss);
  o.pf_degenerate = static_cast<uint32_t>(m.pf_degenerate);
  o.pf_resampled = static_cast<uint32_t>(m.pf_resampled);
  o.pf_ess = m.pf_ess;
  for (int i = 0; i < 2; ++i) {
    o.pf_spread_m[i] = m.pf_spread_m[i];
    o.pf_corr_m[i] = m.pf_corr_m[i];
    o.pf_mean_m[i] = m.pf_mean_m[i];
  }
  o.pf_gzz_s2 = m.pf_gzz_s2;
  o.pf_nis = m.pf_nis;
  o.pf_integ = m.pf_integ;
  o.pf_integ_ratio = m.pf_integ_ratio;
  o.pf_isolated = static_cast<uint32_t>(m.pf_isolated);
  o.pf_uninformative = static_cast<uint32_t>(m.pf_uninformative);
  o.pf_info = m.pf_info;
  for (int i = 0; i < 2; ++i) o.pf_spread_fi_m[i] = m.pf_spread_fi_m[i];
}

// Accumulates the filter's consistency over the shots of a flight.
class PfReport3 {
 public:
  // One output; err_n_m, err_e_m = nav - truth (NED at the true position), m.
  void take(const gg_nav3d_output_t& o, double err_n_m, double err_e_m) {
    if (o.pf_updates != last_.pf_updates && o.pf_info >= -0.5) {  // a weighed shot ended at this step
      ++n_weighed_;
      info_sum_ += o.pf_info;
      info_max_ = std::max(info_max_, o.pf_info);
      withheld_last_ = o.pf_uninformative != last_.pf_uninformative;
    }
    last_ = o;
    if (o.pf_corrected == 0) return;  // a shot's correction was fed at this step
    const double en = err_n_m + o.pf_mean_m[0], ee = err_e_m + o.pf_mean_m[1];
    const double e2 = en * en + ee * ee;
    const double s2 = o.pf_spread_m[0] * o.pf_spread_m[0] + o.pf_spread_m[1] * o.pf_spread_m[1];
    ++n_;
    err_sum_ += std::sqrt(e2);
    if (s2 > 0) {
      nees_sum_ += e2 / s2;
      ++n_nees_;
      if (e2 > 4.0 * s2) ++beyond2_;
    }
  }
  nlohmann::json block(size_t tiles) const {
    nlohmann::json a;
    a["name"] = "aid_pf";
    a["description"] = "cold-atom particle filter (aid_pf.h), closed loop on the horizontal position";
    a["shots"] = last_.pf_shots;
    a["updates"] = last_.pf_updates;
    a["failed"] = last_.pf_failed;
    a["invalid"] = last_.pf_invalid;
    a["dropped"] = last_.pf_dropped;
    a["no_map"] = last_.pf_no_map;
    a["map_miss"] = last_.pf_map_miss;
    a["degenerate"] = last_.pf_degenerate;
    a["resampled"] = last_.pf_resampled;
    a["corrections"] = n_;
    a["estimate_error_mean_m"] = n_ > 0 ? err_sum_ / static_cast<double>(n_) : 0.0;
    a["err_over_spread_sq_mean"] = n_nees_ > 0 ? nees_sum_ / static_cast<double>(n_nees_) : 0.0;
    a["err_over_spread_sq_definition"] =
        "mean over the shots of |horizontal error of state + pf_mean|^2 / (sd_N^2 + sd_E^2) (1 = consistent)";
    a["share_beyond_2_spread"] = n_nees_ > 0 ? static_cast<double>(beyond2_) / static_cast<double>(n_nees_) : 0.0;
    a["ess_last"] = last_.pf_ess;
    a["spread_final_m"] = {{"n", last_.pf_spread_m[0]}, {"e", last_.pf_spread_m[1]}};
    a["tiles"] = tiles;
    a["information"] = {
        {"definition", "info = 1 - (cloud variance N + E) / (free-inertial variance N + E) after a weighed shot: "
                       "the share of dead reckoning's position variance the map removed (pf.h; -1: not modelled)"},
        {"gate_info_min", info_min_},
        {"info_final", last_.pf_info},
        {"info_mean", n_weighed_ > 0 ? info_sum_ / static_cast<double>(n_weighed_) : -1.0},
        {"info_max", n_weighed_ > 0 ? info_max_ : -1.0},
        {"spread_free_inertial_final_m", {{"n", last_.pf_spread_fi_m[0]}, {"e", last_.pf_spread_fi_m[1]}}},
        {"withheld", last_.pf_uninformative},
        {"gate_open_final", gate_open_final()}};
    return a;
  }
  void set_info_min(double v) { info_min_ = v; }
  // The flight's degraded reason when the gate kept the filter's corrections out for
  // most of the flight or at its end (aid_pf.h): the aid did not help there.
  void info_reason(std::vector<std::string>& why) const {
    const int64_t w = static_cast<int64_t>(last_.pf_uninformative), n = static_cast<int64_t>(last_.pf_updates);
    if (info_min_ <= 0 || w == 0 || (gate_open_final() && 2 * w <= n)) return;
    char b[400];
    std::snprintf(b, sizeof b,
                  "particle filter uninformative: corrections withheld on %lld of %lld weighed shots%s (the map removed "
                  "%.3g of the free-inertial position variance at the end, at most %.3g; the gate feeds from %.3g): "
                  "the flight's solution there is dead reckoning",
                  static_cast<long long>(w), static_cast<long long>(n), gate_open_final() ? "" : ", gate closed at the end",
                  last_.pf_info, n_weighed_ > 0 ? info_max_ : -1.0, info_min_);
    why.push_back(b);
  }

 private:
  // the last weighed shot's correction was not withheld by the gate
  bool gate_open_final() const { return !withheld_last_; }
  bool withheld_last_ = false;
  gg_nav3d_output_t last_{};
  int64_t n_ = 0, n_nees_ = 0, beyond2_ = 0, n_weighed_ = 0;
  double err_sum_ = 0, nees_sum_ = 0, info_sum_ = 0, info_max_ = -1, info_min_ = 0;
};

// The gradient estimates of the shots the filter weighed, against the batch-mean true
// Gamma_zz (Phillips et al. section II and Fig. 3): batches of kBatch shots, each giving
//   the ellipse fit's estimate  dphi / (k_eff dz T^2)  of its pairs (ellipse_fit.hpp: the
//     standard method the particle filter replaces; it cannot tell the sign of dphi), and
//   the filter's estimate, the mean over the batch of pf_gzz_s2 (the weighted Gamma_zz of
//     each shot's candidates: the map at the filter's posterior).
// The true Gamma_zz of a shot is the sensor's map at the true position of its step.
class ShotBaseline3 {
 public:
  static constexpr int kBatch = 20;
  explicit ShotBaseline3(double scale_rad_per_s2) : scale_(scale_rad_per_s2) {}
  // A weighed shot: its pair, its true Gamma_zz and the filter's (s^-2).
  void take(double s0, double s1, double gzz_true, double gzz_pf) {
    x_.push_back(s0);
    y_.push_back(s1);
    gt_ += gzz_true;
    gp_ += gzz_pf;
    if (static_cast<int>(x_.size()) < kBatch) return;
    const double t = gt_ / kBatch;
    const ggins::coldatom::EllipseFit f = ggins::coldatom::fit_ellipse(x_, y_);
    if (f.ok) fit_.push_back(f.dphi / scale_ - t);
    else ++fit_failed_;
    pf_.push_back(gp_ / kBatch - t);
    x_.clear();
    y_.clear();
    gt_ = gp_ = 0;
  }
  nlohmann::json block() const {
    return {{"batch_shots", kBatch},
            {"batches", pf_.size()},
            {"definition", "batch estimate - batch-mean true Gamma_zz, E; ellipse fit: dphi / (k_eff dz T^2) of the "
                           "batch's pairs; filter: mean of pf_gzz_s2 (the weighted Gamma_zz of its candidates)"},
            {"ellipse_fit_err_mean_E", mean(fit_) * 1e9},
            {"ellipse_fit_err_std_E", sd(fit_) * 1e9},
            {"ellipse_fit_failed", fit_failed_},
            {"pf_err_mean_E", mean(pf_) * 1e9},
            {"pf_err_std_E", sd(pf_) * 1e9}};
  }

 private:
  static double mean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  }
  static double sd(const std::vector<double>& v) {  // two passes: about the mean
    if (v.size() < 2) return 0.0;
    const double m = mean(v);
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / static_cast<double>(v.size() - 1));
  }
  double scale_;
  std::vector<double> x_, y_;
  double gt_ = 0, gp_ = 0;
  std::vector<double> fit_, pf_;  // the batches' errors, s^-2
  int64_t fit_failed_ = 0;
};

}  // namespace ggins::run3d
