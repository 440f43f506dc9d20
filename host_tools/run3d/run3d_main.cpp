// ggins run3d (ggins-run3d): fly one 3-D scenario (scenarios/3d-*.toml,
// host_tools/truth3d) against the 3-D firmware (nav3d.h), host-in-the-loop
// over LCM through hal_sim (default) or in process (--direct), and write
// summary.json, timeseries.csv, errors.png, run.lcmlog.
//
// LCM protocol (hal_sim in 3-D mode, see hal_sim --help): nav3d_config_t on
// P+CONFIG3D until hal_sim reports CONFIGURED, START on P+CONTROL, then the
// shared transport (hil_common/link.hpp): frame batches on P+FRAMES, output
// batches (nav3d_output_batch_t) on P+NAV3DS, negative acknowledgements on
// P+NAK, truth3d_t on P+TRUTH3D (decimated), STOP.
#include <lcm/lcm.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compare3d.hpp"
#include "config3d.hpp"
#include "ggins/hal_status_t.hpp"
#include "ggins/nav3d_config_t.hpp"
#include "ggins/nav3d_output_t.hpp"
#include "ggins/run_control_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth3d_t.hpp"
#include "direct.hpp"
#include "hil_common.hpp"
#include "link.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;
using ggins::truth3d::Real;
using ggins::truth3d::Vec3;
using ggins::truth3d::Mat3;
using ggins::hil::Fail;
using ggins::hil::free_udp_ports;
using ggins::hil::hilo;
using ggins::hil::mono_s;
using ggins::hil::spawn;
using ggins::hil::stop_child;
using ggins::hil::wait_child;
using ggins::hil::wall_us;

namespace {

struct Options {
  std::string scenario = "3d-stabilized-1h";
  std::string out;
  std::optional<double> duration_s, csv_rate;
  double truth_rate = 10;
  bool direct = false, no_log = false, no_plots = false, quiet = false;
  std::string lcm_url, prefix = "GGINS_";
  int resend_timeout_ms = 50, max_resend = 100;
  std::string hal_sim, python = GGINS_PLOT_PYTHON;
  bool realtime = false;
  int batch = 0, window = 0;
  double deadline_ms = 0;
  ggins::hil::Faults faults;
};

struct MaxFinal {
  double max = 0, final = 0;
  void add(double v) {
    final = v;
    max = std::max(max, std::fabs(v));
  }
  json j() const { return {{"final", final}, {"max", max}}; }
};

class Runner3 {
 public:
  Runner3(const Options& o, const ggins::truth3d::Scenario3& sc, fs::path out)
      : opt_(o), sc_(sc), gen_(sc), out_(std::move(out)) {}
  json run();

 private:
  ggins::sensor_frame_t make_frame(int64_t k);
  ggins::nav3d_config_t build_config();
  void on_output(const ggins::nav3d_output_t& m);
  void consume(int64_t k, const ggins::truth3d::Truth3& t, const gg_nav3d_output_t& o, double step_ns);
  static void from_lcm(const ggins::nav3d_output_t& m, gg_nav3d_output_t& o);

  const Options& opt_;
  ggins::truth3d::Scenario3 sc_;
  ggins::truth3d::Generator3 gen_;
  fs::path out_;
  std::unique_ptr<ggins::hil::Link<ggins::hil::Task3D>> link_;  // over LCM (none with --direct)
  int64_t run_id_ = 0;
  std::string ch_truth_;
  int64_t n_ = 0, csv_every_ = 1, truth_every_ = 1, truth_published_ = 0, outputs_ = 0;
  int64_t aid_closed_ = 0;           // map-aid epochs closed (updated or rejected)
  double aid_nis_sum_ = 0;           // sum of their NIS
  ggins::nav3d_output_t aid_last_{};  // the output of the last step (the aid's counters)
  static constexpr int64_t kTruthRing = 8192;  // > the transport's largest window (4096)
  std::vector<ggins::truth3d::Truth3> truth_ring_;
  // statistics
  MaxFinal pos_, vel_, att_, grav_, gam_e_, gam_b_, hgt_, par_asym_, par_trace_, wdot_;
  std::array<double, 3> fpos_n_{}, fatt_n_{}, fg_n_{};
  int64_t rejected_ = 0;
  uint32_t health_or_ = 0;
  std::vector<double> step_ns_;
  std::ofstream csv_;
};

void Runner3::from_lcm(const ggins::nav3d_output_t& m, gg_nav3d_output_t& o) {
  std::memset(&o, 0, sizeof o);
  o.utime = m.utime;
  o.seq = m.seq;
  o.status = m.status;
  o.health = static_cast<uint32_t>(m.health);
  for (int i = 0; i < 3; ++i) {
    o.r_e[i] = m.r_e[i];
    o.r_e_lo[i] = m.r_e_lo[i];
    o.v_e[i] = m.v_e[i];
    o.v_n[i] = m.v_n[i];
    o.g_e[i] = m.g_e[i];
    o.g_e_lo[i] = m.g_e_lo[i];
    o.f_b[i] = m.f_b[i];
    o.rpy_rad[i] = m.rpy_rad[i];
    o.omega_b[i] = m.omega_b[i];
    o.omega_dot_b[i] = m.omega_dot_b[i];
    for (int j = 0; j < 3; ++j) {
      o.gamma_e[i][j] = m.gamma_e[i][j];
      o.gamma_b[i][j] = m.gamma_b[i][j];
    }
  }
  for (int i = 0; i < 4; ++i) {
    o.q_b_e[i] = m.q_b_e[i];
    o.parity[i] = m.parity[i];
  }
  o.lat_rad = m.lat_rad;
  o.lon_rad = m.lon_rad;
  o.h_m = m.h_m;
  o.h_ins_m = m.h_ins_m;
  o.baro_innov_m = m.baro_innov_m;
  o.g_up_corr = m.g_up_corr;
  o.t_s = m.t_s;
  for (int i = 0; i < GG_MOD_COUNT && i < m.n_cycles && i < 8; ++i) o.cycles[i] = static_cast<uint32_t>(m.cycles[i]);
}

void Runner3::on_output(const ggins::nav3d_output_t& m) {
  ++outputs_;
  if (m.mm_updates + m.mm_rejected > aid_closed_) {  // a map-aid epoch finished: its NIS
    aid_closed_ = m.mm_updates + m.mm_rejected;
    aid_nis_sum_ += m.mm_nis;
  }
  if (m.seq == n_ - 1) aid_last_ = m;
  gg_nav3d_output_t o;
  from_lcm(m, o);
  consume(m.seq, truth_ring_[static_cast<size_t>(m.seq % kTruthRing)], o, static_cast<double>(o.cycles[GG_MOD_TOTAL]));
}

ggins::sensor_frame_t Runner3::make_frame(int64_t k) {
  gg_frame_t f;
  ggins::truth3d::Truth3 t;
  gen_.frame(k, f, &t);
  const ggins::sensor_frame_t m = ggins::hil::sensor_frame_msg(f, run_id_, 0);
  if (link_ && (k % truth_every_ == 0 || k == n_ - 1)) {
    ggins::truth3d_t tm{};
    tm.utime = t.utime;
    tm.seq = k;
    tm.run_id = run_id_;
    tm.t_s = static_cast<double>(t.t_s);
    const auto q = ggins::truth3d::quat_from_dcm(t.s.C_b_e);
    for (int j = 0; j < 3; ++j) {
      hilo(t.s.r_e(j), tm.r_e_hi[j], tm.r_e_lo[j]);
      hilo(t.s.r_i(j), tm.r_i_hi[j], tm.r_i_lo[j]);
      hilo(t.g_e(j), tm.g_e_hi[j], tm.g_e_lo[j]);
      tm.v_e[j] = static_cast<double>(t.s.v_e(j));
      tm.a_e[j] = static_cast<double>(t.s.a_e(j));
      tm.v_i[j] = static_cast<double>(t.s.v_i(j));
      tm.a_i[j] = static_cast<double>(t.s.a_i(j));
      tm.omega_b[j] = static_cast<double>(t.s.omega_b(j));
      tm.omega_dot_b[j] = static_cast<double>(t.s.omega_dot_b(j));
      tm.f_b[j] = static_cast<double>(t.f_b(j));
      for (int i = 0; i < 3; ++i) {
        tm.gamma_e[j][i] = static_cast<double>(t.gamma_e(j, i));
        tm.gamma_b[j][i] = static_cast<double>(t.gamma_b(j, i));
      }
    }
    for (int j = 0; j < 4; ++j) tm.q_b_e[j] = static_cast<double>(q[static_cast<size_t>(j)]);
    tm.rpy_rad[0] = static_cast<double>(t.s.roll);
    tm.rpy_rad[1] = static_cast<double>(t.s.pitch);
    tm.rpy_rad[2] = static_cast<double>(t.s.yaw);
    tm.lat_rad = static_cast<double>(t.s.lat);
    tm.lon_rad = static_cast<double>(t.s.lon);
    tm.h_m = static_cast<double>(t.s.h);
    link_->publish(ch_truth_, tm);
    ++truth_published_;
  }
  truth_ring_[static_cast<size_t>(k % kTruthRing)] = t;
  return m;
}

ggins::nav3d_config_t Runner3::build_config() {
  gg_nav3d_config_t c;
  ggins::truth3d::nav3d_config(sc_, gen_, c);
  ggins::nav3d_config_t m{};
  m.utime = wall_us();
  m.seq = 0;
  std::memcpy(m.scenario, sc_.name.data(), std::min<size_t>(sc_.name.size(), 63));
  for (int i = 0; i < 3; ++i) {
    m.half_base_m[i] = static_cast<double>(c.geometry.half_base_m[i]);
    hilo(c.r0_e[i], m.r0_hi[i], m.r0_lo[i]);
    hilo(c.v0_e[i], m.v0_hi[i], m.v0_lo[i]);
    hilo(c.g0_e[i], m.g0_hi[i], m.g0_lo[i]);
    m.baro_poles[i] = static_cast<double>(c.baro.poles[i]);
  }
  for (int i = 0; i < 4; ++i) hilo(c.q0_b_e[i], m.q0_hi[i], m.q0_lo[i]);
  m.platform = c.platform;
  m.dt_us = c.dt_us;
  m.dt_tol_us = c.dt_tol_us;
  hilo(c.omega_ie, m.omega_ie_hi, m.omega_ie_lo);
  m.f_max = c.f_max;
  m.asym_max = c.asym_max;
  m.fdi_parity_f_max = c.fdi_parity_f_max;
  m.gravity_mode = static_cast<int8_t>(c.gravity_mode);
  hilo(c.model.gm, m.model_gm_hi, m.model_gm_lo);
  m.model_a_m = static_cast<double>(c.model.a_m);
  for (int n = 0; n < 9 && n <= GG_GMODEL_MAX_DEGREE; ++n) m.model_j[n] = static_cast<double>(c.model.j[n]);
  m.baro_enable = static_cast<int8_t>(c.baro_enable);
  m.baro_omega_s2 = static_cast<double>(c.baro.omega_s2);
  m.baro_period_us = c.baro.period_us;
  m.baro_max_age_us = c.baro.max_age_us;
  m.baro_coast_us = c.baro.coast_us;
  m.baro_alt_min_m = c.baro.alt_min_m;
  m.baro_alt_max_m = c.baro.alt_max_m;
  m.baro_gate_m = c.baro.gate_m;
  m.baro_max_rejects = c.baro.max_rejects;
  m.aid_mm_enable = static_cast<int8_t>(c.aid_mm.enable);  // the map aid (aids3d.hpp)
  m.aid_mm_update_steps = c.aid_mm.update_steps;
  m.aid_mm_max_passes = c.aid_mm.max_passes;
  m.aid_mm_sigma_meas_s2 = c.aid_mm.sigma_meas_s2;
  m.aid_mm_sigma_db_s2 = c.aid_mm.sigma_db_s2;
  m.aid_mm_offdiag_ratio = c.aid_mm.offdiag_ratio;
  m.aid_mm_sig0_pos_m = c.aid_mm.sig0_pos_m;
  m.aid_mm_sig0_vel_mps = c.aid_mm.sig0_vel_mps;
  m.aid_mm_sig0_att_rad = c.aid_mm.sig0_att_rad;
  m.aid_mm_sig0_g_mps2 = c.aid_mm.sig0_g_mps2;
  m.aid_mm_q_vel_mps_rts = c.aid_mm.q_vel_mps_rts;
  m.aid_mm_q_att_rad_rts = c.aid_mm.q_att_rad_rts;
  m.aid_mm_q_g_mps2_rts = c.aid_mm.q_g_mps2_rts;
  m.aid_mm_lambda = c.aid_mm.lambda;
  m.aid_mm_gate_nis = c.aid_mm.gate_nis;
  return m;
}

void Runner3::consume(int64_t k, const ggins::truth3d::Truth3& t, const gg_nav3d_output_t& o, double step_ns) {
  const ggins::run3d::Errors3 e = ggins::run3d::compare(t, o);
  if (o.status != GG_OK) ++rejected_;
  health_or_ |= o.health;
  step_ns_.push_back(step_ns);
  pos_.add(static_cast<double>(e.dr));
  vel_.add(static_cast<double>(e.dv));
  att_.add(static_cast<double>(e.psi));
  grav_.add(static_cast<double>(e.dg));
  hgt_.add(static_cast<double>(e.dh));
  if (k > 0) {  // the first output may carry no gradient yet
    gam_e_.add(static_cast<double>(e.dgamma_e));
    gam_b_.add(static_cast<double>(e.dgamma_b));
    par_asym_.add(std::sqrt(o.parity[0] * o.parity[0] + o.parity[1] * o.parity[1] + o.parity[2] * o.parity[2]));
    par_trace_.add(o.parity[3]);
    const Vec3 wd(o.omega_dot_b[0], o.omega_dot_b[1], o.omega_dot_b[2]);
    wdot_.add(static_cast<double>((wd - t.s.omega_dot_b).norm()));
  }
  for (int i = 0; i < 3; ++i) {
    fpos_n_[static_cast<size_t>(i)] = static_cast<double>(e.dr_n(i));
    fatt_n_[static_cast<size_t>(i)] = static_cast<double>(e.psi_n(i));
    fg_n_[static_cast<size_t>(i)] = static_cast<double>(e.dg_n(i));
  }
  if (k % csv_every_ == 0 || k == n_ - 1) {
    const double deg = 180.0 / M_PI;
    char line[1024];
    std::snprintf(line, sizeof line,
                  "%.6f,%lld,%.10f,%.10f,%.4f,%.6f,%.6f,%.6f,%.4f,%.10f,%.10f,%.4f,"
                  "%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,"
                  "%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%d,%u\n",
                  static_cast<double>(t.t_s), static_cast<long long>(k), static_cast<double>(t.s.lat) * deg,
                  static_cast<double>(t.s.lon) * deg, static_cast<double>(t.s.h), static_cast<double>(t.s.roll) * deg,
                  static_cast<double>(t.s.pitch) * deg, static_cast<double>(t.s.yaw) * deg, static_cast<double>(t.s.v_e.norm()),
                  o.lat_rad * deg, o.lon_rad * deg, o.h_m, static_cast<double>(e.dr_n(0)), static_cast<double>(e.dr_n(1)),
                  static_cast<double>(e.dr_n(2)), static_cast<double>(e.dr), static_cast<double>(e.dv_n(0)),
                  static_cast<double>(e.dv_n(1)), static_cast<double>(e.dv_n(2)), static_cast<double>(e.dv),
                  static_cast<double>(e.psi_n(0)), static_cast<double>(e.psi_n(1)), static_cast<double>(e.psi_n(2)),
                  static_cast<double>(e.psi), static_cast<double>(e.dg_n(0)), static_cast<double>(e.dg_n(1)),
                  static_cast<double>(e.dg_n(2)), static_cast<double>(e.dg), static_cast<double>(e.dgamma_e) * 1e9,
                  static_cast<double>(e.dgamma_b) * 1e9, static_cast<double>(e.dh), o.parity[0], o.parity[1], o.parity[2],
                  o.parity[3], o.baro_innov_m, o.g_up_corr, o.status, o.health);
    csv_ << line;
  }
}


json Runner3::run() {
  n_ = gen_.n_steps();
  truth_ring_.resize(static_cast<size_t>(kTruthRing));
  csv_every_ = std::max<int64_t>(1, std::llround(sc_.rate_hz / (opt_.csv_rate ? *opt_.csv_rate : sc_.csv_rate_hz)));
  truth_every_ = opt_.truth_rate > 0 ? std::max<int64_t>(1, std::llround(sc_.rate_hz / opt_.truth_rate)) : 1;
  ch_truth_ = opt_.prefix + "TRUTH3D";
  csv_.open(out_ / "timeseries.csv");
  if (!csv_) throw Fail("cannot write " + (out_ / "timeseries.csv").string());
  csv_ << "t_s,seq,lat_deg,lon_deg,h_m,roll_deg,pitch_deg,yaw_deg,speed_mps,nav_lat_deg,nav_lon_deg,nav_h_m,"
          "err_n_m,err_e_m,err_d_m,err_r_m,err_vn_mps,err_ve_mps,err_vd_mps,err_v_mps,"
          "att_err_n_rad,att_err_e_rad,att_err_d_rad,att_err_rad,err_gn_mps2,err_ge_mps2,err_gd_mps2,err_g_mps2,"
          "err_gamma_e_E,err_gamma_b_E,err_h_m,parity_x,parity_y,parity_z,parity_trace,baro_innov_m,a_c_mps2,status,"
          "health\n";
  const ggins::nav3d_config_t cfg = build_config();
  const auto& aid = sc_.aid_ukf;
  std::vector<std::string> maps;  // the onboard map tiles of the map aid: the computer's map storage
  if (aid.enabled)
    for (const auto& p : ggins::run3d::aid_ukf_map_paths(aid, sc_.source)) maps.push_back(fs::absolute(p).string());
  std::unique_ptr<ggins::hil::Direct<ggins::hil::Task3D>> direct;
  if (opt_.direct) {
    run_id_ = ggins::hil::new_run_id();
    direct = std::make_unique<ggins::hil::Direct<ggins::hil::Task3D>>(cfg);
    for (const auto& p : maps) direct->add_map(p);
  } else {
    ggins::hil::LinkOptions lo;
    lo.tool = "ggins run3d";
    lo.hal_sim = opt_.hal_sim;
    lo.prefix = opt_.prefix;
    lo.lcm_url = opt_.lcm_url;
    lo.log_mode = opt_.no_log ? "none" : "internal";
    lo.resend_timeout_ms = opt_.resend_timeout_ms;
    lo.max_resend = opt_.max_resend;
    lo.batch = opt_.batch;
    lo.window = opt_.window;
    lo.realtime = opt_.realtime;
    lo.deadline_s = 1e-3 * opt_.deadline_ms;
    lo.faults = opt_.faults;
    for (const auto& p : maps) lo.hal_args.insert(lo.hal_args.end(), {"--map", p});
    link_ = std::make_unique<ggins::hil::Link<ggins::hil::Task3D>>(lo, out_, n_, gen_.dt_us());
    run_id_ = link_->run_id();
    link_->start(cfg, 0);
  }
  const double t0 = mono_s();
  const double cpu0 = ggins::hil::LinkBase::cpu_s();
  double fw_ns = 0;  // --direct: the firmware steps (cycles[TOTAL])
  auto progress = [&](int64_t k) {
    static int64_t last = -1;
    const int64_t tenth = std::max<int64_t>(1, n_ / 10);
    if (!opt_.quiet && k / tenth > last && k > 0) {
      last = k / tenth;
      std::fprintf(stderr, "ggins run3d: t = %.0f / %.0f s  |dr| %.3g m\n", static_cast<double>(gen_.time_of(k)),
                   sc_.duration_s, pos_.final);
    }
  };
  std::string error;
  int error_code = 0;
  try {
    if (direct) {
      for (int64_t k = 0; k < n_; ++k) {
        ggins::sensor_frame_t m = make_frame(k);
        m.run_id = run_id_;
        const ggins::nav3d_output_t o = direct->step(m);
        fw_ns += static_cast<double>(static_cast<uint32_t>(o.cycles[GG_MOD_TOTAL]));
        on_output(o);
        if ((k & 1023) == 0) {
          if (ggins::hil::interrupted()) throw Fail("interrupted", 130);
          progress(k);
        }
      }
    } else {
      link_->run([this](int64_t k) { return make_frame(k); }, [this](const ggins::nav3d_output_t& m) { on_output(m); },
                 progress);
    }
  } catch (const Fail& e) {
    error = e.what();
    error_code = e.code;
  }
  const double wall = mono_s() - t0;  // the flight (not the STOP handshake)
  const double cpu_loop = ggins::hil::LinkBase::cpu_s() - cpu0;
  if (link_ && error_code != 130) link_->finish();
  if (link_) link_->close_log();
  if (error_code != 0) throw Fail(error, error_code);
  csv_.close();
  std::vector<double> s = step_ns_;
  std::sort(s.begin(), s.end());
  auto pct = [&](double q) { return s.empty() ? 0.0 : s[static_cast<size_t>(q * static_cast<double>(s.size() - 1))]; };
  json j;
  j["scenario"] = sc_.name;
  j["description"] = sc_.description;
  j["platform"] = sc_.platform;
  j["trajectory"] = sc_.trajectory.type;
  j["gravity_model"] = sc_.gravity.model;
  j["navigation_gravity"] = sc_.nav_gravity;
  j["baro_loop"] = sc_.baro_loop_enabled();
  j["mode"] = opt_.direct ? "direct (in process, no LCM)"
                          : (opt_.realtime ? "host-in-the-loop over LCM (hal_sim), real time"
                                           : "host-in-the-loop over LCM (hal_sim), batched lockstep");
  j["duration_s"] = sc_.duration_s;
  j["rate_hz"] = sc_.rate_hz;
  j["steps"] = n_;
  j["outputs"] = outputs_;
  j["run_id"] = run_id_;
  j["steps_rejected"] = rejected_;
  j["health_or"] = health_or_;
  j["position_error_m"] = pos_.j();
  if (aid.enabled) {  // the map aid's counters at the last step
    json a;
    a["epochs"] = aid_last_.mm_epochs;
    a["updates"] = aid_last_.mm_updates;
    a["rejected"] = aid_last_.mm_rejected;
    a["no_map"] = aid_last_.mm_no_map;
    a["nis_mean"] = aid_closed_ > 0 ? aid_nis_sum_ / static_cast<double>(aid_closed_) : 0.0;
    a["nis_dof"] = 6;
    a["sigma_pos_m"] = {aid_last_.mm_sigma[0], aid_last_.mm_sigma[1], aid_last_.mm_sigma[2]};
    a["tiles"] = maps.size();
    j["aid_ukf"] = a;
  } else {
    j["aid_ukf"] = "off";
  }
  j["position_error_final_ned_m"] = fpos_n_;
  j["velocity_error_mps"] = vel_.j();
  j["height_error_m"] = hgt_.j();
  j["attitude_error_rad"] = att_.j();
  j["attitude_error_final_ned_rad"] = fatt_n_;
  j["gravity_error_mps2"] = grav_.j();
  j["gravity_error_final_ned_mps2"] = fg_n_;
  j["gamma_error_ecef_E"] = {{"final", gam_e_.final * 1e9}, {"max", gam_e_.max * 1e9}};
  j["gamma_error_body_E"] = {{"final", gam_b_.final * 1e9}, {"max", gam_b_.max * 1e9}};
  j["omega_dot_error_radps2"] = wdot_.j();
  j["parity_antisym_radps2"] = par_asym_.j();
  j["parity_trace_ps2"] = par_trace_.j();
  j["acceptance"] = {{"position_below_1cm", pos_.max < 0.01}, {"gamma_below_1e-4_E", gam_e_.max * 1e9 < 1e-4}};
  j["wall_s"] = wall;
  j["cpu_s"] = {{"runner", cpu_loop}};  // CPU (user + system) of the flight
  if (link_ && link_->cpu_s_hal_sim() >= 0) j["cpu_s"]["hal_sim"] = link_->cpu_s_hal_sim();
  if (direct) j["cpu_s"]["firmware_steps"] = 1e-9 * fw_ns;
  j["realtime_factor"] = wall > 0 ? sc_.duration_s / wall : 0.0;
  j["step_ns"] = {{"median", pct(0.5)}, {"p99", pct(0.99)}, {"max", s.empty() ? 0.0 : s.back()}};
  if (link_) {
    json tr = link_->transport_summary();
    tr["truth_published"] = truth_published_;
    j["transport"] = tr;
    j["hal_sim"] = link_->hal_sim_summary();
    j["bus_auth"] = link_->bus_auth_summary(link_->outputs_conflict());
    if (opt_.realtime) j["realtime"] = link_->realtime_summary();
    // two different authenticated messages for one seq: which copy was right
    // cannot be known, so the run is not completed (exit 1)
    j["completed"] = j["bus_auth"]["conflicts_total"].get<int64_t>() == 0 && outputs_ == n_;
    j["lcm_log"] = opt_.no_log ? "" : (out_ / "run.lcmlog").string();
    j["lcm_url"] = link_->url_to_hal();
    j["lcm_url_from_hal"] = link_->url_from_hal();
    if (!opt_.no_log) j["log"] = link_->verify_log(ch_truth_, truth_published_);
  }
  if (!link_) j["completed"] = outputs_ == n_;
  // degraded: flown to the end, but not every frame's readings entered the navigation (frames
  // rejected, axis groups degraded), the last step's output missing, or an outage at the end
  const bool last_ok = outputs_ > 0 && aid_last_.seq == n_ - 1;
  j["degraded"] = rejected_ > 0 || outputs_ != n_ || !last_ok || (last_ok && aid_last_.outage_s != 0.0) ||
                  (health_or_ & (GG_HEALTH_ACC_DEGRADED | GG_HEALTH_FORCE_COAST)) != 0;
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bool list = false, print_scenario = false;
  CLI::App app{
      "ggins run3d: fly one 3-D scenario (six tri-axis accelerometers, rotating WGS-84 Earth,\n"
      "stabilized or strapdown platform) against the 3-D firmware (nav3d.h).\n\n"
      "The 3-D truth generator (host_tools/truth3d, this process) evaluates the scenario's\n"
      "analytic trajectory on Taylor jets (r, v, a, attitude, body rate and its derivative\n"
      "mutually exact), each accelerometer's f = C_i_b (a_j - G(r_j)) with the field at the\n"
      "sensor, the gyro rate and the barometer, and sends sensor frames; hal_sim (own process,\n"
      "3-D mode) steps gg_nav3d once per frame in lockstep over LCM. --direct steps the\n"
      "firmware in this process instead (no LCM; same numbers).\n\n"
      "Writes to the output folder (default out/<scenario>-<UTC>/):\n"
      "  summary.json     final and max position (NED), velocity, attitude, gravity and gradient\n"
      "                   (Eotvos) errors, parity, step time, transport counters, acceptance\n"
      "  timeseries.csv   truth, navigation and errors at --csv-rate\n"
      "  errors.png       position error N/E/D, attitude error, G error, Gamma error vs time\n"
      "  run.lcmlog       every LCM message of the run (not with --direct or --no-log)\n"
      "  scenario.toml, hal_sim.log\n"};
  app.add_option("-s,--scenario", o.scenario, "3-D scenario: built-in name (--list-scenarios) or TOML path")
      ->capture_default_str();
  app.add_option("-o,--out", o.out, "output folder");
  app.add_option("--duration", o.duration_s, "override the scenario duration, s");
  app.add_option("--csv-rate", o.csv_rate, "CSV rows per second (default: scenario, 1)");
  app.add_option("--truth-rate", o.truth_rate, "truth3d_t messages per second on LCM (0: every step)")
      ->capture_default_str();
  app.add_flag("--direct", o.direct,
               "step the firmware in this process (no LCM, no hal_sim; hal_sim's message conversions and task\n"
               "cycle, so the same numbers bit for bit)");
  app.add_flag("--realtime", o.realtime, "pace frames at the sensor rate instead of lockstep");
  app.add_option("--batch", o.batch, "lockstep: frames per LCM message (default 32)")->check(CLI::Range(1, 128));
  app.add_option("--window", o.window, "lockstep: frames in flight (default: automatic, from the round trip)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--deadline-ms", o.deadline_ms, "realtime: output latency deadline, ms (default one sensor period)")
      ->check(CLI::PositiveNumber);
  app.add_option("--drop-prob", o.faults.drop, "inject: drop each frame transmission with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--dup-prob", o.faults.dup, "inject: send a frame twice with this probability")->check(CLI::Range(0.0, 0.99));
  app.add_option("--reorder-prob", o.faults.reorder, "inject: send frame k+1 before frame k with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--drop-output-prob", o.faults.drop_output, "inject: hal_sim drops each navigation output with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--garbage-prob", o.faults.garbage,
                 "inject: before a frame, an undecodable payload on the frame channel with this probability")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--conflict-prob", o.faults.conflict,
                 "inject: a second, different, signed frame for a seq (and output in hal_sim) with this probability\n"
                 "(counted as conflicts, the first copies flown, the run fails)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--fault-seed", o.faults.seed, "seed of the transport fault injection")->capture_default_str();
  app.add_flag("--no-log", o.no_log, "do not record run.lcmlog");
  app.add_flag("--no-plots", o.no_plots, "do not make errors.png");
  app.add_flag("-q,--quiet", o.quiet, "no progress lines");
  app.add_option("--lcm-url", o.lcm_url, "one LCM URL for both directions (default: two private udpm ports)");
  app.add_option("--prefix", o.prefix, "LCM channel prefix")->capture_default_str();
  app.add_option("--resend-timeout-ms", o.resend_timeout_ms, "resend a frame without output after MS ms")
      ->capture_default_str();
  app.add_option("--max-resend", o.max_resend, "resends of one frame before giving up")->capture_default_str();
  app.add_option("--hal-sim", o.hal_sim, "hal_sim executable (default: beside ggins-run3d)");
  app.add_option("--python", o.python, "Python with matplotlib for the plots")->capture_default_str();
  app.add_flag("--list-scenarios", list, "list the built-in 3-D scenarios and exit");
  app.add_flag("--print-scenario", print_scenario, "print the resolved scenario and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (list) {
    for (const auto& n : ggins::truth3d::builtin_scenario3_names()) {
      auto s = ggins::truth3d::load_scenario3(n, {GGINS_SCENARIO_DIR});
      std::printf("%-20s %s\n", n.c_str(), s.description.c_str());
    }
    return 0;
  }
  ggins::truth3d::Scenario3 sc;
  try {
    sc = ggins::truth3d::load_scenario3(o.scenario, {GGINS_SCENARIO_DIR});
    if (o.duration_s) {
      if (!(*o.duration_s > 0)) throw std::runtime_error("--duration must be > 0");
      sc.duration_s = *o.duration_s;
    }
    if (sc.n_steps() < 2) throw std::runtime_error("the scenario needs at least two steps");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins run3d: %s\n", e.what());
    return 2;
  }
  if (print_scenario) {
    std::printf("# %s\n%s", sc.source.c_str(), sc.text.c_str());
    return 0;
  }
  if (o.direct && o.realtime) {
    std::fprintf(stderr, "ggins run3d: --direct and --realtime exclude each other\n");
    return 2;
  }
  if (!o.direct) {
    if (o.hal_sim.empty()) o.hal_sim = (ggins::hil::self_dir() / "hal_sim").string();
    if (access(o.hal_sim.c_str(), X_OK) != 0) {
      std::fprintf(stderr, "ggins run3d: hal_sim not found at %s (build it, give --hal-sim, or --direct)\n",
                   o.hal_sim.c_str());
      return 2;
    }
  }
  std::error_code ec;
  fs::path out = ggins::hil::create_output_dir(o.out, sc.name, ec);
  if (ec) {
    std::fprintf(stderr, "ggins run3d: cannot create %s: %s\n", out.c_str(), ec.message().c_str());
    return 2;
  }
  out = fs::absolute(out);
  {
    std::ofstream f(out / "scenario.toml");
    f << "# scenario " << sc.name << " from " << sc.source << "\n# effective duration_s = " << sc.duration_s << "\n"
      << sc.text;
  }
  ggins::hil::install_interrupt_handlers();
  json summary;
  try {
    Runner3 r(o, sc, out);
    summary = r.run();
  } catch (const Fail& e) {
    std::fprintf(stderr, "ggins run3d: %s\n", e.what());
    return e.code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins run3d: %s\n", e.what());
    return 1;
  }
  summary["output_dir"] = out.string();
  {
    std::ofstream f(out / "summary.json");
    f << summary.dump(2) << "\n";
  }
  if (!o.no_plots) {
    if (o.python.empty()) {
      std::fprintf(stderr, "ggins run3d: no Python with matplotlib; plots skipped (--python)\n");
    } else {
      const std::string cmd = o.python + " " + GGINS_PLOT3D_SCRIPT + " '" + out.string() + "'";
      if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "ggins run3d: plotting failed (%s)\n", cmd.c_str());
    }
  }
  if (!o.quiet)
    std::printf("position error %.3e m (max %.3e), attitude %.3e rad, G %.3e m/s^2, Gamma %.3e E (max %.3e); %lld steps, "
                "wall %.1f s\n",
                summary["position_error_m"]["final"].get<double>(), summary["position_error_m"]["max"].get<double>(),
                summary["attitude_error_rad"]["final"].get<double>(), summary["gravity_error_mps2"]["final"].get<double>(),
                summary["gamma_error_ecef_E"]["final"].get<double>(), summary["gamma_error_ecef_E"]["max"].get<double>(),
                static_cast<long long>(summary["steps"].get<int64_t>()), summary["wall_s"].get<double>());
  if (summary.contains("bus_auth") && summary["bus_auth"]["rejected_total"].get<int64_t>() > 0)
    std::fprintf(stderr, "%s: %lld messages without a valid MAC were dropped (someone without the key published on the "
                 "run's channels): %s\n", "ggins run3d", static_cast<long long>(summary["bus_auth"]["rejected_total"].get<int64_t>()),
                 summary["bus_auth"]["rejected_unauthenticated"].dump().c_str());
  std::printf("report: %s\n", out.c_str());
  if (summary.contains("completed") && !summary["completed"].get<bool>()) {
    std::fprintf(stderr, "ggins run3d: conflicting authenticated messages (%s); the run cannot be trusted\n",
                 summary["bus_auth"]["conflicts"].dump().c_str());
    return 1;
  }
  if (summary.value("degraded", false)) {
    std::fprintf(stderr, "ggins run3d: completed but degraded (%lld steps rejected; see summary.json)\n",
                 static_cast<long long>(summary["steps_rejected"].get<int64_t>()));
    return 4;
  }
  return 0;
}
