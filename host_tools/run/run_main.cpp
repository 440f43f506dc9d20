// ggins run: one host-in-the-loop flight over LCM.
//
//   truth generator (this process) --GGINS_FRAME--> hal_sim (firmware) --GGINS_NAV--> this process
//
// This process generates the sensor frames of a scenario (host_tools/truth),
// flies them through hal_sim over LCM with the shared transport
// (hil_common/link.hpp: batched, pipelined lockstep or real time) or in
// process (--direct, hil_common/direct.hpp), compares every output with the
// truth in seq order, and writes summary.json, timeseries.csv and plots.
// See `ggins run --help`.
#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "ggins/hal_status_t.hpp"
#include "ggins/nav2d_config_t.hpp"
#include "ggins/nav_output_t.hpp"
#include "ggins/run_control_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth/generator.hpp"
#include "ggins/truth/survey.hpp"
#include "ggins/truth_t.hpp"
#include "direct.hpp"
#include "hil_common.hpp"
#include "link.hpp"

namespace fs = std::filesystem;
using ggins::truth::Real;
using ggins::truth::Vec3;
using json = nlohmann::json;
using ggins::hil::Fail;
using ggins::hil::free_udp_ports;
using ggins::hil::hilo;
using ggins::hil::mono_s;
using ggins::hil::Recorder;
using ggins::hil::spawn;
using ggins::hil::stop_child;
using ggins::hil::wait_child;
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


struct Stats {  // running max / final of one error quantity
  double max = 0, final = 0;
  // latest: the sample belongs to the highest step seen so far (outputs can
  // arrive out of order; the final value is that of the last step flown)
  void add(double x, bool latest = true) {
    if (latest) final = x;
    if (!(x <= max)) max = x;  // NaN propagates into max
  }
};

struct Percentiles {
  double median = 0, p99 = 0, max = 0;
};

// Exact order statistics of cycle counts in bounded memory: one bin per tick
// below kBins (131 us at 1 ns/tick), the rare larger values kept as they are.
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
  Percentiles percentiles() {
    Percentiles p;
    if (n_ == 0) return p;
    std::sort(big_.begin(), big_.end());
    auto at = [&](double q) {  // value of rank round(q (n - 1)), 0-based
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

std::string module_name(int j) {
  switch (j) {
    case GG_MOD_DIFF: return "diff";
    case GG_MOD_GRAVDR: return "gravdr";
    case GG_MOD_MECH: return "mech";
    case GG_MOD_VCHAN: return "vchan";
    case GG_MOD_TOTAL: return "total";
    case GG_MOD_AID: return "aid";
    default: return "module" + std::to_string(j);
  }
}

json health_names(uint32_t h) {
  static const struct {
    uint32_t bit;
    const char* name;
  } kBits[] = {{GG_HEALTH_NOT_INIT, "NOT_INIT"},         {GG_HEALTH_ACC_NONFINITE, "ACC_NONFINITE"},
               {GG_HEALTH_ACC_RANGE, "ACC_RANGE"},       {GG_HEALTH_ACC_SENSOR, "ACC_SENSOR"},
               {GG_HEALTH_SEQ_GAP, "SEQ_GAP"},           {GG_HEALTH_SEQ_REPEAT, "SEQ_REPEAT"},
               {GG_HEALTH_TIME_JUMP, "TIME_JUMP"},       {GG_HEALTH_GAMMA_ASYM, "GAMMA_ASYM"},
               {GG_HEALTH_FRAME_REJECTED, "FRAME_REJECTED"}, {GG_HEALTH_DEADLINE, "DEADLINE"},
               {GG_HEALTH_BARO_INVALID, "BARO_INVALID"}, {GG_HEALTH_BARO_STALE, "BARO_STALE"},
               {GG_HEALTH_BARO_OUTLIER, "BARO_OUTLIER"}, {GG_HEALTH_BARO_RECAPTURE, "BARO_RECAPTURE"},
               {GG_HEALTH_BARO_COAST, "BARO_COAST"},     {GG_HEALTH_ACC_FAULT, "ACC_FAULT"},
               {GG_HEALTH_ACC_REBUILT, "ACC_REBUILT"},   {GG_HEALTH_GRAD_COAST, "GRAD_COAST"},
               {GG_HEALTH_MODEL_OUTSIDE, "MODEL_OUTSIDE"}, {GG_HEALTH_GYRO_INVALID, "GYRO_INVALID"},
               {GG_HEALTH_RESYNC, "RESYNC"},             {GG_HEALTH_COAST, "COAST"},
               {GG_HEALTH_ACC_DEGRADED, "ACC_DEGRADED"}, {GG_HEALTH_FORCE_COAST, "FORCE_COAST"},
               {GG_HEALTH_MM_BAD_MEAS, "MM_BAD_MEAS"},   {GG_HEALTH_MM_NO_MAP, "MM_NO_MAP"},
               {GG_HEALTH_MM_GATED, "MM_GATED"},         {GG_HEALTH_MM_FAIL, "MM_FAIL"}};
  json j = json::array();
  uint32_t known = 0;
  for (const auto& b : kBits) {
    known |= b.bit;
    if (h & b.bit) j.push_back(b.name);
  }
  if (h & ~known) j.push_back("0x" + [&] { char x[16]; std::snprintf(x, sizeof x, "%x", h & ~known); return std::string(x); }());
  return j;
}

// ------------------------------------------------------------------------------------
struct Options {
  std::string scenario = "welker-perfect";
  std::string out;
  bool realtime = false;
  std::optional<double> duration_s;
  std::optional<uint64_t> seed;
  std::optional<double> csv_rate, truth_rate;
  std::optional<double> drop, dup, reorder, drop_output, garbage;
  double conflict = 0;
  std::string lcm_url;
  std::string prefix = "GGINS_";
  int resend_timeout_ms = 50;
  int max_resend = 100;
  bool no_log = false, no_plots = false, quiet = false;
  std::string log_mode = "internal";
  std::string progress = "auto";
  std::string hal_sim, python = GGINS_PLOT_PYTHON, logger = GGINS_LCM_LOGGER;
  bool direct = false;
  int batch = 0, window = 0;
  double deadline_ms = 0;
};

class Runner {
 public:
  Runner(const Options& o, const ggins::truth::Scenario& sc, fs::path out)
      : opt_(o), sc_(sc), gen_(sc), out_(std::move(out)) {}
  json run();

 private:
  void consume(const ggins::nav_output_t& m);
  ggins::sensor_frame_t make_frame(int64_t k);
  ggins::nav2d_config_t build_config();
  void progress(bool final);

  const Options& opt_;
  ggins::truth::Scenario sc_;
  ggins::truth::Generator gen_;
  fs::path out_;
  std::unique_ptr<ggins::hil::Link<ggins::hil::Task2D>> link_;  // over LCM (none with --direct)
  int64_t run_id_ = 0;
  std::string ch_truth_;
  std::optional<ggins::truth::SurveyGrid> survey_grid_;  // [navigation.survey], built before hal_sim starts
  json survey_;  // the programmed anomaly grid sent (model mode with [navigation.survey])

  int64_t n_ = 0;
  int64_t truth_every_ = 1, csv_every_ = 1;
  int64_t outputs_ = 0, truth_published_ = 0;
  int64_t steps_rejected_ = 0;
  uint32_t health_or_ = 0;
  CycleStats cyc_[GG_MOD_COUNT];
  Stats pos_, vel_, grav_, gam_;
  // vertical channel and gravimeter
  Stats vert_, horiz_, gravim_;
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
  std::array<int64_t, 32> health_count_{};
  int64_t baro_due_ = 0, baro_dropped_ = 0, baro_outliers_ = 0, baro_invalid_ = 0;
  std::array<double, 3> fpos_{}, fvel_{}, fgrav_{};
  std::optional<ggins::nav_output_t> last_out_;
  std::ofstream csv_;
  double t_start_ = 0, t_last_progress_ = 0, wall_loop_ = 0;
  int64_t last_seq_done_ = -1;
  bool tty_ = false;
  int last_pct_reported_ = -1;
};

// ---- evaluation of one output (in seq order, once per step) -----------------------
void Runner::consume(const ggins::nav_output_t& m) {
  ++outputs_;
  if (m.status != 0) ++steps_rejected_;
  health_or_ |= static_cast<uint32_t>(m.health);
  for (int j = 0; j < GG_MOD_COUNT; ++j)
    cyc_[j].add(j < m.n_cycles ? static_cast<uint32_t>(m.cycles[j]) : 0u);
  last_seq_done_ = m.seq;

  // errors against the truth at the true position (long double)
  const ggins::truth::TruthState t = gen_.truth(m.seq);
  Vec3 dr, dv, dg;
  for (int j = 0; j < 3; ++j) {
    dr(j) = static_cast<Real>(m.r_i[j]) - t.kin.r(j);
    dv(j) = static_cast<Real>(m.v_i[j]) - t.kin.v(j);
    dg(j) = static_cast<Real>(m.g_i[j]) - t.g(j);
  }
  Real dgam = 0;
  for (int j : {0, 2})  // the 2-D firmware measures the x/z block only
    for (int i : {0, 2}) dgam = std::max(dgam, std::fabs(static_cast<Real>(m.gamma_i[j][i]) - t.gamma(j, i)));
  const bool latest = !last_out_ || m.seq > last_out_->seq;
  pos_.add(static_cast<double>(dr.norm()), latest);
  vel_.add(static_cast<double>(dv.norm()), latest);
  grav_.add(static_cast<double>(dg.norm()), latest);
  gam_.add(static_cast<double>(dgam), latest);
  if (latest) {
    for (int j = 0; j < 3; ++j) {
      fpos_[j] = static_cast<double>(dr(j));
      fvel_[j] = static_cast<double>(dv(j));
      fgrav_[j] = static_cast<double>(dg(j));
    }
    last_out_ = m;
  }
  for (int b = 0; b < 32; ++b)
    if (static_cast<uint32_t>(m.health) & (1u << b)) ++health_count_[static_cast<size_t>(b)];
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
    char line[4096];
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
    p += std::snprintf(line + p, sizeof line - static_cast<size_t>(p), ",%.6Lg,%.6Lg,%.6Lg,%.6Lg,%d,%lld", dr.norm(),
                       dv.norm(), dg.norm(), dgam, m.status, static_cast<long long>(m.health));
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
ggins::sensor_frame_t Runner::make_frame(int64_t k) {
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
    link_->publish(ch_truth_, tm);
    ++truth_published_;
  }
  return m;
}

// ---- the configuration ------------------------------------------------------------------
ggins::nav2d_config_t Runner::build_config() {
  const ggins::truth::TruthState t0 = gen_.truth(0);
  ggins::nav2d_config_t c{};
  c.utime = wall_us();
  c.seq = 0;
  c.run_id = run_id_;
  std::memset(c.scenario, 0, sizeof c.scenario);
  std::memcpy(c.scenario, sc_.name.data(), std::min<size_t>(sc_.name.size(), 63));
  c.a_m = sc_.a_m;
  c.b_m = sc_.b_m;
  c.dt_us = sc_.dt_us();
  c.dt_tol_us = sc_.firmware.dt_tol_us;
  for (int j = 0; j < 3; ++j) {
    hilo(t0.kin.r(j), c.r0_hi[j], c.r0_lo[j]);
    hilo(t0.kin.v(j), c.v0_hi[j], c.v0_lo[j]);
    hilo(t0.g(j), c.g0_hi[j], c.g0_lo[j]);
  }
  c.f_max = sc_.firmware.f_max_mps2;
  c.asym_max = sc_.firmware.asym_max_ps2;
  c.gravdr_trapezoid_only = sc_.firmware.gravdr_trapezoid_only ? 1 : 0;
  c.fdi_parity_f_max = sc_.firmware.fdi_parity_f_max_mps2;
  c.fdi_asym_max = sc_.firmware.fdi_asym_max_ps2;
  // gravity source, onboard model, barometric loop, altitude reference
  c.gravity_mode = sc_.navigation.gravity == "model" ? 1 : 0;  // GG_GRAVITY_MODEL : GG_GRAVITY_GRADIOMETER (nav2d.h)
  {
    const ggins::truth::NavModelParams nm = sc_.nav_model();
    hilo(static_cast<Real>(nm.gm_m3ps2), c.model_gm_hi, c.model_gm_lo);
    c.model_a_m = nm.a_m;
    for (int n = 0; n < 9; ++n) c.model_j[n] = nm.j[static_cast<size_t>(n)];
  }
  if (c.gravity_mode == 1 && survey_grid_) {  // programmed anomaly grid (truth/survey.hpp)
    const ggins::truth::SurveyGrid& g = *survey_grid_;
    c.grid_n_th = g.n_th;
    c.grid_n_rho = g.n_rho;
    c.grid_c0 = g.c0;
    c.grid_s0 = g.s0;
    c.grid_th0_rad = g.th0_rad;
    c.grid_dth_rad = g.dth_rad;
    c.grid_rho0_m = g.rho0_m;
    c.grid_drho_m = g.drho_m;
    for (size_t i = 0; i < g.dg.size() && i < 1024; ++i) {
      c.grid_dg[i][0] = g.dg[i][0];
      c.grid_dg[i][1] = g.dg[i][1];
    }
    survey_ = {{"nodes_theta", g.n_th}, {"nodes_rho", g.n_rho}, {"spacing_m", sc_.navigation.survey.spacing_m},
               {"drho_m", g.drho_m}, {"seed", sc_.navigation.survey.seed},
               {"noise_gravity_mgal", sc_.navigation.survey.noise_gravity_mgal},
               {"noise_deflection_arcsec", sc_.navigation.survey.noise_deflection_arcsec},
               {"rms_noise_tangential_mps2", g.rms_noise_t}, {"rms_noise_radial_mps2", g.rms_noise_r},
               {"rms_true_tangential_mps2", g.rms_true_t}, {"rms_true_radial_mps2", g.rms_true_r}};
  }
  c.baro_enable = sc_.baro_loop_enabled() ? 1 : 0;
  {
    const auto& l = sc_.navigation.baro;
    for (int i = 0; i < 3; ++i) c.baro_poles[i] = l.poles_radps[static_cast<size_t>(i)];
    // w_s^2 = |G| / |r| at the start (the point-mass vertical gradient is 2 w_s^2)
    c.baro_omega_s2 = l.omega_s2 > 0 ? l.omega_s2 : static_cast<double>(t0.g.norm() / t0.kin.r.norm());
    c.baro_period_us = std::llround(sc_.baro_period_s() * 1e6);
    c.baro_max_age_us = std::llround(l.max_age_s * 1e6);
    c.baro_coast_us = std::llround(l.coast_s * 1e6);
    c.baro_alt_min_m = l.alt_min_m;
    c.baro_alt_max_m = l.alt_max_m;
    c.baro_gate_m = l.gate_m;
    c.baro_max_rejects = static_cast<int32_t>(l.max_rejects);
  }
  hilo(static_cast<Real>(sc_.r_ref_m()), c.r_ref_hi, c.r_ref_lo);
  return c;
}

// ---- the flight ----------------------------------------------------------------------
void Runner::progress(bool final) {
  if (opt_.quiet) return;
  const double now = mono_s();
  const bool show_tty = tty_ && opt_.progress != "off";
  const double frac = n_ > 0 ? static_cast<double>(outputs_) / static_cast<double>(n_) : 1.0;
  const double sim_t = static_cast<double>(std::max<int64_t>(last_seq_done_, 0)) * static_cast<double>(sc_.dt_us()) * 1e-6;
  const double el = now - t_start_;
  char msg[256];
  std::snprintf(msg, sizeof msg, "t = %7.1f / %.0f s  %5.1f%%  wall %6.1f s  x%.0f real time  |dr| %.3g m  |dG| %.3g m/s^2",
                sim_t, sc_.duration_s, 100.0 * frac, el, el > 0 ? sim_t / el : 0.0, pos_.final, grav_.final);
  if (show_tty) {
    if (!final && now - t_last_progress_ < 0.25) return;
    t_last_progress_ = now;
    std::fprintf(stderr, "\r%s", msg);
    if (final) std::fprintf(stderr, "\n");
  } else if (opt_.progress != "off") {  // not a terminal: one line per 10%
    const int pct = static_cast<int>(frac * 10.0) * 10;
    if (pct > last_pct_reported_) {
      last_pct_reported_ = pct;
      std::fprintf(stderr, "ggins run: %s\n", msg);
    }
  }
}

json Runner::run() {
  n_ = gen_.n_steps();
  const double rate = sc_.rate_hz;
  truth_every_ = sc_.output.truth_rate_hz > 0 ? std::max<int64_t>(1, std::llround(rate / sc_.output.truth_rate_hz)) : 1;
  csv_every_ = std::max<int64_t>(1, std::llround(rate / sc_.output.csv_rate_hz));
  tty_ = isatty(2);

  ch_truth_ = opt_.prefix + "TRUTH";
  csv_.open(out_ / "timeseries.csv");
  if (!csv_) throw Fail("cannot write " + (out_ / "timeseries.csv").string());
  csv_ << "t_s,seq";
  for (const char* q : {"true_r", "true_v", "true_g", "nav_r", "nav_v", "nav_g", "err_r", "err_v", "err_g"})
    for (const char* a : {"x", "y", "z"}) csv_ << "," << q << "_" << a;
  csv_ << ",err_r_norm_m,err_v_norm_mps,err_g_norm_mps2,err_gamma_max_ps2,status,health";
  csv_ << ",h_true_m,h_nav_m,err_h_m,err_horiz_m,err_along_m,baro_alt_m,baro_due,baro_status,baro_outlier,baro_err_m"
          ",baro_innov_m,a_c_mps2,gd_est_up_mps2,gd_true_up_mps2,gd_err_up_mps2,g_up_nav_mps2,g_up_true_mps2\n";
  if (sc_.baro_loop_enabled()) {
    const auto& pl = sc_.navigation.baro.poles_radps;
    settle_s_ = 6.0 / std::min({pl[0], pl[1], pl[2]});
  }

  const double t_setup = mono_s();
  if (sc_.navigation.gravity == "model" && sc_.navigation.survey.enable)  // before hal_sim: it may take a while
    survey_grid_ = ggins::truth::make_survey_grid(gen_);                   // (truth field at every node)
  ggins::nav2d_config_t cfg = build_config();
  std::unique_ptr<ggins::hil::Direct<ggins::hil::Task2D>> direct;
  if (opt_.direct) {
    run_id_ = cfg.run_id = ggins::hil::new_run_id();
    direct = std::make_unique<ggins::hil::Direct<ggins::hil::Task2D>>(cfg);
  } else {
    ggins::hil::LinkOptions lo;
    lo.tool = "ggins run";
    lo.hal_sim = opt_.hal_sim;
    lo.prefix = opt_.prefix;
    lo.lcm_url = opt_.lcm_url;
    lo.log_mode = opt_.log_mode;
    lo.logger = opt_.logger;
    lo.resend_timeout_ms = opt_.resend_timeout_ms;
    lo.max_resend = opt_.max_resend;
    lo.batch = opt_.batch;
    lo.window = opt_.window;
    lo.realtime = opt_.realtime;
    lo.deadline_s = 1e-3 * opt_.deadline_ms;
    const auto& tp = sc_.transport;
    lo.faults = {tp.drop_prob, tp.duplicate_prob, tp.reorder_prob, tp.output_drop_prob, tp.garbage_prob, opt_.conflict,
                 tp.seed};
    link_ = std::make_unique<ggins::hil::Link<ggins::hil::Task2D>>(lo, out_, n_, sc_.dt_us());
    run_id_ = link_->run_id();
    link_->start(cfg, fnv1a(sc_.name));
  }
  if (!opt_.quiet) {
    if (link_)
      std::fprintf(stderr, "ggins run: %s, %lld steps at %g Hz (%s), LCM %s (to hal_sim) %s (back), output %s\n",
                   sc_.name.c_str(), static_cast<long long>(n_), rate, opt_.realtime ? "realtime" : "lockstep",
                   link_->url_to_hal().c_str(), link_->url_from_hal().c_str(), out_.c_str());
    else
      std::fprintf(stderr, "ggins run: %s, %lld steps at %g Hz (direct, in process), output %s\n", sc_.name.c_str(),
                   static_cast<long long>(n_), rate, out_.c_str());
  }

  t_start_ = mono_s();
  const double cpu0 = ggins::hil::LinkBase::cpu_s();
  double fw_ns = 0;  // --direct: the firmware steps (cycles[TOTAL])
  const double setup_s = t_start_ - t_setup;
  std::string error;
  int error_code = 0;
  try {
    if (direct) {
      for (int64_t k = 0; k < n_; ++k) {
        const ggins::nav_output_t o = direct->step(make_frame(k));
        fw_ns += static_cast<double>(static_cast<uint32_t>(o.cycles[GG_MOD_TOTAL]));
        consume(o);
        if ((k & 1023) == 0) {
          if (ggins::hil::interrupted()) throw Fail("interrupted", 130);
          progress(false);
        }
      }
    } else {
      link_->run([this](int64_t k) { return make_frame(k); }, [this](const ggins::nav_output_t& m) { consume(m); },
                 [this](int64_t) { progress(false); });
    }
  } catch (const Fail& e) {
    error = e.what();
    error_code = e.code;
  }
  wall_loop_ = mono_s() - t_start_;
  const double cpu_loop = ggins::hil::LinkBase::cpu_s() - cpu0;
  progress(true);
  if (link_ && error_code != 130) link_->finish();
  csv_.close();
  if (link_) link_->close_log();
  // Two different authenticated messages for one seq: the key holder (this
  // process or hal_sim) contradicted itself, or the key is no longer secret.
  // Which of the two copies is right cannot be known, so the run is not
  // completed, whatever its errors look like.
  const json bus = link_ ? link_->bus_auth_summary(link_->outputs_conflict()) : json();
  if (link_ && bus["conflicts_total"].get<int64_t>() > 0 && error.empty()) {
    error = "conflicting authenticated messages (" + bus["conflicts"].dump() +
            "): two different messages for one seq carried a valid MAC; the run cannot be trusted";
    error_code = 1;
  }

  // ---- summary
  json s;
  s["scenario"] = sc_.name;
  s["scenario_source"] = sc_.source;
  s["description"] = sc_.description;
  s["completed"] = error.empty() && outputs_ == n_;
  if (!error.empty()) s["error"] = error;
  s["mode"] = opt_.direct ? "direct" : (opt_.realtime ? "realtime" : "lockstep");
  s["duration_s"] = static_cast<double>(n_ - 1) * static_cast<double>(sc_.dt_us()) * 1e-6;
  s["rate_hz"] = rate;
  s["steps"] = outputs_;
  s["steps_expected"] = n_;
  s["steps_rejected"] = steps_rejected_;
  if (last_out_) {
    // the navigation at the last step received: how it got there (navtask.h)
    s["final_seq"] = last_out_->seq;
    s["recovery"] = {{"resyncs", last_out_->resync_count},
                     {"coast_steps", last_out_->coast_steps},
                     {"final_outage_s", last_out_->outage_s},
                     {"final_state_lag_s", last_out_->state_lag_s}};
  }
  // degraded: flown to the end, but not every frame's readings entered the
  // navigation (frames rejected, or an axis group that lost more readings than
  // parity rebuilds: components held), or the last step's output is missing,
  // or the run ended in an outage (exit status 4)
  s["degraded"] = steps_rejected_ > 0 || !last_out_ || last_out_->seq != n_ - 1 ||
                  last_out_->outage_s != 0.0 || (health_or_ & (GG_HEALTH_ACC_DEGRADED | GG_HEALTH_FORCE_COAST)) != 0;
  s["health_bits_seen"] = health_or_;  // OR of every output's GG_HEALTH_* word
  s["health_seen"] = health_names(health_or_);
  auto axes = [](const std::array<double, 3>& v) { return json{{"x", v[0]}, {"y", v[1]}, {"z", v[2]}}; };
  s["final"] = {{"position_error_m", pos_.final},
                {"velocity_error_mps", vel_.final},
                {"gravity_error_mps2", grav_.final},
                {"gradient_error_max_abs_ps2", gam_.final},
                {"position_error_axes_m", axes(fpos_)},
                {"velocity_error_axes_mps", axes(fvel_)},
                {"gravity_error_axes_mps2", axes(fgrav_)}};
  s["max"] = {{"position_error_m", pos_.max},
              {"velocity_error_mps", vel_.max},
              {"gravity_error_mps2", grav_.max},
              {"gradient_error_max_abs_ps2", gam_.max}};
  s["gravity_error_definition"] = "|G estimated by the firmware - true gravitation at the TRUE position|";
  {  // vertical channel, horizontal errors, gravimeter, barometer
    json v;
    v["definition"] = "h = |r| - r_ref; error = h(nav) - h(true); horizontal = dr less its component along the true up";
    v["r_ref_m"] = sc_.r_ref_m();
    v["baro_loop"] = sc_.baro_loop_enabled();
    v["final_error_m"] = fvert_;
    v["max_abs_error_m"] = vert_.max;
    v["settle_s"] = settle_s_;
    v["rms_error_after_settle_m"] = vert_n_ ? std::sqrt(vert_ss_ / static_cast<double>(vert_n_)) : 0.0;
    v["max_abs_error_after_settle_m"] = vert_max_settled_;
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
    g["rms_error_mps2"] = gravim_n_ ? std::sqrt(gravim_ss_ / static_cast<double>(gravim_n_)) : 0.0;
    g["max_abs_error_mps2"] = gravim_.max;
    g["rms_true_disturbance_mps2"] = gravim_n_ ? std::sqrt(gravim_true_ss_ / static_cast<double>(gravim_n_)) : 0.0;
    g["mean_true_disturbance_mps2"] = gravim_n_ ? gravim_true_sum_ / static_cast<double>(gravim_n_) : 0.0;
    if (gfilt_n_ > 0)  // error against the true disturbance low-passed by the loop (lag removed)
      g["rms_error_vs_loop_filtered_truth_mps2"] = std::sqrt(gfilt_ss_ / static_cast<double>(gfilt_n_));
    g["poles_radps"] = sc_.navigation.baro.poles_radps;
    g["loop_filter"] = "p1 p2 p3 / ((s + p1)(s + p2)(s + p3)), group delay 1/p1 + 1/p2 + 1/p3 = " +
                       std::to_string(1.0 / sc_.navigation.baro.poles_radps[0] + 1.0 / sc_.navigation.baro.poles_radps[1] +
                                      1.0 / sc_.navigation.baro.poles_radps[2]) + " s";
    s["gravimeter"] = g;
    if (!survey_.is_null()) s["survey_grid"] = survey_;
    json hc = json::object();
    for (int b = 0; b < 32; ++b)
      if (health_count_[static_cast<size_t>(b)] > 0) {
        const json nm = health_names(1u << b);
        hc[nm.empty() ? std::to_string(b) : nm[0].get<std::string>()] = health_count_[static_cast<size_t>(b)];
      }
    s["health_counts"] = hc;
    s["baro"] = {{"enabled", sc_.baro.enable},   {"samples_due", baro_due_},      {"dropped", baro_dropped_},
                 {"outliers_sent", baro_outliers_}, {"invalid_sent", baro_invalid_}};
  }
  if (last_out_) {
    const auto& m = *last_out_;
    const Vec3 rn(m.r_i[0], m.r_i[1], m.r_i[2]);
    const Vec3 g_at_nav = gen_.field().eval(rn).g;
    Vec3 d;
    for (int j = 0; j < 3; ++j) d(j) = static_cast<Real>(m.g_i[j]) - g_at_nav(j);
    s["final"]["gravity_error_vs_field_at_estimated_position_mps2"] = static_cast<double>(d.norm());
  }
  // transport
  const auto& hst = link_ ? link_->hal_status() : std::optional<ggins::hal_status_t>();
  const int64_t hal_recovered = hst ? hst->frames_recovered : 0;
  // steps without a navigation output at the end of the run (a frame hal_sim gave
  // up on, or an output that never came back despite resends)
  s["frames_lost"] = n_ - outputs_;
  s["frames_recovered"] = hal_recovered;
  if (link_) {
    json tr = link_->transport_summary();
    tr["truth_published"] = truth_published_;
    s["transport"] = tr;
    s["bus_auth"] = bus;
    if (opt_.realtime) s["realtime"] = link_->realtime_summary();
  }
  s["wall_s"] = wall_loop_;
  s["cpu_s"] = {{"runner", cpu_loop}};  // CPU (user + system) of the flight
  if (link_ && link_->cpu_s_hal_sim() >= 0) s["cpu_s"]["hal_sim"] = link_->cpu_s_hal_sim();
  if (direct) s["cpu_s"]["firmware_steps"] = 1e-9 * fw_ns;
  s["setup_s"] = setup_s;
  // flight time actually navigated (all of it when the run completed) per wall second
  const double flown_s = static_cast<double>(std::max<int64_t>(outputs_ - 1, 0)) * static_cast<double>(sc_.dt_us()) * 1e-6;
  s["realtime_factor"] = wall_loop_ > 0 ? flown_s / wall_loop_ : 0.0;
  s["steps_per_s"] = wall_loop_ > 0 ? static_cast<double>(outputs_) / wall_loop_ : 0.0;
  json ft;
  for (int j = 0; j < GG_MOD_COUNT; ++j) {
    const Percentiles pc = cyc_[j].percentiles();
    json e = {{"median", pc.median}, {"p99", pc.p99}, {"max", pc.max}};
    if (j == GG_MOD_TOTAL) {
      ft["median"] = pc.median;
      ft["p99"] = pc.p99;
      ft["max"] = pc.max;
    }
    ft["modules"][module_name(j)] = e;
  }
  ft["source"] = "gg_nav_output_t.cycles (HAL cycle counter: CLOCK_MONOTONIC ns truncated to uint32)";
  s["firmware_step_ns"] = ft;
  if (link_) {
    s["lcm_url"] = link_->url_to_hal();
    s["lcm_url_from_hal"] = link_->url_from_hal();
  }
  s["channel_prefix"] = opt_.prefix;
  s["run_id"] = run_id_;
  if (link_ && opt_.log_mode != "none") {
    s["log"] = link_->verify_log(ch_truth_, truth_published_);
    s["log"]["writer"] = opt_.log_mode;
  }
  s["files"] = {{"summary", "summary.json"}, {"timeseries", "timeseries.csv"}, {"scenario", "scenario.toml"},
                {"hal_sim_log", "hal_sim.log"}};
  if (link_ && opt_.log_mode != "none") s["files"]["lcm_log"] = "run.lcmlog";
  if (!error.empty()) throw std::make_pair(s, Fail(error, error_code));
  return s;
}

void write_json(const fs::path& p, const json& j) {
  std::ofstream o(p);
  o << j.dump(2) << "\n";
  if (!o) throw Fail("cannot write " + p.string());
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
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
      "  summary.json     final and max position/velocity/gravity error norms, per-axis\n"
      "                   final errors, steps, frames_lost, frames_recovered, wall_s,\n"
      "                   realtime_factor, firmware step time (median/p99/max ns from\n"
      "                   the HAL cycle counter), transport counters, log check\n"
      "  timeseries.csv   truth, navigation and error at --csv-rate (default 1 Hz)\n"
      "  errors.png       position, velocity and gravity error against time (and\n"
      "                   errors_log.png, the norms on a log scale)\n"
      "  vertical.png     vertical error h(nav) - h(true), h = |r| - r_ref, barometer error\n"
      "                   and innovation; gravimeter.png (barometer loop on): the along-track\n"
      "                   vertical gravity disturbance, estimate against truth (summary.json\n"
      "                   \"vertical\", \"horizontal\", \"gravimeter\", \"baro\", \"health_counts\")\n"
      "  run.lcmlog       every message of the run (play with: lcm-logplayer run.lcmlog)\n"
      "  scenario.toml    the scenario as flown; hal_sim.log (its stderr)\n"
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
      "\"degraded\", \"steps_rejected\", \"recovery\"); 130 interrupted.",
      "ggins run"};
  app.get_formatter()->column_width(34);
  bool list = false, print_scenario = false;
  app.add_option("-s,--scenario", o.scenario, "scenario name or .toml path")->capture_default_str();
  app.add_option("-o,--out", o.out, "output folder (default out/<scenario>-<UTC time>)");
  app.add_flag("--realtime", o.realtime, "pace frames at the sensor rate instead of lockstep");
  app.add_flag("--direct", o.direct,
               "step the firmware in this process (no LCM, no hal_sim; hal_sim's message conversions and task\n"
               "cycle, so the same numbers bit for bit): the reference for the transport's cost");
  app.add_option("--batch", o.batch, "lockstep: frames per LCM message (default 32)")->check(CLI::Range(1, 128));
  app.add_option("--window", o.window, "lockstep: frames in flight (default: automatic, from the round trip)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--deadline-ms", o.deadline_ms, "realtime: output latency deadline, ms (default one sensor period)")
      ->check(CLI::PositiveNumber);
  app.add_option("--duration", o.duration_s, "override the scenario's duration, s")->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "override the accelerometer error seed ([accel] seed)");
  app.add_option("--csv-rate", o.csv_rate, "CSV rows per second of flight (default scenario's, 1 Hz)")
      ->check(CLI::PositiveNumber);
  app.add_option("--truth-rate", o.truth_rate, "truth messages per second on LCM (default scenario's, 10), 0 = every step")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--drop-prob", o.drop, "inject: drop each frame transmission with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--dup-prob", o.dup, "inject: send a frame twice with this probability")->check(CLI::Range(0.0, 0.99));
  app.add_option("--reorder-prob", o.reorder, "inject: send frame k+1 before frame k with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--drop-output-prob", o.drop_output, "inject: hal_sim drops each navigation output with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--garbage-prob", o.garbage,
                 "inject: before a frame, an undecodable payload on the frame channel with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--conflict-prob", o.conflict,
                 "inject: after a frame, a second, different frame with the same seq and a valid MAC, with this\n"
                 "probability, and the same for outputs in hal_sim (an authenticated sender contradicting\n"
                 "itself: counted as conflicts, the first copies flown, the run fails)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--resend-timeout-ms", o.resend_timeout_ms, "resend a frame whose output is this late, ms")
      ->capture_default_str()
      ->check(CLI::Range(1, 60000));
  app.add_option("--max-resend", o.max_resend, "give up on a step after this many resends")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--lcm-url", o.lcm_url, "LCM URL (default: udpm on a free port, ttl=0)");
  app.add_option("--prefix", o.prefix, "LCM channel prefix")->capture_default_str();
  app.add_flag("--no-log", o.no_log, "do not record an LCM log (same as --log none; Monte Carlo)");
  app.add_option("--log", o.log_mode,
                 "LCM log writer: internal (this process records every message it sends and receives;\n"
                 "lossless), lcm-logger (separate process; may drop under load, checked in summary.json\n"
                 "log.complete), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"internal", "lcm-logger", "none"}));
  app.add_flag("--no-plots", o.no_plots, "do not make PNG plots");
  app.add_flag("-q,--quiet", o.quiet, "no progress, only errors and the output folder");
  app.add_option("--progress", o.progress, "progress display: auto (line on a terminal, every 10% otherwise), on, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app.add_option("--hal-sim", o.hal_sim, "hal_sim executable (default: beside ggins-run)");
  app.add_option("--python", o.python, "Python with matplotlib for the plots")->capture_default_str();
  app.add_option("--logger", o.logger, "lcm-logger executable")->capture_default_str();
  app.add_flag("--list-scenarios", list, "list the built-in scenarios and exit");
  app.add_flag("--print-scenario", print_scenario, "print the resolved scenario and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (list) {
    for (const auto& n : ggins::truth::builtin_scenario_names()) {
      auto s = ggins::truth::load_scenario(n, {GGINS_SCENARIO_DIR});
      std::printf("%-20s %s\n", n.c_str(), s.description.c_str());
    }
    return 0;
  }
  ggins::truth::Scenario sc;
  try {
    sc = ggins::truth::load_scenario(o.scenario, {GGINS_SCENARIO_DIR});
    if (o.duration_s) sc.duration_s = *o.duration_s;
    if (o.seed) sc.accel.seed = *o.seed;
    if (o.csv_rate) sc.output.csv_rate_hz = *o.csv_rate;
    if (o.truth_rate) sc.output.truth_rate_hz = *o.truth_rate;
    if (o.drop) sc.transport.drop_prob = *o.drop;
    if (o.dup) sc.transport.duplicate_prob = *o.dup;
    if (o.reorder) sc.transport.reorder_prob = *o.reorder;
    if (o.drop_output) sc.transport.output_drop_prob = *o.drop_output;
    if (o.garbage) sc.transport.garbage_prob = *o.garbage;
    if (sc.n_steps() < 2) throw std::runtime_error("the scenario needs at least two steps");
    if (sc.n_steps() > 100000000)
      throw std::runtime_error("more than 1e8 steps in one run (" + std::to_string(sc.n_steps()) +
                               "): shorten the duration or lower the rate");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins run: %s\n", e.what());
    return 2;
  }
  if (o.no_log) o.log_mode = "none";
  if (print_scenario) {
    std::printf("# %s\n%s", sc.source.c_str(), sc.text.c_str());
    return 0;
  }
  if (o.direct && o.realtime) {
    std::fprintf(stderr, "ggins run: --direct and --realtime exclude each other\n");
    return 2;
  }
  if (o.hal_sim.empty()) o.hal_sim = (ggins::hil::self_dir() / "hal_sim").string();
  if (!o.direct && access(o.hal_sim.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "ggins run: hal_sim not found at %s (build it, or give --hal-sim)\n", o.hal_sim.c_str());
    return 2;
  }
  std::error_code ec;
  fs::path out = ggins::hil::create_output_dir(o.out, sc.name, ec);
  if (ec) {
    std::fprintf(stderr, "ggins run: cannot create %s: %s\n", out.c_str(), ec.message().c_str());
    return 2;
  }
  out = fs::absolute(out);
  {
    std::ofstream f(out / "scenario.toml");
    f << "# scenario " << sc.name << " from " << sc.source << "\n";
    f << "# effective after command-line overrides: duration_s = " << sc.duration_s << ", accel.seed = " << sc.accel.seed
      << ", csv_rate_hz = " << sc.output.csv_rate_hz << ", truth_rate_hz = " << sc.output.truth_rate_hz
      << ", drop/dup/reorder/output-drop = " << sc.transport.drop_prob << "/" << sc.transport.duplicate_prob << "/"
      << sc.transport.reorder_prob << "/" << sc.transport.output_drop_prob << "\n"
      << sc.text;
  }
  ggins::hil::install_interrupt_handlers();

  json summary;
  int rc = 0;
  try {
    Runner r(o, sc, out);
    summary = r.run();
  } catch (std::pair<json, Fail>& e) {
    summary = e.first;
    std::fprintf(stderr, "ggins run: %s\n", e.second.what());
    rc = e.second.code == 3 ? 3 : (e.second.code == 130 ? 130 : 1);
  } catch (const Fail& e) {
    std::fprintf(stderr, "ggins run: %s\n", e.what());
    rc = e.code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins run: %s\n", e.what());
    rc = 1;
  }
  if (summary.is_null()) return rc ? rc : 1;
  summary["output_dir"] = out.string();
  write_json(out / "summary.json", summary);

  if (!o.no_plots) {
    const std::string script = GGINS_PLOT_SCRIPT;
    if (o.python.empty()) {
      std::fprintf(stderr, "ggins run: no Python with matplotlib was found at build time; plots skipped (--python)\n");
    } else {
      int st = -1;
      try {
        const pid_t pid = spawn({o.python, script, out.string()}, out / "plot.log");
        st = wait_child(pid, 300.0);
      } catch (const Fail&) {
      }
      if (st != 0) std::fprintf(stderr, "ggins run: plotting failed; see %s\n", (out / "plot.log").c_str());
    }
  }
  if (!o.quiet) {
    const auto& f = summary["final"];
    std::printf("ggins run: %s %s: %lld steps, final |dr| = %.3e m, |dv| = %.3e m/s, |dG| = %.3e m/s^2\n",
                summary["scenario"].get<std::string>().c_str(), !summary["completed"].get<bool>() ? "FAILED" : (summary.value("degraded", false) ? "completed, DEGRADED" : "completed"),
                static_cast<long long>(summary["steps"].get<int64_t>()), f["position_error_m"].get<double>(),
                f["velocity_error_mps"].get<double>(), f["gravity_error_mps2"].get<double>());
    std::printf("  frames lost %lld, recovered %lld; wall %.2f s, real-time factor %.1f; step %.0f ns median, %.0f p99, %.0f max\n",
                static_cast<long long>(summary["frames_lost"].get<int64_t>()),
                static_cast<long long>(summary["frames_recovered"].get<int64_t>()), summary["wall_s"].get<double>(),
                summary["realtime_factor"].get<double>(), summary["firmware_step_ns"]["median"].get<double>(),
                summary["firmware_step_ns"]["p99"].get<double>(), summary["firmware_step_ns"]["max"].get<double>());
  }
  if (summary.contains("bus_auth") && summary["bus_auth"]["rejected_total"].get<int64_t>() > 0)
    std::fprintf(stderr, "%s: %lld messages without a valid MAC were dropped (someone without the key published on the "
                 "run's channels): %s\n", "ggins run", static_cast<long long>(summary["bus_auth"]["rejected_total"].get<int64_t>()),
                 summary["bus_auth"]["rejected_unauthenticated"].dump().c_str());
  std::printf("report: %s\n", out.c_str());
  if (rc == 0 && !summary["completed"].get<bool>()) rc = 1;
  if (rc == 0 && summary.value("degraded", false)) rc = 4;
  return rc;
}
