// Plumbing shared by the host-in-the-loop runners `ggins run` (run/run_main.cpp)
// and `ggins run3d` (run3d/run3d_main.cpp): clocks, the Fail exception, child
// processes (hal_sim, lcm-logger, plotting), private LCM ports and run ids, the
// sensor frame message, the LCM event-log recorder, the interrupt flag, the
// output folder, and the run's bus authentication (BusAuth: key, MAC, checks).
#pragma once

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <signal.h>
#include <sys/types.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "bus_auth.h"
#include "ggins/frame.h"
#include "ggins/hal_status_t.hpp"
#include "ggins/sensor_frame_t.hpp"

namespace ggins::hil {

// Monotonic seconds (timeouts) and wall-clock microseconds (message utime).
double mono_s();
int64_t wall_us();

// A run failure with its exit status (1 failed, 2 bad arguments, 3 no multicast on loopback, 130 interrupted).
struct Fail : std::runtime_error {
  int code;
  Fail(const std::string& m, int c = 1) : std::runtime_error(m), code(c) {}
};

// Split a long double into the hi + lo pair of doubles that the LCM messages carry.
template <class R>
void hilo(R x, double& hi, double& lo) {
  hi = static_cast<double>(x);
  lo = static_cast<double>(x - static_cast<R>(hi));
}

// Free UDP ports right now (the kernel's choice, all different); LCM's
// multicast sockets on them are then private to this run, so parallel runs do
// not cross-talk. Empty if n ports could not be had.
std::vector<int> free_udp_ports(int n);

// A fresh random run id (>= 0) tagging every message of this run.
int64_t new_run_id();

// Start argv[0] (PATH lookup) with stdout and stderr to log_path, stdin from
// /dev/null; throws Fail if it cannot be started. own_group: the child leads a
// process group of its own (a terminal's SIGINT to this process's group does
// not reach it; this process stops it in order). inherit: descriptors of this
// process given to the child, as (fd here, fd number in the child).
pid_t spawn(const std::vector<std::string>& argv, const std::filesystem::path& log_path,
            const std::vector<std::pair<int, int>>& inherit = {}, bool own_group = false);

// Wait up to timeout_s for a child; returns its status or -1 if still running.
int wait_child(pid_t pid, double timeout_s);

// Send sig, wait grace_s, then SIGKILL; pid becomes -1.
void stop_child(pid_t& pid, int sig = SIGTERM, double grace_s = 1.0);

// The LCM message of a sensor frame of this run; attempts: transmissions of
// this seq before this one (sent as `resent`, saturated at 127).
ggins::sensor_frame_t sensor_frame_msg(const gg_frame_t& f, int64_t run_id, int attempts);

// hal_sim's command line common to both runners (callers append their own
// options); the key travels on descriptor kHalKeyFd (spawn_hal_sim).
std::vector<std::string> hal_sim_argv(const std::string& hal_sim, const std::string& url_to_hal,
                                      const std::string& url_from_hal, const std::string& prefix, int64_t run_id,
                                      int resend_timeout_ms);

// Descriptor number on which hal_sim receives the run's key.
constexpr int kHalKeyFd = 3;

// The run's bus authentication (hal_sim/bus_auth.h): a fresh random key per
// run, signing of what this process publishes, and the checks on what it
// receives. The key lives only in this object (wiped on destruction) and in
// hal_sim, which gets it through a pipe on kHalKeyFd (spawn_hal_sim).
class BusAuth {
 public:
  BusAuth();  // throws Fail if libsodium cannot be initialised
  ~BusAuth() { ggins_bus_key_wipe(&key_); }
  BusAuth(const BusAuth&) = delete;
  BusAuth& operator=(const BusAuth&) = delete;

  // Sign an encoded message of this run in place (its last 32 bytes, the mac field).
  void sign(const std::string& channel, uint8_t* buf, int n) const;

  enum class Check { kOk, kUndecodable, kForeign, kUnauthenticated };
  // Decode a received message into m and check it: it decodes to exactly its
  // size, carries run_id, and its MAC verifies. kUnauthenticated is counted
  // per channel (rejected()).
  template <class M>
  Check check(const std::string& channel, const void* data, uint32_t size, int64_t run_id, M& m) {
    const int d = m.decode(data, 0, static_cast<int>(size));
    if (d < 0 || static_cast<uint32_t>(d) != size) return Check::kUndecodable;
    if (m.run_id != run_id) return Check::kForeign;
    if (ggins_bus_verify(&key_, channel.c_str(), static_cast<const uint8_t*>(data), size) != 0) {
      ++rejected_[channel];
      return Check::kUnauthenticated;
    }
    return Check::kOk;
  }

  // Start hal_sim with the key on kHalKeyFd (a pipe holding exactly the key).
  pid_t spawn_hal_sim(const std::vector<std::string>& argv, const std::filesystem::path& log_path) const;

  const std::map<std::string, int64_t>& rejected() const { return rejected_; }

 private:
  ggins_bus_key_t key_{};
  std::map<std::string, int64_t> rejected_;
};

// Whether two messages have the same content: equal encodings with the MAC
// zeroed (the caller zeroes the transport fields, resent / republished).
template <class M>
bool same_content(M a, M b) {
  std::fill(std::begin(a.mac), std::end(a.mac), 0);
  std::fill(std::begin(b.mac), std::end(b.mac), 0);
  std::vector<uint8_t> x(static_cast<size_t>(a.getEncodedSize())), y(static_cast<size_t>(b.getEncodedSize()));
  a.encode(x.data(), 0, static_cast<int>(x.size()));
  b.encode(y.data(), 0, static_cast<int>(y.size()));
  return x == y;
}

// The messages taken for the last `n` seqs (a ring): whether a second message
// for a seq is a repeat of the first or a conflict. Compared only when a
// second copy comes; taking a message costs one copy.
template <class M>
class SeqCopies {
 public:
  explicit SeqCopies(size_t n = 8192) : seq_(n, -1), m_(n) {}
  void put(int64_t seq, const M& m) {
    if (seq < 0) return;
    const size_t i = static_cast<size_t>(seq) % seq_.size();
    seq_[i] = seq;
    m_[i] = m;
  }
  // +1 the same as the one kept, -1 different (a conflict), 0 not kept
  int compare(int64_t seq, const M& m) const {
    if (seq < 0) return 0;
    const size_t i = static_cast<size_t>(seq) % seq_.size();
    if (seq_[i] != seq) return 0;
    return same_content(m_[i], m) ? 1 : -1;
  }

 private:
  std::vector<int64_t> seq_;
  std::vector<M> m_;
};

// summary.json "bus_auth": how messages are authenticated; the messages of this
// run whose MAC failed, per channel (this process's counts and hal_sim's last
// status: ch_frame, ch_config, ch_control); the conflicts (two different
// authenticated messages for one seq) and their total; other runs' messages.
nlohmann::json bus_auth_summary(const BusAuth& auth, const ggins::hal_status_t* hal, const std::string& ch_frame,
                                const std::string& ch_config, const std::string& ch_control, int64_t outputs_conflict,
                                int64_t status_conflict, int64_t foreign);

// lcm_handle_timeout for up to timeout_s (rounded up to ms); throws Fail on an error other than EINTR.
void handle_lcm(lcm_t* lcm, double timeout_s);

// LCM log written by the runner itself: every message it publishes and every
// message it receives on the run's channels, in the LCM event-log format
// (lcm-logplayer plays it). Nothing can be dropped between the wire and the
// file, unlike a separate lcm-logger that must keep up with ~10^4 messages/s.
class Recorder {
 public:
  explicit Recorder(const std::filesystem::path& p);
  ~Recorder() { close(); }
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;
  void write(const std::string& ch, const void* data, int len, int64_t utime);
  void close();

 private:
  lcm_eventlog_t* log_ = nullptr;
  int64_t n_ = 0;
};

// SIGINT/SIGTERM set the interrupt flag (interrupted()); SIGPIPE is ignored.
void install_interrupt_handlers();
bool interrupted();

// UTC time stamp for folder names, e.g. 20260101T120000Z.
std::string utc_stamp();

// The folder of this executable (hal_sim is looked for beside it).
std::filesystem::path self_dir();

// The output folder: `requested` if given (created with its parents), else a
// fresh out/<name>-<UTC>[-N] (also when runs start in the same second). On
// failure ec is set and the folder tried is returned.
std::filesystem::path create_output_dir(const std::string& requested, const std::string& name, std::error_code& ec);

}  // namespace ggins::hil
