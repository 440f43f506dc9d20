// ggins run3d (ggins-run3d): fly one 3-D scenario (scenarios/3d-*.toml,
// host_tools/truth3d) against the 3-D firmware (nav3d.h), host-in-the-loop
// over LCM through hal_sim (default) or in process (--direct), and write
// summary.json, timeseries.csv, errors.png, run.lcmlog.
//
// LCM protocol (hal_sim in 3-D mode, see hal_sim --help): nav3d_config_t on
// P+CONFIG3D until hal_sim reports CONFIGURED, START on P+CONTROL, then in
// lockstep sensor_frame_t k on P+FRAME -> nav3d_output_t k on P+NAV3D (a frame
// whose output does not come within --resend-timeout-ms is sent again; RESEND
// requests on P+REQUEST are answered), truth3d_t on P+TRUTH3D (decimated), STOP.
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
#include "hal_map.h"
#include "ggins/hal_status_t.hpp"
#include "ggins/nav3d_config_t.hpp"
#include "ggins/nav3d_output_t.hpp"
#include "ggins/run_control_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth3d_t.hpp"
#include "hil_common.hpp"

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
  ~Runner3() { cleanup(); }
  json run();

 private:
  static void on_nav_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Runner3*>(u)->on_nav(rb); }
  static void on_hal_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Runner3*>(u)->on_hal(rb); }
  static void on_req_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Runner3*>(u)->on_req(rb); }
  void on_nav(const lcm_recv_buf_t* rb);
  void on_hal(const lcm_recv_buf_t* rb);
  void on_req(const lcm_recv_buf_t* rb);
  template <class M>
  void publish(const std::string& ch, const M& m) {
    const int n = m.encode(buf_.data(), 0, static_cast<int>(buf_.size()));
    auth_.sign(ch, buf_.data(), n);  // every message of the run carries its MAC
    if (n < 0 || lcm_publish(lcm_out_, ch.c_str(), buf_.data(), static_cast<unsigned>(n)) != 0)
      throw Fail("LCM publish on " + ch + " failed");
    record(ch, buf_.data(), n, wall_us());
  }
  void record(const std::string& ch, const void* d, int n, int64_t ut) {
    if (log_) log_->write(ch, d, n, ut);
  }
  // The checks on a received message (BusAuth::check); authentic messages are
  // logged under their channel, those of our run whose MAC fails under
  // <channel>.UNAUTHENTICATED, other runs' traffic and undecodable payloads not.
  template <class M>
  bool accept(const lcm_recv_buf_t* rb, const std::string& ch, M& m) {
    const int n = static_cast<int>(rb->data_size);
    switch (auth_.check(ch, rb->data, rb->data_size, run_id_, m)) {
      case ggins::hil::BusAuth::Check::kOk: record(ch, rb->data, n, rb->recv_utime); return true;
      case ggins::hil::BusAuth::Check::kUndecodable: ++decode_errors_; return false;
      case ggins::hil::BusAuth::Check::kForeign: ++foreign_msgs_; return false;
      case ggins::hil::BusAuth::Check::kUnauthenticated:
        record(ch + ".UNAUTHENTICATED", rb->data, n, rb->recv_utime);
        return false;
    }
    return false;
  }
  json bus_auth_summary() const;
  void handle(double timeout_s) { ggins::hil::handle_lcm(lcm_, timeout_s); }
  void check_children();
  void send_frame(int64_t k);
  void send_control(int32_t cmd);
  void setup_lcm();
  void configure_hal();
  void finish_hal();
  void cleanup();
  void consume(int64_t k, const ggins::truth3d::Truth3& t, const gg_nav3d_output_t& o, double step_ns);
  static void from_lcm(const ggins::nav3d_output_t& m, gg_nav3d_output_t& o);

  const Options& opt_;
  ggins::truth3d::Scenario3 sc_;
  ggins::truth3d::Generator3 gen_;
  fs::path out_;
  std::string url_, url_in_;
  lcm_t *lcm_ = nullptr, *lcm_out_ = nullptr;
  std::unique_ptr<ggins::hil::Recorder> log_;
  pid_t hal_pid_ = -1;
  int64_t run_id_ = 0;
  std::string ch_frame_, ch_nav_, ch_truth_, ch_config_, ch_control_, ch_request_, ch_hal_;
  std::vector<uint8_t> buf_ = std::vector<uint8_t>(16384);
  ggins::hil::BusAuth auth_;           // the run's key; MACs
  ggins::hil::SeqCopies<ggins::nav3d_output_t> out_taken_;  // the outputs taken, per seq
  int64_t outputs_conflict_ = 0, status_conflict_ = 0, foreign_msgs_ = 0;
  int64_t n_ = 0, csv_every_ = 1, truth_every_ = 1;
  int64_t pending_ = -1;  // seq whose output we wait for (lockstep)
  ggins::truth3d::Truth3 pending_truth_;
  bool got_pending_ = false;
  std::vector<uint8_t> attempts_;
  int64_t frames_published_ = 0, truth_published_ = 0, resend_timeouts_ = 0, resend_on_request_ = 0;
  int64_t outputs_ = 0, outputs_dup_ = 0, outputs_foreign_ = 0, decode_errors_ = 0, control_seq_ = 0;
  std::optional<ggins::hal_status_t> hal_;
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

void Runner3::on_nav(const lcm_recv_buf_t* rb) {
  ggins::nav3d_output_t m{};
  const int64_t foreign_before = foreign_msgs_;
  if (!accept(rb, ch_nav_, m)) {
    outputs_foreign_ += foreign_msgs_ - foreign_before;
    return;
  }
  ggins::nav3d_output_t plain = m;
  plain.republished = 0;  // transport: differs between copies of one output
  if (m.seq != pending_ || got_pending_) {
    if (out_taken_.compare(m.seq, plain) < 0) {
      ++outputs_conflict_;  // two different authenticated outputs for one seq
      if (outputs_conflict_ <= 10)
        std::fprintf(stderr, "ggins run3d: conflict: a second authenticated output for step %lld differs from the first\n",
                     static_cast<long long>(m.seq));
    } else {
      ++outputs_dup_;
    }
    return;
  }
  got_pending_ = true;
  out_taken_.put(m.seq, plain);
  ++outputs_;
  gg_nav3d_output_t o;
  from_lcm(m, o);
  consume(m.seq, pending_truth_, o, static_cast<double>(o.cycles[GG_MOD_TOTAL]));
}

void Runner3::on_hal(const lcm_recv_buf_t* rb) {
  ggins::hal_status_t m{};
  if (!accept(rb, ch_hal_, m)) return;
  if (hal_ && m.seq == hal_->seq && !ggins::hil::same_content(*hal_, m)) ++status_conflict_;
  if (!hal_ || m.seq > hal_->seq) hal_ = m;
}

void Runner3::on_req(const lcm_recv_buf_t* rb) {
  ggins::run_control_t m{};
  if (!accept(rb, ch_request_, m)) return;
  if (m.command != ggins::run_control_t::RESEND) return;
  if (m.resend_seq == pending_) {  // lockstep: only the frame in flight can be missing
    ++resend_on_request_;
    send_frame(pending_);
  }
}

void Runner3::check_children() {
  if (hal_pid_ > 0) {
    int st = 0;
    if (waitpid(hal_pid_, &st, WNOHANG) == hal_pid_) {
      hal_pid_ = -1;
      throw Fail("hal_sim exited unexpectedly; see " + (out_ / "hal_sim.log").string());
    }
  }
  if (ggins::hil::interrupted()) throw Fail("interrupted", 130);
}

void Runner3::send_frame(int64_t k) {
  gg_frame_t f;
  ggins::truth3d::Truth3 t;
  gen_.frame(k, f, &t);
  auto& att = attempts_[static_cast<size_t>(k)];
  const ggins::sensor_frame_t m = ggins::hil::sensor_frame_msg(f, run_id_, att);
  publish(ch_frame_, m);
  ++frames_published_;
  if (att == 0 && (k % truth_every_ == 0 || k == n_ - 1)) {
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
    publish(ch_truth_, tm);
    ++truth_published_;
  }
  if (att < 255) ++att;
  pending_ = k;
  pending_truth_ = t;
}

void Runner3::send_control(int32_t cmd) {
  ggins::run_control_t c{};
  c.utime = wall_us();
  c.seq = control_seq_++;
  c.run_id = run_id_;
  c.command = cmd;
  c.resend_seq = -1;
  c.n_steps = n_;
  publish(ch_control_, c);
}

void Runner3::setup_lcm() {
  if (!opt_.lcm_url.empty()) {
    url_ = url_in_ = opt_.lcm_url;
  } else {
    const std::vector<int> ports = free_udp_ports(2);
    if (ports.empty()) throw Fail("cannot find free UDP ports for LCM");
    auto url = [](int port) { return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=4194304"; };
    url_ = url(ports[0]);     // to hal_sim
    url_in_ = url(ports[1]);  // from hal_sim
  }
  lcm_ = lcm_create(url_in_.c_str());
  if (!lcm_)
    throw Fail("cannot open LCM at " + url_in_ +
                   " (UDP multicast on loopback needed: ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo)",
               3);
  lcm_out_ = lcm_;
  if (url_ != url_in_) {
    lcm_out_ = lcm_create(url_.c_str());
    if (!lcm_out_) throw Fail("cannot open LCM at " + url_, 3);
  }
  lcm_subscription_t* s = lcm_subscribe(lcm_, ch_nav_.c_str(), on_nav_cb, this);
  lcm_subscription_set_queue_capacity(s, 100000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_hal_.c_str(), on_hal_cb, this), 100000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_request_.c_str(), on_req_cb, this), 100000);
  auto hal_argv = ggins::hil::hal_sim_argv(opt_.hal_sim, url_, url_in_, opt_.prefix, run_id_, opt_.resend_timeout_ms);
  {  // the onboard map tiles of the map aid: hal_sim's map storage
    const auto aid = ggins::run3d::parse_aid_ukf(sc_.text, sc_.source);
    if (aid.enabled)
      for (const auto& p : ggins::run3d::aid_ukf_map_paths(aid, sc_.source)) {
        hal_argv.push_back("--map");
        hal_argv.push_back(fs::absolute(p).string());
      }
  }
  hal_pid_ = auth_.spawn_hal_sim(hal_argv, out_ / "hal_sim.log");
  const double end = mono_s() + 10.0;
  while (!hal_) {
    handle(0.05);
    check_children();
    if (mono_s() > end) throw Fail("hal_sim did not report within 10 s; see " + (out_ / "hal_sim.log").string());
  }
}

void Runner3::configure_hal() {
  gg_nav3d_config_t c;
  ggins::truth3d::nav3d_config(sc_, gen_, c);
  ggins::nav3d_config_t m{};
  m.utime = wall_us();
  m.seq = 0;
  m.run_id = run_id_;
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
  const double end = mono_s() + 10.0;
  double next_send = 0;
  while (!(hal_ && hal_->config_seq == 0 && hal_->state != ggins::hal_status_t::IDLE)) {
    if (mono_s() >= next_send) {
      publish(ch_config_, m);
      next_send = mono_s() + 0.1;
    }
    handle(0.02);
    check_children();
    if (mono_s() > end) throw Fail("hal_sim did not accept the configuration within 10 s");
  }
  if (hal_->init_status != 0)
    throw Fail("the firmware refused the configuration (gg_nav3d_init status " + std::to_string(hal_->init_status) + ")");
  send_control(ggins::run_control_t::START);
}

void Runner3::finish_hal() {
  for (int i = 0; i < 20; ++i) {
    send_control(ggins::run_control_t::STOP);
    const double end = mono_s() + 0.1;
    while (mono_s() < end && !(hal_ && hal_->state == ggins::hal_status_t::STOPPED)) handle(0.02);
    if (hal_ && hal_->state == ggins::hal_status_t::STOPPED) break;
  }
  if (hal_pid_ > 0) {
    if (wait_child(hal_pid_, 3.0) == -1) stop_child(hal_pid_);
    hal_pid_ = -1;
  }
}

void Runner3::cleanup() {
  if (hal_pid_ > 0) stop_child(hal_pid_);
  if (lcm_out_ && lcm_out_ != lcm_) lcm_destroy(lcm_out_);
  lcm_out_ = nullptr;
  if (lcm_) lcm_destroy(lcm_);
  lcm_ = nullptr;
  log_.reset();
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

json Runner3::bus_auth_summary() const {
  return ggins::hil::bus_auth_summary(auth_, hal_ ? &*hal_ : nullptr, ch_frame_, ch_config_, ch_control_, outputs_conflict_,
                                      status_conflict_, foreign_msgs_);
}

json Runner3::run() {
  n_ = gen_.n_steps();
  attempts_.assign(static_cast<size_t>(n_), 0);
  csv_every_ = std::max<int64_t>(1, std::llround(sc_.rate_hz / (opt_.csv_rate ? *opt_.csv_rate : sc_.csv_rate_hz)));
  truth_every_ = opt_.truth_rate > 0 ? std::max<int64_t>(1, std::llround(sc_.rate_hz / opt_.truth_rate)) : 1;
  run_id_ = ggins::hil::new_run_id();
  const std::string& p = opt_.prefix;
  ch_frame_ = p + "FRAME";
  ch_nav_ = p + "NAV3D";
  ch_truth_ = p + "TRUTH3D";
  ch_config_ = p + "CONFIG3D";
  ch_control_ = p + "CONTROL";
  ch_request_ = p + "REQUEST";
  ch_hal_ = p + "HAL";
  csv_.open(out_ / "timeseries.csv");
  if (!csv_) throw Fail("cannot write " + (out_ / "timeseries.csv").string());
  csv_ << "t_s,seq,lat_deg,lon_deg,h_m,roll_deg,pitch_deg,yaw_deg,speed_mps,nav_lat_deg,nav_lon_deg,nav_h_m,"
          "err_n_m,err_e_m,err_d_m,err_r_m,err_vn_mps,err_ve_mps,err_vd_mps,err_v_mps,"
          "att_err_n_rad,att_err_e_rad,att_err_d_rad,att_err_rad,err_gn_mps2,err_ge_mps2,err_gd_mps2,err_g_mps2,"
          "err_gamma_e_E,err_gamma_b_E,err_h_m,parity_x,parity_y,parity_z,parity_trace,baro_innov_m,a_c_mps2,status,"
          "health\n";
  const double t0 = mono_s();
  static gg_nav3d_t nav;  // large: static storage (direct mode)
  static hal_map_store_t maps;  // the computer's map storage (direct mode; hal_sim/hal_map.c)
  const auto aid = ggins::run3d::parse_aid_ukf(sc_.text, sc_.source);
  json aid_j;  // the map aid's counters (direct mode)
  if (opt_.direct) {
    gg_nav3d_config_t c;
    ggins::truth3d::nav3d_config(sc_, gen_, c);
    const gg_status_t st = gg_nav3d_init(&nav, &c);
    if (st != GG_OK) throw Fail("gg_nav3d_init refused the configuration (status " + std::to_string(st) + ")");
    hal_map_init(&maps);
    if (aid.enabled) {
      for (const auto& p : ggins::run3d::aid_ukf_map_paths(aid, sc_.source)) {
        char err[512];
        if (hal_map_load(&maps, p.c_str(), err, sizeof err) != 0) throw Fail(std::string("aid_ukf.map: ") + err);
      }
    }
    gg_hal_t hal{};
    hal.map = maps.n_tiles > 0 ? &maps.ops : nullptr;
    uint32_t closed = 0;
    double nis_sum = 0.0;
    gg_nav3d_output_t last{};
    for (int64_t k = 0; k < n_; ++k) {
      gg_frame_t f;
      ggins::truth3d::Truth3 t;
      gen_.frame(k, f, &t);
      gg_nav3d_output_t o;
      const auto a = std::chrono::steady_clock::now();
      gg_nav3d_step(&nav, &f, &hal, &o);
      const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - a).count();
      ++outputs_;
      consume(k, t, o, ns);
      if (o.mm_updates + o.mm_rejected > closed) {  // an epoch finished: its NIS
        closed = o.mm_updates + o.mm_rejected;
        nis_sum += o.mm_nis;
      }
      last = o;
      if (ggins::hil::interrupted()) throw Fail("interrupted", 130);
    }
    if (aid.enabled) {
      aid_j["epochs"] = last.mm_epochs;
      aid_j["updates"] = last.mm_updates;
      aid_j["rejected"] = last.mm_rejected;
      aid_j["no_map"] = last.mm_no_map;
      aid_j["nis_mean"] = closed > 0 ? nis_sum / closed : 0.0;
      aid_j["nis_dof"] = 6;
      aid_j["sigma_pos_m"] = {last.mm_sigma[0], last.mm_sigma[1], last.mm_sigma[2]};
      aid_j["tiles"] = maps.n_tiles;
    }
    hal_map_free(&maps);
  } else {
    if (!opt_.no_log) {
      log_ = std::make_unique<ggins::hil::Recorder>(out_ / "run.lcmlog");
    }
    setup_lcm();
    configure_hal();
    const double timeout = 1e-3 * opt_.resend_timeout_ms;
    for (int64_t k = 0; k < n_; ++k) {
      got_pending_ = false;
      send_frame(k);
      double deadline = mono_s() + timeout;
      int tries = 0;
      while (!got_pending_) {
        const double now = mono_s();
        if (now >= deadline) {
          check_children();
          if (++tries > opt_.max_resend)
            throw Fail("no navigation output for step " + std::to_string(k) + "; see " + (out_ / "hal_sim.log").string());
          ++resend_timeouts_;
          send_frame(k);
          deadline = mono_s() + timeout;
          continue;
        }
        handle(deadline - now);
      }
      if ((k & 1023) == 0) check_children();
      if (!opt_.quiet && (k % std::max<int64_t>(1, n_ / 10)) == 0 && k > 0)
        std::fprintf(stderr, "ggins run3d: t = %.0f / %.0f s  |dr| %.3g m\n", static_cast<double>(gen_.time_of(k)),
                     sc_.duration_s, pos_.final);
    }
    finish_hal();
  }
  const double wall = mono_s() - t0;
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
  j["mode"] = opt_.direct ? "direct (in process, no LCM)" : "host-in-the-loop over LCM (hal_sim)";
  j["duration_s"] = sc_.duration_s;
  j["rate_hz"] = sc_.rate_hz;
  j["steps"] = n_;
  j["outputs"] = outputs_;
  j["steps_rejected"] = rejected_;
  j["health_or"] = health_or_;
  j["position_error_m"] = pos_.j();
  j["aid_ukf"] = aid.enabled ? (opt_.direct ? aid_j : json("on (counters in the LCM output)")) : json("off");
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
  j["realtime_factor"] = wall > 0 ? sc_.duration_s / wall : 0.0;
  j["step_ns"] = {{"median", pct(0.5)}, {"p99", pct(0.99)}, {"max", s.empty() ? 0.0 : s.back()}};
  if (!opt_.direct) {
    j["transport"] = {{"frames_published", frames_published_}, {"truth_published", truth_published_},
                      {"resend_timeouts", resend_timeouts_}, {"resend_on_request", resend_on_request_},
                      {"outputs_duplicate", outputs_dup_}, {"outputs_foreign", outputs_foreign_},
                      {"decode_errors", decode_errors_}};
    if (hal_)
      j["hal_sim"] = {{"steps", hal_->steps}, {"steps_rejected", hal_->steps_rejected},
                      {"frames_received", hal_->frames_received}, {"frames_lost", hal_->frames_lost},
                      {"frames_duplicate", hal_->frames_duplicate}, {"decode_errors", hal_->decode_errors},
                      {"foreign_messages", hal_->foreign_messages}, {"auth_failed_frame", hal_->auth_failed_frame},
                      {"auth_failed_config", hal_->auth_failed_config},
                      {"auth_failed_control", hal_->auth_failed_control}, {"frames_conflict", hal_->frames_conflict},
                      {"config_conflict", hal_->config_conflict}};
    j["bus_auth"] = bus_auth_summary();
    // two different authenticated messages for one seq: which copy was right
    // cannot be known, so the run is not completed (exit 1)
    j["completed"] = j["bus_auth"]["conflicts_total"].get<int64_t>() == 0;
    j["lcm_log"] = opt_.no_log ? "" : (out_ / "run.lcmlog").string();
  }
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bool list = false, print_scenario = false;
  CLI::App app{
      "ggins run3d: fly one 3-D scenario (six tri-axis accelerometers, rotating WGS-84 Earth,\n"
      "stabilized or strapdown platform; issue 7) against the 3-D firmware (nav3d.h).\n\n"
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
  app.add_flag("--direct", o.direct, "step the firmware in this process (no LCM, no hal_sim)");
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
  return 0;
}
