// The host-in-the-loop transport, written once for both runners (`ggins run`,
// 2-D, and `ggins run3d`, 3-D): a Link<Task> owns the LCM bus of one run, the
// run's key, its LCM log, the hal_sim process (start, configuration, START,
// STOP, its status) and the flow of frames and outputs; the runner gives it
// two functions, one that makes frame k (make_frame) and one that takes the
// output of step k (on_output), and keeps the evaluation.
//
// Batched, pipelined lockstep. Frames go out several per message
// (frame_batch_t on P+FRAMES) with a window of frames in flight; hal_sim steps
// every frame once, in seq order, and returns the outputs in batches
// (nav_output_batch_t / nav3d_output_batch_t). on_output is called once per
// step, in seq order, whatever the transport did (an output is held until
// every earlier one has come), so a run is the same bit for bit however many
// messages were lost, repeated or reordered, and the same as --direct.
//
// Window. Without a fixed --window, the window covers the round trip: it is
// kWindowRtts times the smoothed round trip (frame batch sent -> its output
// received; it includes the machine's scheduling delays) divided by the time
// the runner spends per frame (making it and taking its output), between 4
// batches and kMaxWindow. When hal_sim is the slower side, frames queue
// there, the round trip grows and so does the window, up to kMaxWindow.
//
// Fast recovery. A frame that is missing at hal_sim is asked for as soon as a
// later one arrives (negative acknowledgement, resend_request_t on P+NAK);
// an output that is missing here is known as soon as a later first publication
// arrives (hal_sim steps in seq order), and its frame is sent again (hal_sim
// answers a repeated frame with the output it keeps). Only the very last
// messages of a run, whose loss nothing later can reveal, wait for a timeout
// (a few round trips). The resends of one seq back off (want_resend), so a
// process descheduled for a while is not mistaken for a loss.
//
// Redundancy after a loss. Once a loss is known (a negative acknowledgement,
// an output gap, a timeout), for the next kRedSpan steps every frame batch
// also re-carries, first, the frames of the previous batch whose outputs have
// not come back (resent = -1); when the window is full those copies go out at
// once in a batch of their own. hal_sim does the same with its outputs
// (republished = -1) after a loss on its side. A lost frame or output is then
// usually recovered from its copy, without a round trip: hal_sim asks
// (negative acknowledgement) only for a frame whose copy did not come either,
// and this side asks for a lost output (run_control_t OUTPUT_COPIES: hal_sim
// publishes it again from its ring; cheaper than resending the frame) only
// when the next output batch did not carry it. Copies are ordinary items of
// signed batches (one MAC per message, whatever it carries).
//
// Real time (--realtime): one frame per message at its scheduled time (start
// + k dt); the lateness of each send against its schedule and the output
// latency (first send -> output received) are measured against a deadline:
// one sensor period plus an allowance for the host's scheduling and the bus
// (--deadline-allowance-ms, default kDeadlineAllowanceS), or --deadline-ms.
// An output later than the deadline, or never received, is an overrun; a run
// with overruns is degraded (runner.hpp).
//
// Every message carries its MAC (BusAuth); a second, different authenticated
// output for one seq is a conflict (counted, never taken).
#pragma once

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ggins/frame_batch_t.hpp"
#include "ggins/hal_status_t.hpp"
#include "ggins/nav2d_config_t.hpp"
#include "ggins/nav3d_config_t.hpp"
#include "ggins/nav3d_output_batch_t.hpp"
#include "ggins/nav3d_output_t.hpp"
#include "ggins/nav_output_batch_t.hpp"
#include "ggins/nav_output_t.hpp"
#include "ggins/resend_request_t.hpp"
#include "ggins/run_control_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "hil_common.hpp"

namespace ggins::hil {

// The two tasks: message types and channel names.
struct Task2D {
  using Out = ggins::nav_output_t;
  using OutBatch = ggins::nav_output_batch_t;
  using Config = ggins::nav2d_config_t;
  static constexpr const char* kName = "2-D";
  static constexpr const char* kNav = "NAV";
  static constexpr const char* kNavs = "NAVS";
  static constexpr const char* kConfig = "CONFIG";
};
struct Task3D {
  using Out = ggins::nav3d_output_t;
  using OutBatch = ggins::nav3d_output_batch_t;
  using Config = ggins::nav3d_config_t;
  static constexpr const char* kName = "3-D";
  static constexpr const char* kNav = "NAV3D";
  static constexpr const char* kNavs = "NAV3DS";
  static constexpr const char* kConfig = "CONFIG3D";
};

// Transport faults injected by the sender (frames) and by hal_sim (outputs);
// each decision is a pure function of (seed, kind, seq, transmission), so a
// run's faults repeat exactly.
struct Faults {
  double drop = 0, dup = 0, reorder = 0, drop_output = 0, garbage = 0, conflict = 0;
  uint64_t seed = 1;
};

// A uniform deviate in [0, 1), a pure function of its inputs (splitmix64 finaliser).
double fault_uniform(uint64_t seed, uint64_t kind, uint64_t seq, uint64_t attempt);

struct LinkOptions {
  std::string tool = "ggins run";  // for messages
  std::string hal_sim, prefix = "GGINS_", lcm_url;
  std::string log_mode = "internal";  // internal | lcm-logger | none
  std::string logger;                 // lcm-logger executable (log_mode lcm-logger)
  int resend_timeout_ms = 50, max_resend = 100;
  int batch = 0, window = 0;  // frames per message, frames in flight; 0: automatic
  bool realtime = false;
  double deadline_s = 0;  // real time: output deadline (0: one sensor period + deadline_allowance_s)
  double deadline_allowance_s = -1;  // real time: allowance over one sensor period (< 0: kDeadlineAllowanceS)
  Faults faults;
  std::vector<std::string> hal_args;  // more hal_sim options (e.g. --map FILE: the computer's map storage)
};

// Real time: the default allowance of the output deadline over one sensor period, s:
// the host's scheduling (a loaded machine delays a process by tens of ms) and the
// recovery of a lost frame (hal_sim notices the gap at the next frame and asks
// for it again), with margin; a stalled firmware process (seconds) exceeds it.
constexpr double kDeadlineAllowanceS = 0.1;

// Order statistics of a sample (median / p99 / max), exact.
nlohmann::json percentiles_json(std::vector<double> v, double scale = 1.0);

// Process-independent part of the Link (non-template): LCM bus, key, log,
// hal_sim, status, control.
class LinkBase {
 public:
  LinkBase(const LinkOptions& o, std::filesystem::path out, int64_t n_steps, int64_t dt_us);
  virtual ~LinkBase();
  LinkBase(const LinkBase&) = delete;
  LinkBase& operator=(const LinkBase&) = delete;

  std::string channel(const std::string& name) const { return opt_.prefix + name; }
  const std::string& url_to_hal() const { return url_; }
  const std::string& url_from_hal() const { return url_in_; }
  int64_t run_id() const { return run_id_; }

  // Sign, publish on the run's bus (toward hal_sim) and record.
  template <class M>
  void publish(const std::string& ch, const M& m) {
    const int n = m.encode(buf_.data(), 0, static_cast<int>(buf_.size()));
    publish_raw(ch, n, true);
  }
  // The messages of the run received so far, up to timeout_s (at least one wait).
  void handle(double timeout_s);
  // Everything queued now, without waiting.
  void handle_ready();
  // One message, waiting at most until t_abs (mono_s clock, sub-millisecond).
  void handle_until(double t_abs);
  void check_children();
  void send_control(int32_t cmd, uint64_t scenario_id);
  void finish();  // STOP until hal_sim says STOPPED, then wait for it
  void close_log();
  const std::optional<ggins::hal_status_t>& hal_status() const { return hal_; }
  // CPU seconds (user + system) hal_sim has used so far (/proc; -1 if unknown), and this process's.
  double hal_sim_cpu_s() const;
  static double cpu_s();
  nlohmann::json bus_auth_summary(int64_t outputs_conflict) const;
  nlohmann::json hal_sim_summary() const;

 protected:
  void open_bus(const std::string& config_channel);  // LCM, multicast check, log, hal_sim
  void publish_raw(const std::string& ch, int n, bool sign);
  template <class M>
  bool accept(const lcm_recv_buf_t* rb, const std::string& ch, M& m) {
    switch (auth_.check(ch, rb->data, rb->data_size, run_id_, m)) {
      case BusAuth::Check::kOk: record(rb, ch); return true;
      case BusAuth::Check::kUndecodable: record(rb, ch); ++decode_errors_; return false;
      case BusAuth::Check::kForeign: ++foreign_msgs_; return false;
      case BusAuth::Check::kUnauthenticated: record(rb, ch + ".UNAUTHENTICATED"); return false;
    }
    return false;
  }
  void record(const lcm_recv_buf_t* rb, const std::string& ch) {
    if (rec_) rec_->write(ch, rb->data, static_cast<int>(rb->data_size), rb->recv_utime);
  }
  static void on_hal_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<LinkBase*>(u)->on_hal(rb); }
  static void on_ping_cb(const lcm_recv_buf_t*, const char*, void* u) { static_cast<LinkBase*>(u)->pings_++; }
  void on_hal(const lcm_recv_buf_t* rb);
  void start_logger();

  LinkOptions opt_;
  std::filesystem::path out_;
  int64_t n_ = 0, dt_us_ = 0;
  std::string url_, url_in_;
  lcm_t *lcm_ = nullptr, *lcm_out_ = nullptr;
  int64_t run_id_ = 0;
  pid_t hal_pid_ = -1, logger_pid_ = -1;
  std::unique_ptr<Recorder> rec_;
  BusAuth auth_;
  std::vector<uint8_t> buf_ = std::vector<uint8_t>(1 << 18);
  std::string ch_frame_, ch_frames_, ch_control_, ch_hal_, ch_nak_, ch_request_, ch_ping_, ch_config_;
  std::optional<ggins::hal_status_t> hal_;
  int64_t status_conflict_ = 0, foreign_msgs_ = 0, decode_errors_ = 0, pings_ = 0, control_seq_ = 0;
  int64_t frames_published_ = 0, frame_messages_ = 0, garbage_inj_ = 0;
};

// The transport of one run of Task (Task2D or Task3D).
template <class Task>
class Link : public LinkBase {
 public:
  using Out = typename Task::Out;
  using MakeFrame = std::function<ggins::sensor_frame_t(int64_t k)>;
  using OnOutput = std::function<void(const Out&)>;
  using Progress = std::function<void(int64_t steps_done)>;

  Link(const LinkOptions& o, std::filesystem::path out, int64_t n_steps, int64_t dt_us)
      : LinkBase(o, std::move(out), n_steps, dt_us), taken_(kRing) {}

  // LCM, hal_sim, the configuration (sent until hal_sim reports it applied), START.
  void start(typename Task::Config cfg, uint64_t scenario_id) {
    scenario_id_ = scenario_id;
    open_bus(Task::kConfig);
    ch_nav_ = channel(Task::kNav);
    ch_navs_ = channel(Task::kNavs);
    lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_nav_.c_str(), on_nav_cb, this), 100000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_navs_.c_str(), on_navs_cb, this), 100000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_nak_.c_str(), on_nak_cb, this), 100000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch_request_.c_str(), on_req_cb, this), 100000);
    cfg.run_id = run_id_;
    const double end = mono_s() + 10.0;
    double next_send = 0;
    while (!(hal_ && hal_->config_seq == cfg.seq && hal_->state != ggins::hal_status_t::IDLE)) {
      if (hal_ && hal_->init_status > 0) break;
      if (mono_s() >= next_send) {
        cfg.utime = wall_us();
        publish(ch_config_, cfg);
        next_send = mono_s() + 0.1;
      }
      handle(0.02);
      check_children();
      if (mono_s() > end) throw Fail("hal_sim did not accept the configuration within 10 s");
    }
    if (hal_->init_status != 0)
      throw Fail("the firmware refused the configuration (" + std::string(Task::kName) + " init status " +
                 std::to_string(hal_->init_status) + ")");
    send_control(ggins::run_control_t::START, scenario_id_);
  }

  // The flight: every frame 0 .. n-1 made once, every output taken once, in order.
  void run(const MakeFrame& make, const OnOutput& take, const Progress& progress) {
    make_ = make;
    take_ = take;
    ring_.assign(kRing, Slot{});
    t_start_ = mono_s();
    cpu_start_ = cpu_s();
    try {
      if (opt_.realtime)
        loop_realtime(progress);
      else
        loop_lockstep(progress);
    } catch (...) {
      wall_ = mono_s() - t_start_;
      throw;
    }
    wall_ = mono_s() - t_start_;
    cpu_loop_ = cpu_s() - cpu_start_;
    hal_cpu_s_ = hal_sim_cpu_s();  // before STOP: the flight only
  }

  double wall_s() const { return wall_; }
  double cpu_s_runner() const { return cpu_loop_; }
  double cpu_s_hal_sim() const { return hal_cpu_s_; }
  int64_t outputs() const { return outputs_; }
  int64_t outputs_conflict() const { return outputs_conflict_; }
  int64_t frames_published() const { return frames_published_; }

  // summary.json "transport" (with hal_sim's counters) and, in real time, "realtime".
  nlohmann::json transport_summary() const {
    using nlohmann::json;
    json tr;
    tr["protocol"] = opt_.realtime ? "real time: one frame per message at its scheduled time"
                                   : "batched, pipelined lockstep (frame batches, output batches, negative acknowledgement)";
    tr["frames_published"] = frames_published_;
    tr["frame_messages"] = frame_messages_;
    tr["output_messages"] = output_messages_;
    tr["outputs_received"] = outputs_;
    tr["outputs_duplicate"] = outputs_dup_;
    tr["outputs_recovered"] = outputs_recovered_;
    tr["outputs_foreign"] = outputs_foreign_;
    tr["decode_errors"] = decode_errors_;
    tr["resend_timeouts"] = resend_timeouts_;
    tr["resends_on_request"] = resend_on_request_;
    tr["resends_on_output_gap"] = resend_on_gap_;
    {
      json r;
      r["definition"] =
          "redundancy after a loss: for span_steps after a known loss each frame batch re-carries the previous "
          "batch's frames whose outputs have not come (resent = -1), and hal_sim each output batch the previous "
          "batch's outputs (republished = -1); a lost item is asked for only when its copy was lost too (frames: "
          "hal_sim's negative acknowledgement; outputs: OUTPUT_COPIES requests)";
      r["span_steps"] = kRedSpan;
      r["steps_redundant"] = steps_redundant_;
      r["frame_copies_sent"] = frame_copies_;
      r["frame_copy_batches"] = copy_batches_;
      r["outputs_from_copies"] = outputs_from_copies_;
      r["outputs_from_answers"] = outputs_from_answers_;
      r["output_gaps_deferred"] = gaps_deferred_;
      r["output_copy_requests"] = copy_requests_;
      r["outputs_requested"] = outputs_requested_;
      if (hal_) {
        r["hal_sim_frame_copies_received"] = hal_->frame_copies_received;
        r["hal_sim_frames_from_copies"] = hal_->frames_from_copies;
        r["hal_sim_naks_deferred"] = hal_->naks_deferred;
        r["hal_sim_output_copy_requests"] = hal_->output_copy_requests;
        r["hal_sim_output_copies_sent"] = hal_->output_copies_sent;
        r["hal_sim_output_copies_dropped_injected"] = hal_->output_copies_dropped_injected;
      }
      tr["redundancy"] = r;
    }
    tr["nak_received"] = naks_;
    tr["batch_frames"] = batch_;
    tr["window_full"] = {{"waits", blocked_}, {"wait_s", blocked_s_}};  // the runner waited for outputs
    tr["window_frames"] = {{"final", window_}, {"max", window_max_}, {"automatic", opt_.window <= 0}};
    tr["round_trip_us"] = {{"min", rtt_min_ < 1e9 ? rtt_min_ * 1e6 : 0.0}, {"smoothed", srtt_ * 1e6}};
    tr["runner_us_per_frame"] = t_frame_ * 1e6;
    {  // CPU time of each process per step
      const double nf = static_cast<double>(std::max<int64_t>(outputs_, 1));
      json c;
      c["runner"] = 1e6 * cpu_loop_ / nf;
      if (hal_cpu_s_ >= 0) {
        const double step = fw_ns_ * 1e-9;
        c["hal_sim"] = 1e6 * hal_cpu_s_ / nf;
        c["hal_sim_firmware_step"] = 1e6 * step / nf;
        c["hal_sim_transport"] = 1e6 * (hal_cpu_s_ - step) / nf;
      }
      c["definition"] =
          "microseconds of CPU (user + system) per step during the flight: the runner (making frames, taking "
          "outputs, transport), hal_sim (10 ms ticks), of which the firmware steps (cycles[TOTAL]) and the rest "
          "(hal_sim's transport). The runner's transport share: runner less the runner's CPU with --direct less "
          "the firmware steps there (scripts/bench-rig)";
      tr["cpu_us_per_step"] = c;
    }
    tr["injected"] = {{"dropped", dropped_inj_},     {"dropped_copies", dropped_copies_inj_}, {"duplicated", dup_inj_}, {"duplicated_copies", dup_copies_inj_},       {"reordered", reordered_inj_},
                      {"garbage", garbage_inj_},     {"conflicting", conflict_inj_}, {"output_drop_prob", opt_.faults.drop_output}};
    if (hal_) tr["hal_sim"] = hal_sim_summary();
    return tr;
  }
  // The run's LCM log read back: events per channel, the frames and outputs in it (alone or in batches).
  nlohmann::json verify_log(const std::string& ch_truth, int64_t truth_published) const {
    using nlohmann::json;
    json j;
    const std::filesystem::path p = out_ / "run.lcmlog";
    j["path"] = p.string();
    lcm_eventlog_t* log = lcm_eventlog_create(p.c_str(), "r");
    if (!log) {
      j["error"] = "cannot open";
      j["complete"] = false;
      return j;
    }
    std::map<std::string, int64_t> per;
    int64_t n = 0, frame_items = 0;
    std::vector<uint8_t> seen(static_cast<size_t>(n_), 0);
    auto see = [&](const Out& m) {
      if (m.run_id == run_id_ && m.seq >= 0 && m.seq < n_) seen[static_cast<size_t>(m.seq)] = 1;
    };
    for (lcm_eventlog_event_t* e; (e = lcm_eventlog_read_next_event(log)) != nullptr; lcm_eventlog_free_event(e)) {
      ++n;
      const std::string ch(e->channel, static_cast<size_t>(e->channellen));
      ++per[ch];
      if (ch == ch_nav_) {
        Out m{};
        if (m.decode(e->data, 0, static_cast<int>(e->datalen)) >= 0) see(m);
      } else if (ch == ch_navs_) {
        typename Task::OutBatch b{};
        if (b.decode(e->data, 0, static_cast<int>(e->datalen)) >= 0)
          for (const Out& m : b.outputs) see(m);
      } else if (ch == ch_frames_) {
        ggins::frame_batch_t b{};
        if (b.decode(e->data, 0, static_cast<int>(e->datalen)) >= 0) frame_items += b.n;
      }
    }
    lcm_eventlog_destroy(log);
    const int64_t unique = std::count(seen.begin(), seen.end(), 1);
    j["events"] = n;
    j["per_channel"] = per;
    j["frames_expected"] = frames_published_;
    j["frames_in_log"] = frame_items;
    j["nav_outputs_unique"] = unique;
    j["complete"] = frame_items >= frames_published_ && per[ch_truth] == truth_published && unique == outputs_ &&
                    per[ch_frame_] >= (opt_.log_mode == "internal" ? garbage_inj_ : 0);
    return j;
  }

  nlohmann::json realtime_summary() const {
    using nlohmann::json;
    const double dt = static_cast<double>(dt_us_) * 1e-6;
    const double allowance = opt_.deadline_allowance_s >= 0 ? opt_.deadline_allowance_s : kDeadlineAllowanceS;
    const double dl = opt_.deadline_s > 0 ? opt_.deadline_s : dt + allowance;
    int64_t over = 0, over_period = 0;
    std::vector<double> lat;
    lat.reserve(static_cast<size_t>(n_));
    for (int64_t k = 0; k < n_; ++k) {
      const double l = latency_[static_cast<size_t>(k)];
      if (!(l >= 0) || l > dl) ++over;  // never received counts as an overrun
      if (!(l >= 0) || l > dt) ++over_period;
      if (l >= 0) lat.push_back(l);
    }
    json j;
    j["lateness_definition"] = "frame k published at t_start + k dt + lateness (the step's schedule)";
    j["lateness_us"] = percentiles_json(lateness_, 1e6);
    j["output_latency_definition"] = "first transmission of frame k -> its output received by the runner";
    j["output_latency_us"] = percentiles_json(lat, 1e6);
    j["deadline_us"] = dl * 1e6;
    if (opt_.deadline_s > 0) {
      j["deadline_definition"] = "--deadline-ms";
    } else {
      j["deadline_definition"] = "one sensor period + allowance (--deadline-allowance-ms)";
      j["deadline_allowance_us"] = allowance * 1e6;
    }
    j["deadline_overruns"] = over;
    j["outputs_over_one_period"] = over_period;
    j["outputs_never_received"] = static_cast<int64_t>(n_) - static_cast<int64_t>(lat.size());
    return j;
  }

 private:
  static constexpr int64_t kRing = 8192;       // seqs held (frames for resends, outputs until their turn)
  static constexpr int64_t kMaxWindow = 4096;  // < hal_sim's reorder window (8192); <= kRing / 2
  static constexpr double kWindowRtts = 4.0;
  static constexpr int kDefaultBatch = 32;
  static constexpr int64_t kRedSpan = 8192;  // steps of redundancy after a known loss

  struct Slot {
    int64_t seq = -1;
    ggins::sensor_frame_t msg{};
    double t_first = -1, t_last = -1;  // first / last transmission
    double t_resend = -1;              // last resend asked for (request, gap or timeout)
    int resends = 0;                   // resends of this seq so far
    int attempts = 0;                  // first transmission and resends
    int tx = 0;                        // transmissions, redundant copies included (fault-injection index)
    int64_t gap_msg = -1;              // output messages received when its output was first seen missing
    double t_gap = -1;                 // ... and when
    bool got = false;
    Out out{};
  };
  Slot& slot(int64_t k) { return ring_[static_cast<size_t>(k & (kRing - 1))]; }

  static void on_nav_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Link*>(u)->on_nav(rb); }
  static void on_navs_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Link*>(u)->on_navs(rb); }
  static void on_nak_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Link*>(u)->on_nak(rb); }
  static void on_req_cb(const lcm_recv_buf_t* rb, const char*, void* u) { static_cast<Link*>(u)->on_req(rb); }

  void on_nav(const lcm_recv_buf_t* rb) {
    Out m{};
    const int64_t f0 = foreign_msgs_;
    if (!accept(rb, ch_nav_, m)) {
      outputs_foreign_ += foreign_msgs_ - f0;
      return;
    }
    ++output_messages_;
    take_output(m, mono_s());
    output_gaps(mono_s());
  }
  void on_navs(const lcm_recv_buf_t* rb) {
    typename Task::OutBatch b{};
    const int64_t f0 = foreign_msgs_;
    if (!accept(rb, ch_navs_, b)) {
      outputs_foreign_ += foreign_msgs_ - f0;
      return;
    }
    ++output_messages_;
    const double now = mono_s();
    for (const Out& m : b.outputs) {
      if (m.run_id != run_id_) {
        ++outputs_foreign_;
        ++foreign_msgs_;
        continue;
      }
      if (m.republished < 0) last_copy_msg_ = output_messages_;
      take_output(m, now);
    }
    output_gaps(now);
  }
  void take_output(const Out& m, double now) {
    Out plain = m;
    plain.republished = 0;  // transport: differs between copies of one output
    std::fill(std::begin(plain.mac), std::end(plain.mac), 0);
    const int64_t k = m.seq;
    if (k < 0 || k >= n_ || k < base_ || k >= next_ || slot(k).got) {
      if (taken_.compare(k, plain) < 0) {
        ++outputs_conflict_;
        if (outputs_conflict_ <= 10)
          std::fprintf(stderr, "%s: conflict: a second authenticated output for step %lld differs from the first\n",
                       opt_.tool.c_str(), static_cast<long long>(k));
      } else {
        ++outputs_dup_;
      }
      return;
    }
    Slot& s = slot(k);
    s.got = true;
    s.out = plain;
    if (m.n_cycles > GG_MOD_TOTAL) fw_ns_ += static_cast<double>(static_cast<uint32_t>(m.cycles[GG_MOD_TOTAL]));
    taken_.put(k, plain);
    ++outputs_;
    if (s.attempts > 1 || m.republished != 0) ++outputs_recovered_;
    if (m.republished < 0) ++outputs_from_copies_;
    if (m.republished > 0) ++outputs_from_answers_;
    if (opt_.realtime) latency_[static_cast<size_t>(k)] = now - s.t_first;
    if (s.attempts == 1 && m.republished == 0) {  // round trip of a frame sent once
      const double rtt = now - s.t_first;
      rtt_min_ = std::min(rtt_min_, rtt);
      srtt_ = srtt_ > 0 ? 0.875 * srtt_ + 0.125 * rtt : rtt;
    }
    if (m.republished == 0 && k > max_first_) max_first_ = k;
    last_progress_ = now;
  }
  // hal_sim steps in seq order and publishes the outputs in that order: an
  // output below the highest first publication that is not here was lost on
  // the way (or its answer to a request was). While hal_sim re-carries its
  // outputs, the next output message brings its copy; when that did not (or
  // after a timeout) it is asked for (OUTPUT_COPIES), and hal_sim publishes
  // it again from its ring.
  void output_gaps(double now) {
    const bool hal_red = last_copy_msg_ >= 0 && output_messages_ - last_copy_msg_ <= 2;
    for (int64_t j = std::max(scanned_, base_); j < max_first_; ++j)  // newly below the highest first publication
      if (!slot(j).got) missing_.push_back(j);
    scanned_ = std::max(scanned_, max_first_);
    size_t keep = 0;
    for (size_t i = 0; i < missing_.size(); ++i) {
      const int64_t j = missing_[i];
      Slot& s = slot(j);
      if (j < base_ || s.got) continue;
      missing_[keep++] = j;
      if (s.gap_msg < 0) {
        s.gap_msg = output_messages_;
        s.t_gap = now;
        red_until_ = next_ + kRedSpan;
        if (hal_red) {
          ++gaps_deferred_;
          continue;
        }
      } else if (hal_red && output_messages_ <= s.gap_msg && now - s.t_gap < rto()) {
        continue;  // its copy is still on the way
      }
      if (want_resend(j, now)) {
        ++resend_on_gap_;
        copies_wanted_.push_back(j);
      }
    }
    missing_.resize(keep);
  }
  // The outputs asked for, as OUTPUT_COPIES requests of contiguous ranges.
  void request_output_copies() {
    if (copies_wanted_.empty()) return;
    std::sort(copies_wanted_.begin(), copies_wanted_.end());
    copies_wanted_.erase(std::unique(copies_wanted_.begin(), copies_wanted_.end()), copies_wanted_.end());
    size_t i = 0;
    while (i < copies_wanted_.size()) {
      size_t e = i + 1;
      while (e < copies_wanted_.size() && copies_wanted_[e] == copies_wanted_[e - 1] + 1) ++e;
      ggins::run_control_t c{};
      c.utime = wall_us();
      c.seq = control_seq_++;
      c.run_id = run_id_;
      c.command = ggins::run_control_t::OUTPUT_COPIES;
      c.scenario_id = static_cast<int64_t>(scenario_id_);
      c.resend_seq = copies_wanted_[i];
      c.n_steps = static_cast<int64_t>(e - i);
      c.realtime = opt_.realtime ? 1 : 0;
      publish(ch_control_, c);
      ++copy_requests_;
      outputs_requested_ += static_cast<int64_t>(e - i);
      i = e;
    }
    copies_wanted_.clear();
  }
  void on_nak(const lcm_recv_buf_t* rb) {
    ggins::resend_request_t m{};
    if (!accept(rb, ch_nak_, m)) return;
    ++naks_;
    const double now = mono_s();
    red_until_ = next_ + kRedSpan;
    for (int i = 0; i < m.n && i < static_cast<int>(m.count.size()); ++i)
      for (int64_t j = std::max(m.first[static_cast<size_t>(i)], base_);
           j < std::min(m.first[static_cast<size_t>(i)] + m.count[static_cast<size_t>(i)], next_); ++j)
        if (!slot(j).got && want_resend(j, now)) {
          ++resend_on_request_;
          resend_.push_back(j);
        }
  }
  void on_req(const lcm_recv_buf_t* rb) {  // a single RESEND request (older hal_sim protocol)
    ggins::run_control_t m{};
    if (!accept(rb, ch_request_, m)) return;
    if (m.command != ggins::run_control_t::RESEND) return;
    const int64_t j = m.resend_seq;
    if (j >= base_ && j < next_ && !slot(j).got && want_resend(j, mono_s())) {
      ++resend_on_request_;
      resend_.push_back(j);
    }
  }
  // Not sent again within half hal_sim's re-request interval (one request, one resend).
  // Backing off: the n-th resend of one seq waits 2^min(n, 6) half re-request
  // intervals after the previous one (1, 2, 4 .. 64 ms), so that a process
  // descheduled for a while on a busy machine is not taken for a lost frame.
  bool want_resend(int64_t j, double now) {
    Slot& s = slot(j);
    if (s.seq != j) return false;
    const double wait = 0.5 * gap_interval_s() * static_cast<double>(1 << std::min(s.resends, 6));
    if (s.t_resend >= 0 && now - s.t_resend < wait) return false;
    s.t_resend = now;  // reserved: sent with the next batch
    ++s.resends;
    return true;
  }
  double gap_interval_s() const { return 1e-3 * std::max(2, opt_.resend_timeout_ms / 25); }

  // ---- sending
  // Frame k (its stored message) into the batch under construction, through
  // the fault injection; copy: a redundant copy (resent = -1), not a resend.
  void emit(int64_t k, bool copy = false) {
    Slot& s = slot(k);
    const auto ua = static_cast<uint64_t>(s.tx);
    const auto uk = static_cast<uint64_t>(k);
    if (s.attempts >= opt_.max_resend + 1)
      throw Fail("no navigation output for step " + std::to_string(k) + " after " + std::to_string(opt_.max_resend) +
                 " resends; see " + (out_ / "hal_sim.log").string());
    ggins::sensor_frame_t m = s.msg;
    if (copy) {
      m.resent = -1;
      ++frame_copies_;
    } else {
      m.resent = static_cast<int8_t>(std::min(s.attempts, 127));
      ++s.attempts;
    }
    ++s.tx;
    pending_seqs_.push_back(k);
    const Faults& f = opt_.faults;
    if (f.garbage > 0 && fault_uniform(f.seed, 13, uk, ua) < f.garbage) publish_garbage(m);
    if (f.drop > 0 && fault_uniform(f.seed, 10, uk, ua) < f.drop) {
      ++dropped_inj_;
      if (copy) ++dropped_copies_inj_;
      return;
    }
    batch_msgs_.push_back(m);
    if (f.dup > 0 && fault_uniform(f.seed, 11, uk, ua) < f.dup) {
      batch_msgs_.push_back(m);
      ++dup_inj_;
      if (copy) ++dup_copies_inj_;
    }
    if (f.conflict > 0 && fault_uniform(f.seed, 14, uk, ua) < f.conflict) {
      ggins::sensor_frame_t other = m;  // a sender contradicting itself: a different frame, correctly signed
      other.f[0][0] += 1e-9;
      batch_msgs_.push_back(other);
      ++conflict_inj_;
    }
  }
  // An undecodable payload on the frame channel: alternately a truncated frame
  // and a message of another type.
  void publish_garbage(const ggins::sensor_frame_t& m) {
    int n;
    if ((garbage_inj_ & 1) == 0) {
      n = m.encode(buf_.data(), 0, static_cast<int>(buf_.size())) / 2;
    } else {
      ggins::run_control_t wrong{};
      wrong.seq = m.seq;
      wrong.run_id = run_id_;
      n = wrong.encode(buf_.data(), 0, static_cast<int>(buf_.size()));
    }
    ++garbage_inj_;
    publish_raw(ch_frame_, n, false);
  }
  // The batch under construction goes out as one signed message.
  void flush() {
    const double now = mono_s();
    for (int64_t k : pending_seqs_) {
      Slot& s = slot(k);
      if (s.t_first < 0) s.t_first = now;
      s.t_last = now;
    }
    pending_seqs_.clear();
    if (batch_msgs_.empty()) return;
    ggins::frame_batch_t b{};
    b.utime = wall_us();
    b.seq = batch_seq_++;
    b.run_id = run_id_;
    b.n = static_cast<int32_t>(batch_msgs_.size());
    b.frames.swap(batch_msgs_);
    frames_published_ += b.n;
    ++frame_messages_;
    publish(ch_frames_, b);
    b.frames.swap(batch_msgs_);
    batch_msgs_.clear();
  }
  // Resends asked for while a batch is being made: in a message of their own, now.
  void flush_resends_now() {
    if (resend_.empty()) return;
    std::vector<ggins::sensor_frame_t> held;
    std::vector<int64_t> held_seqs;
    held.swap(batch_msgs_);
    held_seqs.swap(pending_seqs_);
    flush_resends();
    batch_msgs_.swap(held);
    pending_seqs_.swap(held_seqs);
  }
  void flush_resends() {
    request_output_copies();
    if (resend_.empty()) return;
    std::sort(resend_.begin(), resend_.end());
    resend_.erase(std::unique(resend_.begin(), resend_.end()), resend_.end());
    std::vector<int64_t> r;
    r.swap(resend_);
    for (int64_t k : r)
      if (k >= base_ && !slot(k).got) {
        emit(k);
        if (static_cast<int>(batch_msgs_.size()) >= 2 * batch_) flush();
      }
    flush();
  }
  void make(int64_t k) {
    Slot& s = slot(k);
    s = Slot{};
    s.seq = k;
    s.msg = make_(k);
    std::fill(std::begin(s.msg.mac), std::end(s.msg.mac), 0);
  }
  // Outputs whose turn has come, to the runner, in seq order.
  void deliver() {
    while (base_ < next_ && slot(base_).got) {
      const double a = mono_s();
      take_(slot(base_).out);
      t_take_ += mono_s() - a;
      ++base_;
    }
  }
  // Timeout for what nothing later can reveal (the last messages of a run):
  // four smoothed round trips, at least 10 ms (a busy machine descheduling
  // hal_sim for a few ms is no loss), at most --resend-timeout-ms.
  double rto() const {
    const double hi = 1e-3 * opt_.resend_timeout_ms;
    const double r = srtt_ > 0 ? 4.0 * srtt_ : hi;
    return std::clamp(r, std::min(10e-3, hi), hi);
  }
  // Nothing heard for a timeout while outputs are missing: the first missing
  // frames again (their loss had nothing later to reveal it).
  void on_timeout() {
    check_children();
    int c = 0;
    const double now = mono_s();
    red_until_ = next_ + kRedSpan;
    for (int64_t k = base_; k < next_ && c < batch_; ++k)
      if (!slot(k).got && want_resend(k, now)) {
        ++resend_timeouts_;
        emit(k);
        ++c;
      }
    flush();
    last_progress_ = mono_s();
  }
  // Redundant copies of the previous batch's frames whose outputs have not come.
  void emit_copies() {
    for (int64_t k = std::max(prev_lo_, base_); k < prev_hi_; ++k)
      if (!slot(k).got) emit(k, true);
    prev_lo_ = prev_hi_;
  }
  void update_window() {
    if (opt_.window > 0) return;
    const int64_t made = std::max<int64_t>(next_, 1);
    t_frame_ = (t_make_ + t_take_) / static_cast<double>(made);
    if (srtt_ > 0 && t_frame_ > 0) {
      const double w = kWindowRtts * srtt_ / t_frame_;
      window_ = static_cast<int64_t>(std::clamp(w, 4.0 * batch_, static_cast<double>(kMaxWindow)));
      window_max_ = std::max(window_max_, window_);
    }
  }

  void loop_lockstep(const Progress& progress) {
    batch_ = opt_.batch > 0 ? opt_.batch : kDefaultBatch;
    window_ = opt_.window > 0 ? std::min<int64_t>(opt_.window, kMaxWindow) : 8 * batch_;
    window_max_ = window_;
    last_progress_ = mono_s();
    int64_t rounds = 0;
    while (base_ < n_) {
      flush_resends();
      int added = 0;
      const double a = mono_s();
      const bool red = next_ < red_until_;
      if (red) emit_copies();  // the previous batch's frames again, first (they fill a gap before a new one opens)
      prev_lo_ = next_;
      while (next_ < n_ && next_ - base_ < window_ && added < batch_) {
        const Faults& f = opt_.faults;
        if (f.reorder > 0 && next_ + 1 < n_ &&
            fault_uniform(f.seed, 12, static_cast<uint64_t>(next_), 0) < f.reorder) {
          make(next_);
          make(next_ + 1);
          emit(next_ + 1);  // frame k + 1 before frame k
          emit(next_);
          ++reordered_inj_;
          next_ += 2;
          added += 2;
        } else {
          make(next_);
          emit(next_);
          ++next_;
          ++added;
        }
        if ((added & 7) == 0 && added < batch_) {  // requests that came meanwhile: answered at once
          handle_ready();
          flush_resends_now();
        }
      }
      t_make_ += mono_s() - a;
      prev_hi_ = next_;
      if (red) steps_redundant_ += added;
      flush();
      const bool can_send = next_ < n_ && next_ - base_ < window_;
      if (can_send) {
        handle_ready();
      } else {
        if (red && prev_lo_ < prev_hi_) {  // the copies of the last batch now, not after the wait
          const int64_t c0 = frame_copies_;
          emit_copies();
          flush();
          if (frame_copies_ > c0) ++copy_batches_;
        }
        // outputs known to be missing (below the highest first publication) are
        // asked for again when their last resend is half a re-request interval old,
        // whether or not anything else arrives meanwhile
        double wait = rto() - (mono_s() - last_progress_);
        if (base_ < max_first_) wait = std::min(wait, 0.5 * gap_interval_s());
        const double w0 = mono_s();
        if (wait > 0) handle_until(w0 + wait);
        ++blocked_;
        blocked_s_ += mono_s() - w0;
        handle_ready();
        output_gaps(mono_s());
        if (mono_s() - last_progress_ >= rto() && base_ < n_ && resend_.empty()) on_timeout();
      }
      deliver();
      if ((++rounds & 63) == 0) {
        update_window();
        check_children();
        if (progress) progress(base_);
      }
    }
  }

  void loop_realtime(const Progress& progress) {
    batch_ = 1;
    window_ = window_max_ = kMaxWindow;
    latency_.assign(static_cast<size_t>(n_), -1.0);
    lateness_.reserve(static_cast<size_t>(n_));
    const double dt = static_cast<double>(dt_us_) * 1e-6;
    const Faults& f = opt_.faults;
    int64_t held = -1;  // frame held back by the reorder injection
    for (int64_t k = 0; k < n_; ++k) {
      const double t_send = t_start_ + static_cast<double>(k) * dt;
      make(k);  // ahead of its time: the schedule is that of the send
      for (double now = mono_s(); now < t_send; now = mono_s()) {
        handle_until(t_send);
        flush_resends();
        deliver();
      }
      while (base_ + kMaxWindow <= k) {  // the window is full: wait (counts as lateness)
        handle(rto());
        flush_resends();
        deliver();
        if (base_ + kMaxWindow <= k) on_timeout();
      }
      next_ = k + 1;
      if (f.reorder > 0 && held < 0 && k + 1 < n_ && fault_uniform(f.seed, 12, static_cast<uint64_t>(k), 0) < f.reorder) {
        held = k;  // goes out after frame k + 1
        ++reordered_inj_;
        lateness_.push_back(mono_s() - t_send);
      } else {
        emit(k);
        if (held >= 0) {
          emit(held);
          held = -1;
        }
        flush();
        lateness_.push_back(mono_s() - t_send);
      }
      handle_ready();
      flush_resends();
      deliver();
      if ((k & 63) == 0) {
        check_children();
        if (progress) progress(base_);
      }
    }
    if (held >= 0) {
      emit(held);
      flush();
    }
    last_progress_ = mono_s();
    while (base_ < n_) {  // the last outputs, resending what is missing
      const double wait = rto() - (mono_s() - last_progress_);
      if (wait > 0) handle(wait);
      handle_ready();
      flush_resends();
      deliver();
      if (base_ < n_ && mono_s() - last_progress_ >= rto()) on_timeout();
    }
  }

  std::string ch_nav_, ch_navs_;
  uint64_t scenario_id_ = 0;
  MakeFrame make_;
  OnOutput take_;
  std::vector<Slot> ring_;
  SeqCopies<Out> taken_;
  std::vector<ggins::sensor_frame_t> batch_msgs_;
  std::vector<int64_t> pending_seqs_, resend_, copies_wanted_, missing_;  // missing_: outputs known lost
  int64_t scanned_ = 0;  // output_gaps has looked at the seqs below this
  int64_t red_until_ = 0, prev_lo_ = 0, prev_hi_ = 0, last_copy_msg_ = -1;
  int64_t steps_redundant_ = 0, frame_copies_ = 0, copy_batches_ = 0, outputs_from_copies_ = 0,
          outputs_from_answers_ = 0, gaps_deferred_ = 0, copy_requests_ = 0, outputs_requested_ = 0;
  int64_t base_ = 0, next_ = 0, max_first_ = -1, batch_seq_ = 0;
  int batch_ = kDefaultBatch;
  int64_t window_ = 0, window_max_ = 0;
  double t_start_ = 0, wall_ = 0, last_progress_ = 0, t_make_ = 0, t_take_ = 0, t_frame_ = 0;
  double rtt_min_ = 1e30, srtt_ = 0, blocked_s_ = 0;
  int64_t blocked_ = 0;
  double cpu_start_ = 0, cpu_loop_ = 0, hal_cpu_s_ = -1, fw_ns_ = 0;
  int64_t outputs_ = 0, outputs_dup_ = 0, outputs_recovered_ = 0, outputs_foreign_ = 0, outputs_conflict_ = 0;
  int64_t output_messages_ = 0, resend_timeouts_ = 0, resend_on_request_ = 0, resend_on_gap_ = 0, naks_ = 0;
  int64_t dropped_copies_inj_ = 0, dup_copies_inj_ = 0, dropped_inj_ = 0, dup_inj_ = 0, reordered_inj_ = 0, conflict_inj_ = 0;
  std::vector<double> latency_, lateness_;
};

}  // namespace ggins::hil
