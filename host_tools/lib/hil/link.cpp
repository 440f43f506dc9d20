// See link.hpp.
#include "link.hpp"

#include <poll.h>
#include <sys/wait.h>
#include <time.h>

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace ggins::hil {

namespace {
uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

const char* kMulticastFix =
    "  UDP multicast on the loopback interface is needed for LCM. Fix (as root):\n"
    "    ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo\n"
    "  (scripts/setup does this when it runs as root.)";
}  // namespace

double fault_uniform(uint64_t seed, uint64_t kind, uint64_t seq, uint64_t attempt) {
  const uint64_t x = mix64(mix64(mix64(seed ^ (kind << 56)) ^ seq) ^ mix64(attempt + 0x5157ull));
  return static_cast<double>(mix64(x) >> 11) * 0x1.0p-53;
}

json percentiles_json(std::vector<double> v, double scale) {
  if (v.empty()) return {{"median", 0.0}, {"p99", 0.0}, {"max", 0.0}, {"n", 0}};
  std::sort(v.begin(), v.end());
  auto at = [&](double q) { return scale * v[static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5)]; };
  return {{"median", at(0.5)}, {"p99", at(0.99)}, {"max", scale * v.back()}, {"n", v.size()}};
}

LinkBase::LinkBase(const LinkOptions& o, fs::path out, int64_t n_steps, int64_t dt_us)
    : opt_(o), out_(std::move(out)), n_(n_steps), dt_us_(dt_us) {
  run_id_ = new_run_id();
  ch_frame_ = channel("FRAME");
  ch_frames_ = channel("FRAMES");
  ch_control_ = channel("CONTROL");
  ch_hal_ = channel("HAL");
  ch_nak_ = channel("NAK");
  ch_request_ = channel("REQUEST");
  ch_ping_ = channel("PING");
}

LinkBase::~LinkBase() {
  if (hal_pid_ > 0) stop_child(hal_pid_, SIGTERM, 1.0);
  if (logger_pid_ > 0) stop_child(logger_pid_, SIGINT, 10.0);
  if (lcm_out_ && lcm_out_ != lcm_) lcm_destroy(lcm_out_);
  if (lcm_) lcm_destroy(lcm_);
}

void LinkBase::publish_raw(const std::string& ch, int n, bool sign) {
  if (n < 0) throw Fail("cannot encode a message for " + ch);
  if (sign) auth_.sign(ch, buf_.data(), n);  // every message of the run carries its MAC
  lcm_t* l = ch == ch_ping_ ? lcm_ : lcm_out_;  // pings go round our own inbound URL
  if (lcm_publish(l, ch.c_str(), buf_.data(), static_cast<unsigned>(n)) != 0)
    throw Fail("LCM publish on " + ch + " failed");
  if (rec_ && ch != ch_ping_) rec_->write(ch, buf_.data(), n, wall_us());
}

void LinkBase::handle(double timeout_s) { handle_lcm(lcm_, timeout_s); }

void LinkBase::handle_ready() {
  pollfd p{lcm_get_fileno(lcm_), POLLIN, 0};
  for (int i = 0; i < 100000 && poll(&p, 1, 0) > 0 && (p.revents & POLLIN); ++i)
    if (lcm_handle(lcm_) != 0) throw Fail("lcm_handle failed");
}

void LinkBase::handle_until(double t_abs) {
  const double rem = t_abs - mono_s();
  if (rem <= 0) return;
  timespec ts;
  ts.tv_sec = static_cast<time_t>(rem);
  ts.tv_nsec = static_cast<long>((rem - static_cast<double>(ts.tv_sec)) * 1e9);
  pollfd p{lcm_get_fileno(lcm_), POLLIN, 0};
  const int r = ppoll(&p, 1, &ts, nullptr);
  if (r > 0 && (p.revents & POLLIN)) {
    if (lcm_handle(lcm_) != 0) throw Fail("lcm_handle failed");
  } else if (r < 0 && errno != EINTR) {
    throw Fail("ppoll failed");
  }
}

double LinkBase::cpu_s() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double LinkBase::hal_sim_cpu_s() const {
  if (hal_pid_ <= 0) return -1;
  std::ifstream f("/proc/" + std::to_string(hal_pid_) + "/stat");
  std::string st((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t close = st.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return -1;
  std::istringstream in(st.substr(close + 2));
  std::string x;
  unsigned long long ut = 0, stime = 0;
  for (int field = 3; field <= 15 && in >> x; ++field) {  // fields 14 utime, 15 stime (man 5 proc)
    if (field == 14) ut = std::stoull(x);
    if (field == 15) stime = std::stoull(x);
  }
  const long hz = sysconf(_SC_CLK_TCK);
  return hz > 0 ? static_cast<double>(ut + stime) / static_cast<double>(hz) : -1;
}

void LinkBase::check_children() {
  if (hal_pid_ > 0) {
    int st = 0;
    if (waitpid(hal_pid_, &st, WNOHANG) == hal_pid_) {
      hal_pid_ = -1;
      throw Fail("hal_sim exited unexpectedly (status " + std::to_string(WIFEXITED(st) ? WEXITSTATUS(st) : -WTERMSIG(st)) +
                 "); see " + (out_ / "hal_sim.log").string());
    }
  }
  if (interrupted()) throw Fail("interrupted", 130);
}

void LinkBase::on_hal(const lcm_recv_buf_t* rb) {
  ggins::hal_status_t m{};
  if (!accept(rb, ch_hal_, m)) return;
  if (hal_ && m.seq == hal_->seq && !same_content(*hal_, m)) ++status_conflict_;
  if (!hal_ || m.seq > hal_->seq) hal_ = m;
}

void LinkBase::send_control(int32_t cmd, uint64_t scenario_id) {
  ggins::run_control_t c{};
  c.utime = wall_us();
  c.seq = control_seq_++;
  c.run_id = run_id_;
  c.command = cmd;
  c.scenario_id = static_cast<int64_t>(scenario_id);
  c.resend_seq = -1;
  c.n_steps = n_;
  c.realtime = opt_.realtime ? 1 : 0;
  publish(ch_control_, c);
}

void LinkBase::open_bus(const std::string& config_channel) {
  ch_config_ = channel(config_channel);
  if (!opt_.lcm_url.empty()) {
    url_ = url_in_ = opt_.lcm_url;
  } else {
    const std::vector<int> ports = free_udp_ports(2);
    if (ports.empty()) throw Fail("cannot find free UDP ports for LCM");
    // a large socket receive buffer (up to net.core.rmem_max): room for bursts of batches
    long rmem = 4 << 20;
    if (std::FILE* f = std::fopen("/proc/sys/net/core/rmem_max", "r")) {
      long v = 0;
      if (std::fscanf(f, "%ld", &v) == 1 && v > 0) rmem = std::min<long>(v, 16 << 20);
      std::fclose(f);
    }
    auto url = [&](int port) {
      return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=" + std::to_string(rmem);
    };
    // one port per direction, so that no process receives and discards its own
    // traffic; a separate lcm-logger listens to one URL only: then one for all
    url_ = url(ports[0]);
    url_in_ = opt_.log_mode == "lcm-logger" ? url_ : url(ports[1]);
  }
  lcm_ = lcm_create(url_in_.c_str());
  if (!lcm_) throw Fail("cannot open LCM at " + url_in_ + " (lcm_create failed).\n" + kMulticastFix, 3);
  lcm_out_ = lcm_;
  if (url_ != url_in_) {
    lcm_out_ = lcm_create(url_.c_str());
    if (!lcm_out_) throw Fail("cannot open LCM at " + url_ + " (lcm_create failed).\n" + kMulticastFix, 3);
  }
  lcm_subscribe(lcm_, ch_ping_.c_str(), on_ping_cb, this);
  const double end = mono_s() + 1.5;
  while (pings_ == 0 && mono_s() < end) {  // multicast on loopback works
    ggins::run_control_t c{};
    c.utime = wall_us();
    c.run_id = run_id_;
    c.resend_seq = -1;
    publish(ch_ping_, c);
    handle(0.1);
  }
  if (pings_ == 0) throw Fail("an LCM message sent to " + url_in_ + " did not come back within 1.5 s.\n" + kMulticastFix, 3);
  if (opt_.log_mode == "lcm-logger") start_logger();
  if (opt_.log_mode == "internal") rec_ = std::make_unique<Recorder>(out_ / "run.lcmlog");
  lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_hal_.c_str(), on_hal_cb, this), 100000);

  // hal_sim re-requests a missing frame every max(2, resend timeout / 25) ms (Link::gap_interval_s)
  const int gap_ms = std::max(2, opt_.resend_timeout_ms / 25);
  std::vector<std::string> argv = hal_sim_argv(opt_.hal_sim, url_, url_in_, opt_.prefix, run_id_, 2 * gap_ms);
  argv.insert(argv.end(), opt_.hal_args.begin(), opt_.hal_args.end());
  if (opt_.faults.drop_output > 0 || opt_.faults.conflict > 0)
    argv.insert(argv.end(), {"--drop-output-prob", std::to_string(opt_.faults.drop_output), "--inject-seed",
                             std::to_string(opt_.faults.seed)});
  if (opt_.faults.conflict > 0) argv.insert(argv.end(), {"--conflict-output-prob", std::to_string(opt_.faults.conflict)});
  hal_pid_ = auth_.spawn_hal_sim(argv, out_ / "hal_sim.log");
  const double end2 = mono_s() + 10.0;
  while (!hal_) {
    handle(0.05);
    check_children();
    if (mono_s() > end2) throw Fail("hal_sim did not report within 10 s; see " + (out_ / "hal_sim.log").string());
  }
}

void LinkBase::start_logger() {
  const fs::path log = out_ / "run.lcmlog";
  logger_pid_ = spawn({opt_.logger, "-q", "-f", "--lcm-url=" + url_, log.string()}, out_ / "lcm-logger.log");
  // lcm-logger subscribes before it creates the file; the file grows once our
  // pings reach it (it flushes every 100 ms). Wait for that.
  const double end = mono_s() + 10.0;
  std::error_code ec;
  for (;;) {
    ggins::run_control_t c{};
    c.utime = wall_us();
    c.run_id = run_id_;
    c.resend_seq = -1;
    publish(ch_ping_, c);
    handle(0.02);
    if (fs::exists(log, ec) && fs::file_size(log, ec) > 0) break;
    int st = 0;
    if (waitpid(logger_pid_, &st, WNOHANG) == logger_pid_) {
      logger_pid_ = -1;
      throw Fail("lcm-logger exited at start; see " + (out_ / "lcm-logger.log").string());
    }
    if (mono_s() > end) throw Fail("lcm-logger did not record anything within 10 s");
  }
}

void LinkBase::finish() {
  const int64_t status_before = hal_ ? hal_->seq : -1;
  for (int i = 0; i < 20; ++i) {
    send_control(ggins::run_control_t::STOP, 0);
    const double end = mono_s() + 0.1;
    while (mono_s() < end) {
      handle(0.02);
      if (hal_ && hal_->seq > status_before && hal_->state == ggins::hal_status_t::STOPPED) break;
    }
    if (hal_ && hal_->state == ggins::hal_status_t::STOPPED) break;
  }
  if (hal_pid_ > 0) {
    if (wait_child(hal_pid_, 3.0) == -1) stop_child(hal_pid_, SIGTERM, 1.0);
    hal_pid_ = -1;
  }
}

void LinkBase::close_log() {
  if (logger_pid_ > 0) stop_child(logger_pid_, SIGINT, 30.0);  // flushes and closes the log
  if (rec_) rec_->close();
}

json LinkBase::bus_auth_summary(int64_t outputs_conflict) const {
  return hil::bus_auth_summary(auth_, hal_ ? &*hal_ : nullptr, ch_frame_, ch_config_, ch_control_, outputs_conflict,
                               status_conflict_, foreign_msgs_);
}

json LinkBase::hal_sim_summary() const {
  if (!hal_) return nullptr;
  const auto& h = *hal_;
  return {{"state", h.state},
          {"steps", h.steps},
          {"steps_rejected", h.steps_rejected},
          {"frames_received", h.frames_received},
          {"frames_duplicate", h.frames_duplicate},
          {"frames_out_of_order", h.frames_out_of_order},
          {"frames_recovered", h.frames_recovered},
          {"frames_lost", h.frames_lost},
          {"resend_requests", h.resend_requests},
          {"outputs_republished", h.outputs_republished},
          {"decode_errors", h.decode_errors},
          {"foreign_messages", h.foreign_messages},
          {"deadline_overruns", h.deadline_overruns},
          {"outputs_dropped_injected", h.outputs_dropped_injected},
          {"auth_failed_frame", h.auth_failed_frame},
          {"auth_failed_config", h.auth_failed_config},
          {"auth_failed_control", h.auth_failed_control},
          {"frames_conflict", h.frames_conflict},
          {"config_conflict", h.config_conflict},
          {"outputs_conflict_injected", h.outputs_conflict_injected}};
}

}  // namespace ggins::hil
