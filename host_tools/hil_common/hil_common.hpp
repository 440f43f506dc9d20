// Plumbing shared by the host-in-the-loop runners `ggins run` (run/run_main.cpp)
// and `ggins run3d` (run3d/run3d_main.cpp): clocks, the Fail exception, child
// processes (hal_sim, lcm-logger, plotting), private LCM ports and run ids, the
// sensor frame message, the LCM event-log recorder, the interrupt flag and the
// output folder.
#pragma once

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <signal.h>
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "ggins/frame.h"
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
// /dev/null; throws Fail if it cannot be started.
pid_t spawn(const std::vector<std::string>& argv, const std::filesystem::path& log_path);

// Wait up to timeout_s for a child; returns its status or -1 if still running.
int wait_child(pid_t pid, double timeout_s);

// Send sig, wait grace_s, then SIGKILL; pid becomes -1.
void stop_child(pid_t& pid, int sig = SIGTERM, double grace_s = 1.0);

// The LCM message of a sensor frame of this run; attempts: transmissions of
// this seq before this one (sent as `resent`, saturated at 127).
ggins::sensor_frame_t sensor_frame_msg(const gg_frame_t& f, int64_t run_id, int attempts);

// hal_sim's command line common to both runners (callers append their own options).
std::vector<std::string> hal_sim_argv(const std::string& hal_sim, const std::string& url_to_hal,
                                      const std::string& url_from_hal, const std::string& prefix, int64_t run_id,
                                      int resend_timeout_ms);

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
