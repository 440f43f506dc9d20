// See hil_common.hpp.
#include "hil_common.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iterator>
#include <random>

extern char** environ;

namespace fs = std::filesystem;

namespace ggins::hil {

namespace {
volatile sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int) { g_interrupted = 1; }
}  // namespace

double mono_s() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int64_t wall_us() {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
}

std::vector<int> free_udp_ports(int n) {
  std::vector<int> fds, ports;
  for (int i = 0; i < n; ++i) {
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) break;
    fds.push_back(fd);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = 0;
    socklen_t len = sizeof a;
    if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0)
      break;
    ports.push_back(ntohs(a.sin_port));
  }
  for (int fd : fds) close(fd);
  if (static_cast<int>(ports.size()) != n) ports.clear();
  return ports;
}

int64_t new_run_id() {
  std::random_device rd;
  return static_cast<int64_t>((static_cast<uint64_t>(rd()) << 31 ^ rd() ^ static_cast<uint64_t>(getpid())) &
                              0x7fffffffffffffffULL);
}

pid_t spawn(const std::vector<std::string>& argv, const fs::path& log_path,
            const std::vector<std::pair<int, int>>& inherit, bool own_group) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  for (const auto& [from, to] : inherit) posix_spawn_file_actions_adddup2(&fa, from, to);  // dup2 clears FD_CLOEXEC
  posix_spawn_file_actions_addopen(&fa, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  std::vector<char*> av;
  for (const auto& a : argv) av.push_back(const_cast<char*>(a.c_str()));
  av.push_back(nullptr);
  pid_t pid = -1;
  posix_spawnattr_t at;
  posix_spawnattr_init(&at);
  if (own_group) {
    posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&at, 0);
  }
  const int rc = posix_spawnp(&pid, av[0], &fa, &at, av.data(), environ);
  posix_spawnattr_destroy(&at);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw Fail("cannot start " + argv[0] + ": " + std::strerror(rc));
  return pid;
}

int wait_child(pid_t pid, double timeout_s) {
  const double end = mono_s() + timeout_s;
  for (;;) {
    int st = 0;
    pid_t r = waitpid(pid, &st, WNOHANG);
    if (r == pid) return st;
    if (r < 0) return 0;
    if (mono_s() > end) return -1;
    usleep(5000);
  }
}

void stop_child(pid_t& pid, int sig, double grace_s) {
  if (pid <= 0) return;
  kill(pid, sig);
  if (wait_child(pid, grace_s) == -1) {
    kill(pid, SIGKILL);
    wait_child(pid, 2.0);
  }
  pid = -1;
}

ggins::sensor_frame_t sensor_frame_msg(const gg_frame_t& f, int64_t run_id, int attempts) {
  ggins::sensor_frame_t m{};
  m.utime = f.utime;
  m.seq = f.seq;
  m.run_id = run_id;
  m.n_acc = f.n_acc;
  std::memcpy(m.f, f.f, sizeof m.f);
  std::memcpy(m.f_lo, f.f_lo, sizeof m.f_lo);
  std::copy(std::begin(f.acc_status), std::end(f.acc_status), m.acc_status);
  std::copy(std::begin(f.omega_b), std::end(f.omega_b), m.omega_b);
  m.gyro_status = f.gyro_status;
  m.baro_alt_m = f.baro_alt_m;
  m.baro_utime = f.baro_utime;
  m.baro_status = f.baro_status;
  m.ca_s[0] = f.ca_s[0];
  m.ca_s[1] = f.ca_s[1];
  m.ca_utime = f.ca_utime;
  m.ca_status = f.ca_status;
  m.resent = static_cast<int8_t>(std::min<int>(attempts, 127));
  return m;
}

std::vector<std::string> hal_sim_argv(const std::string& hal_sim, const std::string& url_to_hal,
                                      const std::string& url_from_hal, const std::string& prefix, int64_t run_id,
                                      int resend_timeout_ms) {
  return {hal_sim,
          "--lcm-url",
          url_to_hal,
          "--lcm-url-out",
          url_from_hal,
          "--prefix",
          prefix,
          "--run-id",
          std::to_string(run_id),
          "--key-fd",
          std::to_string(kHalKeyFd),
          "--gap-timeout-ms",
          std::to_string(std::max(2, resend_timeout_ms / 2)),
          "--idle-timeout-s",
          "30"};
}

BusAuth::BusAuth() {
  if (ggins_bus_init() != 0) throw Fail("libsodium cannot be initialised");
  ggins_bus_key_new(&key_);
}

void BusAuth::sign(const std::string& channel, uint8_t* buf, int n) const {
  if (n < 0 || ggins_bus_sign(&key_, channel.c_str(), buf, static_cast<size_t>(n)) != 0)
    throw Fail("cannot sign a message on " + channel);
}

pid_t BusAuth::spawn_hal_sim(const std::vector<std::string>& argv, const fs::path& log_path) const {
  int fd = ggins_bus_key_pipe(&key_);
  if (fd == kHalKeyFd) {  // dup2 onto itself would keep FD_CLOEXEC on some C libraries: move it first
    const int moved = fcntl(fd, F_DUPFD_CLOEXEC, kHalKeyFd + 1);
    close(fd);
    fd = moved;
  }
  if (fd < 0) throw Fail(std::string("cannot make the key pipe for hal_sim: ") + std::strerror(errno));
  try {
    const pid_t pid = spawn(argv, log_path, {{fd, kHalKeyFd}}, true);
    close(fd);
    return pid;
  } catch (...) {
    close(fd);
    throw;
  }
}

nlohmann::json bus_auth_summary(const BusAuth& auth, const ggins::hal_status_t* hal, const std::string& ch_frame,
                                const std::string& ch_config, const std::string& ch_control, int64_t outputs_conflict,
                                int64_t status_conflict, int64_t foreign) {
  using nlohmann::json;
  json j;
  j["mac"] = "keyed BLAKE2b-256 (RFC 7693; libsodium crypto_generichash) over the channel name and the encoded message";
  j["key"] = "32 random bytes per run (randombytes_buf); to hal_sim through an inherited pipe (--key-fd " +
             std::to_string(kHalKeyFd) + "), never on a command line, in the environment, a file or the log";
  json rej = json::object();
  for (const auto& [ch, n] : auth.rejected()) rej[ch] = n;
  if (hal) {
    if (hal->auth_failed_frame) rej[ch_frame] = hal->auth_failed_frame;
    if (hal->auth_failed_config) rej[ch_config] = hal->auth_failed_config;
    if (hal->auth_failed_control) rej[ch_control] = hal->auth_failed_control;
  }
  int64_t total = 0;
  for (const auto& [ch, n] : rej.items()) total += n.get<int64_t>();
  j["rejected_unauthenticated"] = rej;
  j["rejected_total"] = total;
  const json c = {{"frames", hal ? hal->frames_conflict : 0},
                  {"configurations", hal ? hal->config_conflict : 0},
                  {"outputs", outputs_conflict},
                  {"hal_status", status_conflict}};
  int64_t ct = 0;
  for (const auto& [k, n] : c.items()) ct += n.get<int64_t>();
  j["conflicts"] = c;
  j["conflicts_total"] = ct;
  j["foreign_run_messages"] = foreign + (hal ? hal->foreign_messages : 0);
  j["hal_sim_status_received"] = hal != nullptr;
  return j;
}

void handle_lcm(lcm_t* lcm, double timeout_s) {
  const int ms = std::max(0, static_cast<int>(std::ceil(timeout_s * 1000.0)));
  if (lcm_handle_timeout(lcm, ms) < 0 && errno != EINTR) throw Fail("lcm_handle_timeout failed");
}

Recorder::Recorder(const fs::path& p) {
  log_ = lcm_eventlog_create(p.c_str(), "w");
  if (!log_) throw Fail("cannot create LCM log " + p.string());
  setvbuf(log_->f, nullptr, _IOFBF, 1 << 20);
}

void Recorder::write(const std::string& ch, const void* data, int len, int64_t utime) {
  if (!log_) return;
  lcm_eventlog_event_t e{};
  e.eventnum = n_++;
  e.timestamp = utime;
  e.channellen = static_cast<int32_t>(ch.size());
  e.datalen = len;
  e.channel = const_cast<char*>(ch.c_str());
  e.data = const_cast<void*>(data);
  if (lcm_eventlog_write_event(log_, &e) != 0) throw Fail("writing the LCM log failed (disk full?)");
}

void Recorder::close() {
  if (log_) lcm_eventlog_destroy(log_);
  log_ = nullptr;
}

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

bool interrupted() { return g_interrupted != 0; }

std::string utc_stamp() {
  char b[32];
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(b, sizeof b, "%Y%m%dT%H%M%SZ", &tm);
  return b;
}

fs::path self_dir() {
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::current_path() : p.parent_path();
}

fs::path create_output_dir(const std::string& requested, const std::string& name, std::error_code& ec) {
  ec.clear();
  fs::path out = requested.empty() ? fs::path("out") / (name + "-" + utc_stamp()) : fs::path(requested);
  if (requested.empty()) {  // a fresh folder, also when runs start in the same second
    fs::create_directories(out.parent_path(), ec);
    const std::string stem = out.string();
    for (int i = 2; !ec && !fs::create_directory(out, ec) && i < 10000; ++i) out = stem + "-" + std::to_string(i);
  } else {
    fs::create_directories(out, ec);
  }
  return out;
}

}  // namespace ggins::hil
