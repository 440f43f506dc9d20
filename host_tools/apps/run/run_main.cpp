// ggins run: one 2-D host-in-the-loop flight (the front-end of the runner,
// hil_common/runner.hpp, with the 2-D task's model).
//
//   truth generator (this process) --GGINS_FRAME--> hal_sim (firmware) --GGINS_NAV--> this process
//
// This process generates the sensor frames of a scenario (host_tools/lib/truth),
// flies them through hal_sim over LCM with the shared transport
// (hil_common/link.hpp: batched, pipelined lockstep or real time) or in
// process (--direct, hil_common/direct.hpp), compares every output with the
// truth in seq order (hil_common/evaluation.hpp), and writes the report
// (hil_common/report.hpp: summary.json), timeseries.csv and plots.
// See `ggins run --help`.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "ggins/nav2d_config_t.hpp"
#include "ggins/nav_output_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth/config2d.hpp"
#include "ggins/truth/generator.hpp"
#include "ggins/truth/survey.hpp"
#include "ggins/truth_t.hpp"
#include "runner.hpp"

namespace fs = std::filesystem;
using ggins::truth::Real;
using ggins::truth::Vec3;
using json = nlohmann::json;
using ggins::hil::Fail;
using ggins::hil::hilo;
using ggins::hil::MaxFinal;
using ggins::hil::wall_us;

namespace {

uint64_t fnv1a(const std::string& s) {
  uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

// The 2-D task for the runner: frames from the 2-D truth generator, the
// firmware configuration, the evaluation of every output against the truth.
class Model2D {
 public:
  using Task = ggins::hil::Task2D;

  Model2D(const ggins::hil::RunOptions& o, const ggins::truth::Scenario& sc) : opt_(o), sc_(sc), gen_(sc) {}

  int64_t n_steps() const { return gen_.n_steps(); }
  int64_t dt_us() const { return sc_.dt_us(); }
  double rate_hz() const { return sc_.rate_hz; }
  double duration_s() const { return sc_.duration_s; }
  std::string name() const { return sc_.name; }
  std::string source() const { return sc_.source; }
  std::string description() const { return sc_.description; }
  uint64_t scenario_id() const { return fnv1a(sc_.name); }
  std::vector<std::string> maps() const { return {}; }
  ggins::hil::Faults faults() const {
    const auto& tp = sc_.transport;
    return {tp.drop_prob, tp.duplicate_prob, tp.reorder_prob, tp.output_drop_prob, tp.garbage_prob, opt_.conflict, tp.seed};
  }
  std::string truth_channel() const { return opt_.prefix + "TRUTH"; }
  int64_t truth_published() const { return truth_published_; }
  double progress_error_m() const { return pos_.final; }

  ggins::nav2d_config_t config();
  void begin(const fs::path& out, ggins::hil::LinkBase* link, int64_t run_id);
  ggins::sensor_frame_t frame(int64_t k);
  void take(const ggins::nav_output_t& m, bool latest);
  void end() { csv_.close(); }
  void report(json& s);
  static std::string final_line(const json& s);
  static void before_plots(const ggins::hil::RunOptions& o, const fs::path& out, const json& summary);

 private:
  const ggins::hil::RunOptions& opt_;
  ggins::truth::Scenario sc_;
  ggins::truth::Generator gen_;
  ggins::hil::LinkBase* link_ = nullptr;  // over LCM (none with --direct)
  int64_t run_id_ = 0;
  std::optional<ggins::truth::SurveyGrid> survey_grid_;  // [navigation.survey], built before hal_sim starts
  json survey_;  // the programmed anomaly grid sent (model mode with [navigation.survey])

  int64_t n_ = 0;
  int64_t truth_every_ = 1, csv_every_ = 1;
  int64_t truth_published_ = 0;
  MaxFinal pos_, vel_, grav_, gam_;
  // vertical channel and gravimeter
  MaxFinal vert_, horiz_, gravim_;
  double settle_s_ = 0;  // statistics "after settling" start here (6 / smallest loop pole)
  double vert_ss_ = 0, vert_max_settled_ = 0, gravim_ss_ = 0, gravim_true_ss_ = 0, gravim_true_sum_ = 0;
  int64_t vert_n_ = 0, gravim_n_ = 0;
  // the true disturbance through the loop's ideal transfer function from the
  // disturbance to -a_c, p1 p2 p3 / ((s + p1)(s + p2)(s + p3)) (vchan.h: a_c' = k3 e,
  // characteristic polynomial s^3 + k1 s^2 + (k2 - 2 w_s^2) s + k3): what a
  // gravimeter of this bandwidth can see; outputs taken in seq order only
  std::array<double, 3> gfilt_{};
  double gfilt_prev_in_ = 0, gfilt_ss_ = 0;
  int64_t gfilt_seq_ = -1, gfilt_n_ = 0;
  double falong_ = 0, fvert_ = 0;
  std::map<int, double> vert_at_h_, horiz_at_h_;  // errors at whole hours
  int64_t baro_due_ = 0, baro_dropped_ = 0, baro_outliers_ = 0, baro_invalid_ = 0;
  std::array<double, 3> fpos_{}, fvel_{}, fgrav_{};
  std::optional<ggins::nav_output_t> last_out_;
  std::ofstream csv_;
};

void Model2D::begin(const fs::path& out, ggins::hil::LinkBase* link, int64_t run_id) {
  link_ = link;
  run_id_ = run_id;
  n_ = gen_.n_steps();
  const double rate = sc_.rate_hz;
  truth_every_ = sc_.output.truth_rate_hz > 0 ? std::max<int64_t>(1, std::llround(rate / sc_.output.truth_rate_hz)) : 1;
  csv_every_ = std::max<int64_t>(1, std::llround(rate / sc_.output.csv_rate_hz));
  csv_.open(out / "timeseries.csv");
  if (!csv_) throw Fail("cannot write " + (out / "timeseries.csv").string());
  // the flight's inertial frame: x equatorial, z polar (y out of the flight plane)
  csv_ << "t_s,seq";
  for (const auto& [q, u] : std::vector<std::pair<const char*, const char*>>{{"true_r", "m"}, {"true_v", "mps"},
                                                                                {"true_g", "mps2"}, {"nav_r", "m"},
                                                                                {"nav_v", "mps"}, {"nav_g", "mps2"},
                                                                                {"err_r", "m"}, {"err_v", "mps"},
                                                                                {"err_g", "mps2"}})
    for (const char* a : {"x", "y", "z"}) csv_ << "," << q << "_" << a << "_" << u;
  csv_ << ",err_r_norm_m,err_v_norm_mps,err_g_norm_mps2,err_gamma_max_ps2,status,health,health_bits";
  csv_ << ",h_true_m,h_nav_m,err_h_m,err_horiz_m,err_along_m,baro_alt_m,baro_due,baro_status,baro_outlier,baro_err_m"
          ",baro_innov_m,a_c_mps2,gd_est_up_mps2,gd_true_up_mps2,gd_err_up_mps2,g_up_nav_mps2,g_up_true_mps2\n";
  if (sc_.baro_loop_enabled()) {
    const auto& pl = sc_.navigation.baro.poles_radps;
    settle_s_ = 6.0 / std::min({pl[0], pl[1], pl[2]});
  }
}

// ---- evaluation of one output (in seq order, once per step) -----------------------
void Model2D::take(const ggins::nav_output_t& m, bool latest) {
  // errors against the truth at the true position (long double)
  const ggins::truth::TruthState t = gen_.truth(m.seq);
  const auto e = ggins::hil::errors2d(t.kin.r, t.kin.v, t.g, t.gamma, m);
  const Vec3 &dr = e.dr, &dv = e.dv, &dg = e.dg;
  const Real dgam = e.dgamma;
  pos_.add(static_cast<double>(dr.norm()), latest);
  vel_.add(static_cast<double>(dv.norm()), latest);
  grav_.add(static_cast<double>(dg.norm()), latest);
  gam_.add(static_cast<double>(dgam), latest);
  if (latest) {
    for (int j = 0; j < 3; ++j) {
      fpos_[static_cast<size_t>(j)] = static_cast<double>(dr(j));
      fvel_[static_cast<size_t>(j)] = static_cast<double>(dv(j));
      fgrav_[static_cast<size_t>(j)] = static_cast<double>(dg(j));
    }
    last_out_ = m;
  }
  // Vertical channel: h = |r| - r_ref (the barometer's altitude); horizontal =
  // the rest of dr (in the 2-D flight: along track). Gravimeter: the vertical
  // gravity disturbance, true minus onboard model along up (positive up):
  //   true      (G(r) - G_model(r)) . u at the TRUE position r,
  //   estimate  (g_nav - G_model(r_nav)) . u_nav - a_c   (the gravity the navigator effectively uses,
  //             less the model; in model mode g_nav = G_model(r_nav), so it is -a_c, Rubenstein & Winter Fig. 4)
  const Vec3 rn(static_cast<Real>(m.r_i[0]), static_cast<Real>(m.r_i[1]), static_cast<Real>(m.r_i[2]));
  const Vec3 gn(static_cast<Real>(m.g_i[0]), static_cast<Real>(m.g_i[1]), static_cast<Real>(m.g_i[2]));
  const Vec3 ut = t.kin.r.normalized(), un = rn.normalized();
  const Real h_true = gen_.altitude(t.kin.r), h_nav = gen_.altitude(rn), err_h = h_nav - h_true;
  const Vec3 dr_h = dr - dr.dot(ut) * ut;
  const Real err_along = dr.dot(t.kin.v.normalized());
  const Real gd_true = (t.g - gen_.model_g(t.kin.r)).dot(ut);
  const Real gd_est = (gn - gen_.model_g(rn)).dot(un) - static_cast<Real>(m.g_up_corr);
  const double t_s = static_cast<double>(t.t_s);
  vert_.add(static_cast<double>(std::fabs(err_h)), latest);
  horiz_.add(static_cast<double>(dr_h.norm()), latest);
  if (latest) {
    falong_ = static_cast<double>(err_along);
    fvert_ = static_cast<double>(err_h);
  }
  const int64_t steps_per_h = 3600000000LL / sc_.dt_us();
  if (3600000000LL % sc_.dt_us() == 0 && m.seq > 0 && m.seq % steps_per_h == 0) {
    vert_at_h_[static_cast<int>(m.seq / steps_per_h)] = static_cast<double>(err_h);
    horiz_at_h_[static_cast<int>(m.seq / steps_per_h)] = static_cast<double>(dr_h.norm());
  }
  if (sc_.baro_loop_enabled() && m.seq == gfilt_seq_ + 1) {
    const double in = static_cast<double>(gd_true), dts = static_cast<double>(sc_.dt_us()) * 1e-6;
    double u = m.seq == 0 ? in : 0.5 * (in + gfilt_prev_in_);  // trapezoidal input over the step
    for (size_t i = 0; i < 3; ++i) {
      const double a = std::exp(-sc_.navigation.baro.poles_radps[i] * dts);
      gfilt_[i] = m.seq == 0 ? 0.0 : a * gfilt_[i] + (1.0 - a) * u;
      u = gfilt_[i];
    }
    gfilt_prev_in_ = in;
    gfilt_seq_ = m.seq;
    if (t_s >= settle_s_) {
      const double e = static_cast<double>(gd_est) - gfilt_[2];
      gfilt_ss_ += e * e;
      ++gfilt_n_;
    }
  }
  if (t_s >= settle_s_) {
    const double e = static_cast<double>(err_h), ge = static_cast<double>(gd_est - gd_true);
    vert_ss_ += e * e;
    vert_max_settled_ = std::max(vert_max_settled_, std::fabs(e));
    ++vert_n_;
    gravim_.add(std::fabs(ge));
    gravim_ss_ += ge * ge;
    gravim_true_ss_ += static_cast<double>(gd_true * gd_true);
    gravim_true_sum_ += static_cast<double>(gd_true);
    ++gravim_n_;
  }
  const ggins::truth::BaroSample bs = gen_.baro(m.seq, t);
  if (bs.due) {
    ++baro_due_;
    baro_dropped_ += bs.dropped;
    baro_outliers_ += bs.outlier && !bs.dropped;
    baro_invalid_ += bs.invalid && !bs.dropped;
  }
  if (csv_ && (m.seq % csv_every_ == 0 || m.seq == n_ - 1)) {
    char line[4200];
    int p = std::snprintf(line, sizeof line, "%.6Lf,%lld", t.t_s, static_cast<long long>(m.seq));
    auto put3 = [&](const double* v) {
      for (int j = 0; j < 3; ++j) p += std::snprintf(line + p, sizeof line - static_cast<size_t>(p), ",%.17g", v[j]);
    };
    auto put3L = [&](const Vec3& v) {
      for (int j = 0; j < 3; ++j) p += std::snprintf(line + p, sizeof line - static_cast<size_t>(p), ",%.21Lg", v(j));
    };
    put3L(t.kin.r);
    put3L(t.kin.v);
    put3L(t.g);
    put3(m.r_i);
    put3(m.v_i);
    put3(m.g_i);
    put3L(dr);
    put3L(dv);
    put3L(dg);
    p += std::snprintf(line + p, sizeof line - static_cast<size_t>(p), ",%.6Lg,%.6Lg,%.6Lg,%.6Lg,%d,%lld,%s", dr.norm(),
                       dv.norm(), dg.norm(), dgam, m.status, static_cast<long long>(m.health),
                       ggins::hil::health_csv(static_cast<uint32_t>(m.health)).c_str());
    // vertical channel, barometer (the sample of this step, if any) and gravimeter
    p += std::snprintf(line + p, sizeof line - static_cast<size_t>(p),
                       ",%.12Lg,%.12Lg,%.9Lg,%.9Lg,%.9Lg,%.12g,%d,%d,%d,%.9g,%.9g,%.9g,%.12Lg,%.12Lg,%.9Lg,%.12g,%.12Lg", h_true,
                       h_nav, err_h, dr_h.norm(), err_along, bs.alt_m, bs.due ? 1 : 0, bs.status, bs.outlier ? 1 : 0,
                       bs.due ? bs.error_m : 0.0, m.baro_innov_m, m.g_up_corr, gd_est, gd_true, gd_est - gd_true,
                       static_cast<double>(gn.dot(un)), t.g.dot(ut));
    p += std::snprintf(line + p, sizeof line - static_cast<size_t>(p), "\n");
    csv_.write(line, p);
  }
}

// ---- frames -------------------------------------------------------------------------
// Frame k (its first transmission; the transport keeps it for resends) and,
// decimated, the truth at its time on the bus.
ggins::sensor_frame_t Model2D::frame(int64_t k) {
  gg_frame_t f;
  ggins::truth::TruthState t;
  gen_.frame(k, f, &t);
  const ggins::sensor_frame_t m = ggins::hil::sensor_frame_msg(f, run_id_, 0);
  if (link_ && (k % truth_every_ == 0 || k == n_ - 1)) {
    ggins::truth_t tm{};
    tm.utime = t.utime;
    tm.seq = k;
    tm.run_id = run_id_;
    tm.t_s = static_cast<double>(t.t_s);
    for (int j = 0; j < 3; ++j) {
      hilo(t.kin.r(j), tm.r_hi[j], tm.r_lo[j]);
      hilo(t.kin.v(j), tm.v_hi[j], tm.v_lo[j]);
      hilo(t.g(j), tm.g_hi[j], tm.g_lo[j]);
      tm.a[j] = static_cast<double>(t.kin.a(j));
      tm.f_c[j] = static_cast<double>(t.f_c(j));
      for (int i = 0; i < 3; ++i) tm.gamma[j][i] = static_cast<double>(t.gamma(j, i));
    }
    link_->publish(truth_channel(), tm);
    ++truth_published_;
  }
  return m;
}

// ---- the configuration ------------------------------------------------------------------
ggins::nav2d_config_t Model2D::config() {
  if (sc_.navigation.gravity == "model" && sc_.navigation.survey.enable)  // before hal_sim: it may take a while
    survey_grid_ = ggins::truth::make_survey_grid(gen_);                   // (truth field at every node)
  // the one scenario -> configuration mapping (truth/config2d.hpp), sent as its LCM message
  const gg_nav2d_config_t f = ggins::truth::config2d(gen_, survey_grid_ ? &*survey_grid_ : nullptr);
  ggins::nav2d_config_t c{};
  c.utime = wall_us();
  c.seq = 0;
  c.run_id = run_id_;
  std::memset(c.scenario, 0, sizeof c.scenario);
  std::memcpy(c.scenario, sc_.name.data(), std::min<size_t>(sc_.name.size(), 63));
  c.a_m = static_cast<double>(f.geometry.a_m);
  c.b_m = static_cast<double>(f.geometry.b_m);
  c.dt_us = f.dt_us;
  c.dt_tol_us = f.dt_tol_us;
  for (int j = 0; j < 3; ++j) {
    hilo(f.r0[j], c.r0_hi[j], c.r0_lo[j]);
    hilo(f.v0[j], c.v0_hi[j], c.v0_lo[j]);
    hilo(f.g0[j], c.g0_hi[j], c.g0_lo[j]);
  }
  c.f_max = f.f_max;
  c.asym_max = f.asym_max;
  c.gravdr_trapezoid_only = static_cast<int8_t>(f.gravdr_trapezoid_only);
  c.fdi_parity_f_max = f.fdi_parity_f_max;
  c.fdi_asym_max = f.fdi_asym_max;
  c.acc_frozen_frames = f.acc_frozen_frames;
  c.gravity_mode = static_cast<int8_t>(f.gravity_mode);
  hilo(f.model.gm, c.model_gm_hi, c.model_gm_lo);
  c.model_a_m = static_cast<double>(f.model.a_m);
  for (int n = 0; n < 9; ++n) c.model_j[n] = static_cast<double>(f.model.j[n]);
  c.grid_n_th = f.model.grid.n_th;
  c.grid_n_rho = f.model.grid.n_rho;
  c.grid_c0 = static_cast<double>(f.model.grid.c0);
  c.grid_s0 = static_cast<double>(f.model.grid.s0);
  c.grid_th0_rad = static_cast<double>(f.model.grid.th0_rad);
  c.grid_dth_rad = static_cast<double>(f.model.grid.dth_rad);
  c.grid_rho0_m = static_cast<double>(f.model.grid.rho0_m);
  c.grid_drho_m = static_cast<double>(f.model.grid.drho_m);
  for (int i = 0; i < GG_GMODEL_GRID_MAX; ++i) {
    c.grid_dg[i][0] = f.model.grid.dg[i][0];
    c.grid_dg[i][1] = f.model.grid.dg[i][1];
  }
  if (c.gravity_mode == GG_GRAVITY_MODEL && survey_grid_) {
    const ggins::truth::SurveyGrid& g = *survey_grid_;
    survey_ = {{"nodes_theta", g.n_th}, {"nodes_rho", g.n_rho}, {"spacing_m", sc_.navigation.survey.spacing_m},
               {"drho_m", g.drho_m}, {"seed", sc_.navigation.survey.seed},
               {"noise_gravity_mgal", sc_.navigation.survey.noise_gravity_mgal},
               {"noise_deflection_arcsec", sc_.navigation.survey.noise_deflection_arcsec},
               {"rms_noise_tangential_mps2", g.rms_noise_t}, {"rms_noise_radial_mps2", g.rms_noise_r},
               {"rms_true_tangential_mps2", g.rms_true_t}, {"rms_true_radial_mps2", g.rms_true_r}};
  }
  c.baro_enable = static_cast<int8_t>(f.baro_enable);
  for (int i = 0; i < 3; ++i) c.baro_poles[i] = static_cast<double>(f.baro.poles[i]);
  c.baro_omega_s2 = static_cast<double>(f.baro.omega_s2);
  c.baro_period_us = f.baro.period_us;
  c.baro_max_age_us = f.baro.max_age_us;
  c.baro_coast_us = f.baro.coast_us;
  c.baro_alt_min_m = f.baro.alt_min_m;
  c.baro_alt_max_m = f.baro.alt_max_m;
  c.baro_gate_m = f.baro.gate_m;
  c.baro_max_rejects = f.baro.max_rejects;
  hilo(f.r_ref_m, c.r_ref_hi, c.r_ref_lo);
  return c;
}

// ---- the report's 2-D blocks ------------------------------------------------------------
void Model2D::report(json& s) {
  using ggins::hil::axes_json;
  json& e = s["errors"];
  e["frame"] = "the flight's inertial frame: x equatorial, z polar, y normal to the flight plane";
  e["definition"] = "nav - truth at the same step; gravity: G estimated by the firmware - true gravitation at the TRUE "
                    "position; gradient: largest |element| of the x/z block";
  e["position_error_m"] = pos_.json();
  e["velocity_error_mps"] = vel_.json();
  e["gravity_error_mps2"] = grav_.json();
  e["gradient_error_max_abs_ps2"] = gam_.json();
  e["position_error_final_m"] = axes_json(fpos_);
  e["velocity_error_final_mps"] = axes_json(fvel_);
  e["gravity_error_final_mps2"] = axes_json(fgrav_);
  if (last_out_) {
    const auto& m = *last_out_;
    const Vec3 rn(m.r_i[0], m.r_i[1], m.r_i[2]);
    const Vec3 g_at_nav = gen_.field().eval(rn).g;
    Vec3 d;
    for (int j = 0; j < 3; ++j) d(j) = static_cast<Real>(m.g_i[j]) - g_at_nav(j);
    e["gravity_error_vs_field_at_estimated_position_final_mps2"] = static_cast<double>(d.norm());
  }
  {  // vertical channel, horizontal errors, gravimeter, barometer
    json v;
    v["definition"] = "h = |r| - r_ref; error = h(nav) - h(true); horizontal = dr less its component along the true up";
    v["r_ref_m"] = sc_.r_ref_m();
    v["baro_loop"] = sc_.baro_loop_enabled();
    v["final_error_m"] = fvert_;
    v["max_abs_error_m"] = vert_.max;
    v["settle_s"] = settle_s_;
    // after settling: none on a flight shorter than settle_s (null, not 0)
    v["samples_after_settle"] = vert_n_;
    v["rms_error_after_settle_m"] = vert_n_ ? json(std::sqrt(vert_ss_ / static_cast<double>(vert_n_))) : json(nullptr);
    v["max_abs_error_after_settle_m"] = vert_n_ ? json(vert_max_settled_) : json(nullptr);
    json vh = json::object(), hh = json::object();
    for (const auto& [h, e] : vert_at_h_) vh[std::to_string(h) + "h"] = e;
    for (const auto& [h, e] : horiz_at_h_) hh[std::to_string(h) + "h"] = e;
    v["error_at_hours_m"] = vh;
    s["vertical"] = v;
    s["horizontal"] = {{"final_error_m", horiz_.final},
                       {"max_error_m", horiz_.max},
                       {"final_along_track_error_m", falong_},
                       {"error_at_hours_m", hh}};
    json g;
    g["definition"] = "vertical gravity disturbance along up (true minus onboard model, m/s^2); estimate = "
                      "(g_nav - G_model(r_nav)).u_nav - a_c (model mode: -a_c); error over t >= settle_s";
    g["mode"] = sc_.navigation.gravity;
    g["settle_s"] = settle_s_;
    g["samples"] = gravim_n_;
    const json none(nullptr);
    g["rms_error_mps2"] = gravim_n_ ? json(std::sqrt(gravim_ss_ / static_cast<double>(gravim_n_))) : none;
    g["max_abs_error_mps2"] = gravim_n_ ? json(gravim_.max) : none;
    g["rms_true_disturbance_mps2"] = gravim_n_ ? json(std::sqrt(gravim_true_ss_ / static_cast<double>(gravim_n_))) : none;
    g["mean_true_disturbance_mps2"] = gravim_n_ ? json(gravim_true_sum_ / static_cast<double>(gravim_n_)) : none;
    if (gfilt_n_ > 0)  // error against the true disturbance low-passed by the loop (lag removed)
      g["rms_error_vs_loop_filtered_truth_mps2"] = std::sqrt(gfilt_ss_ / static_cast<double>(gfilt_n_));
    g["poles_radps"] = sc_.navigation.baro.poles_radps;
    g["loop_filter"] = "p1 p2 p3 / ((s + p1)(s + p2)(s + p3)), group delay 1/p1 + 1/p2 + 1/p3 = " +
                       std::to_string(1.0 / sc_.navigation.baro.poles_radps[0] + 1.0 / sc_.navigation.baro.poles_radps[1] +
                                      1.0 / sc_.navigation.baro.poles_radps[2]) + " s";
    s["gravimeter"] = g;
    if (!survey_.is_null()) s["survey_grid"] = survey_;
    s["baro"] = {{"enabled", sc_.baro.enable},   {"samples_due", baro_due_},      {"dropped", baro_dropped_},
                 {"outliers_sent", baro_outliers_}, {"invalid_sent", baro_invalid_}};
  }
}

// The plots' one-sigma envelopes: Welker et al.'s error model along the same trajectory
// (ggins covariance on the scenario as flown, covariance/ beside the flight's files).
void Model2D::before_plots(const ggins::hil::RunOptions& o, const fs::path& out, const json&) {
  ggins::hil::error_model_covariance(o, out, "ggins-covariance");
}

std::string Model2D::final_line(const json& s) {
  const json& e = s["errors"];
  char b[512];
  std::snprintf(b, sizeof b, "ggins run: %s %s: %lld steps, final |dr| = %.3e m, |dv| = %.3e m/s, |dG| = %.3e m/s^2",
                s["scenario"].get<std::string>().c_str(), s["status"].get<std::string>().c_str(),
                static_cast<long long>(s["steps_flown"].get<int64_t>()), e["position_error_m"]["final"].get<double>(),
                e["velocity_error_mps"]["final"].get<double>(), e["gravity_error_mps2"]["final"].get<double>());
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  ggins::hil::RunOptions o;
  o.tool = "ggins run";
  o.python = GGINS_PLOT_PYTHON;
  o.logger = GGINS_LCM_LOGGER;
  std::string scenario = "welker-perfect";
  CLI::App app{
      "ggins run: fly one scenario host-in-the-loop over LCM.\n\n"
      "The truth generator (this process) computes each accelerometer's specific force\n"
      "f = a - G(r + d_i) from the scenario's analytic trajectory and gravitation field\n"
      "(long double, G evaluated at every sensor), adds the scenario's sensor errors and\n"
      "publishes sensor frames; hal_sim (a separate process) implements the firmware's\n"
      "HAL over LCM and steps the firmware once per frame; every message of the run is\n"
      "recorded to an LCM log (--log). In lockstep mode (default) the firmware steps every\n"
      "frame once, in order, as fast as the machine allows: frames travel --batch per message\n"
      "with a window of frames in flight sized from the round trip, outputs come back in\n"
      "batches; a frame hal_sim misses is asked for at once (negative acknowledgement), an\n"
      "output that is missing is asked for as soon as a later one arrives; all of it is\n"
      "counted, and the outputs are taken in seq order, so the numbers are the same bit for\n"
      "bit whatever the transport does, and the same as --direct (in process, no bus).\n\n"
      "Output folder (--out, default out/<scenario>-<UTC time>):\n"
      "  summary.json     the flight report (docs/hil.md, the same shape as ggins run3d's):\n"
      "                   status (completed, degraded, failed, interrupted), steps flown and\n"
      "                   unflown, frames lost and recovered, health seen (raw and named bits),\n"
      "                   errors (final = last step flown, and max), wall_s, realtime_factor,\n"
      "                   firmware step time (median/p99/max ns), transport counters, log check\n"
      "  timeseries.csv   truth, navigation and error at --csv-rate (default 1 Hz), units in\n"
      "                   every column; x equatorial, z polar (the flight's inertial frame)\n"
      "  errors.png       position, velocity and gravity error against time with the\n"
      "                   one-sigma envelope of the error model (and errors_log.png, the\n"
      "                   norms on a log scale)\n"
      "  covariance/      the error model's covariance for the scenario as flown (ggins\n"
      "                   covariance: Welker et al., eqs. 7-11), computed for the plots;\n"
      "                   covariance.log says why when the model does not cover the\n"
      "                   scenario (an anomaly field, gravity-model navigation)\n"
      "  vertical.png     vertical error h(nav) - h(true), h = |r| - r_ref, barometer error\n"
      "                   and innovation; gravimeter.png (barometer loop on): the along-track\n"
      "                   vertical gravity disturbance, estimate against truth (summary.json\n"
      "                   \"vertical\", \"horizontal\", \"gravimeter\", \"baro\", \"health_counts\")\n"
      "  run.lcmlog       every message of the run (play with: lcm-logplayer run.lcmlog)\n"
      "  scenario.toml    the scenario as flown (effective values, overrides applied);\n"
      "                   hal_sim.log (its stderr)\n"
      "Gravity error = |G estimated - true gravitation at the TRUE position|.\n"
      "Gravimeter: vertical gravity disturbance along up, true = (G - G_model) . u at the\n"
      "true position (G_model = the onboard zonal model, [navigation.model]); estimate =\n"
      "(g_nav - G_model(r_nav)) . u_nav - a_c (model mode: -a_c, the loop's integral state).\n\n"
      "Scenarios are TOML files: --scenario takes a path, or a name looked up in\n"
      "" GGINS_SCENARIO_DIR " and then among the built-ins.\n"
      "Each run uses its own LCM ports (udpm://239.255.76.67:<free port>?ttl=0, one per\n"
      "direction) and run id, so runs in parallel do not interfere. Needs UDP multicast\n"
      "on loopback:\n"
      "  ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo   (as root)\n\n"
      "Exit status: 0 run completed, every frame used; 1 run failed; 2 bad arguments or\n"
      "scenario; 3 multicast on loopback unavailable; 4 completed but degraded (frames\n"
      "rejected, the last output missing, or an outage at the end: summary.json\n"
      "\"degraded\", \"steps_rejected\", \"recovery\"); 130 interrupted (Ctrl-C: hal_sim is\n"
      "stopped, the report is written with status \"interrupted\" and the unflown steps).",
      "ggins run"};
  app.get_formatter()->column_width(34);
  app.add_option("-s,--scenario", scenario, "scenario name or .toml path")->capture_default_str();
  ggins::hil::add_run_options(app, o);
  ggins::hil::FrontEndFlags flags;
  ggins::hil::add_scenario_flags(app, flags);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  namespace truth = ggins::truth;
  ggins::hil::ScenarioFrontEnd<truth::Scenario> fe;
  fe.names = [] { return truth::builtin_scenario_names(); };
  fe.load = [](const std::string& n, const truth::ScenarioAdjust& adjust) {
    return truth::load_scenario(n, {GGINS_SCENARIO_DIR}, adjust);
  };
  fe.template_toml = [] { return truth::scenario_to_toml(truth::Scenario{}, true); };
  fe.apply = [&](truth::Scenario& sc) {
    if (o.csv_rate) sc.output.csv_rate_hz = *o.csv_rate;
    if (o.truth_rate) sc.output.truth_rate_hz = *o.truth_rate;
    if (o.drop) sc.transport.drop_prob = *o.drop;
    if (o.dup) sc.transport.duplicate_prob = *o.dup;
    if (o.reorder) sc.transport.reorder_prob = *o.reorder;
    if (o.drop_output) sc.transport.output_drop_prob = *o.drop_output;
    if (o.garbage) sc.transport.garbage_prob = *o.garbage;
    if (o.fault_seed) sc.transport.seed = *o.fault_seed;
  };
  // scenario.toml as flown: every key, the effective values (overrides applied)
  fe.as_flown = [](const truth::Scenario& sc) { return truth::scenario_to_toml(sc); };
  fe.fly = [&](truth::Scenario& sc, const std::string& as_flown) {
    return ggins::hil::fly_scenario<Model2D>(o, sc.name, sc.source, as_flown, json::object(), GGINS_PLOT_SCRIPT,
                                             [&](const fs::path&) { return std::make_unique<Model2D>(o, sc); });
  };
  return ggins::hil::scenario_main(o, scenario, flags, fe);
}
