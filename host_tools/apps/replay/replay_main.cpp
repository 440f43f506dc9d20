// ggins replay: deterministic replay of a recorded host-in-the-loop run.
//
// Reads the LCM log a run wrote (run.lcmlog: every message of the run) with a
// bounded reader of its own (lcmlog_reader.hpp: every event header is checked
// against the file before it is used), takes the navigation configuration
// (2-D: GGINS_CONFIG, nav2d_config_t; 3-D: GGINS_CONFIG3D, nav3d_config_t) and
// the sensor frames (GGINS_FRAME, and the items of the frame batches on
// GGINS_FRAMES) of one run id, feeds the frames through the
// firmware again in this process -- the same gg_nav2d_init / gg_nav2d_task_cycle
// (or gg_nav3d_*) of the same build, through the same message -> struct
// conversions as hal_sim (hal_sim/hal_lcm.c, hal_lcm3d.c) -- in seq order, each
// seq once, as hal_sim's reorder window delivered them, and compares every
// navigation output with the recorded one (GGINS_NAV / GGINS_NAV3D, and the
// items of the output batches on GGINS_NAVS / GGINS_NAV3DS) bit for bit.
//
// Not compared: cycles[] (the HAL cycle counter: wall-clock timing) and
// republished (a transport count). The recorded step time cycles[GG_MOD_TOTAL]
// is fed back through the replay HAL's cycle counter, so the firmware's own
// deadline check reproduces the recorded GG_HEALTH_DEADLINE bit, which is
// compared like every other bit. Everything else is compared (fields.hpp: one
// table per message type, checked against the message's encoded size): doubles
// by their bit pattern (so -0.0 != +0.0 and NaN payloads count), integers
// exactly.
//
// The log must also be the whole record of the run: the START message's
// n_steps says how many frames the run sent (seq 0 .. n_steps-1), and every one
// of them must have its recorded output (but for frames hal_sim reported lost),
// no output may be undecodable, beyond n_steps, or published twice as a first
// publication, and hal_sim's final status (STOPPED) must be there and agree
// with the outputs in the log.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <type_traits>
#include <string>
#include <vector>

#include "fields.hpp"
#include "ggins/cli_checks.hpp"
#include "frame_names.hpp"
#include "ggins_hal_status_t.h"
#include "ggins_nav2d_config_t.h"
#include "ggins_nav3d_config_t.h"
#include "ggins_nav3d_output_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_run_control_t.h"
#include "ggins_sensor_frame_t.h"
#include "ggins_frame_batch_t.h"
#include "ggins_nav3d_output_batch_t.h"
#include "ggins_nav_output_batch_t.h"
#include "hal_lcm.h"
#include "hal_lcm3d.h"
#include "hal_map.h"
#include "lcmlog_reader.hpp"
#include "map_storage.hpp"

using json = nlohmann::json;
using namespace ggins::replay;

namespace {

// ---- exit status -----------------------------------------------------------------------
enum Exit : int {
  kExact = 0,       // every output reproduced bit for bit, the record complete
  kDifferent = 1,   // a replayed output differs from the recorded one (listed)
  kUnreadable = 2,  // bad arguments, a file that cannot be read or is not an LCM log
  kNothing = 3,     // no configuration, frames or outputs of the run in the log
  kCorrupt = 4,     // corrupt or truncated log (event framing, event numbering)
  kIncomplete = 5,  // the log is not the whole record of the run (see the header)
};

struct Problem {
  Exit code;
  std::string message;
};

const char* verdict_name(Exit e) {
  switch (e) {
    case kExact: return "BIT-EXACT";
    case kDifferent: return "DIFFERENT";
    case kUnreadable: return "UNREADABLE";
    case kNothing: return "NOTHING TO COMPARE";
    case kCorrupt: return "CORRUPT LOG";
    case kIncomplete: return "INCOMPLETE RECORD";
  }
  return "?";
}

// A log with several problems: corruption first (it may explain the rest), then
// a difference of the firmware, then an incomplete record.
int severity(Exit e) {
  switch (e) {
    case kUnreadable: return 5;
    case kCorrupt: return 4;
    case kNothing: return 3;
    case kDifferent: return 2;
    case kIncomplete: return 1;
    case kExact: return 0;
  }
  return 0;
}

const char* state_name(int32_t s) {
  switch (s) {
    case GGINS_HAL_STATUS_T_IDLE: return "IDLE";
    case GGINS_HAL_STATUS_T_CONFIGURED: return "CONFIGURED";
    case GGINS_HAL_STATUS_T_RUNNING: return "RUNNING";
    case GGINS_HAL_STATUS_T_STOPPED: return "STOPPED";
  }
  return "unknown";
}

// "a, b, c, ... (n in all)"
std::string seq_list(const std::vector<int64_t>& s, size_t keep = 8, int64_t total = -1) {
  if (total < 0) total = static_cast<int64_t>(s.size());
  std::string r;
  for (size_t i = 0; i < s.size() && i < keep; ++i) r += (i ? ", " : "") + std::to_string(s[i]);
  if (total > static_cast<int64_t>(std::min(keep, s.size()))) r += ", ... (" + std::to_string(total) + " in all)";
  return r;
}

// The seqs of 0 .. n-1 that are not keys of `m` (a map ordered by seq): how many, and
// the first `keep` of them. Walks the gaps between the keys, never 0 .. n-1 itself
// (n comes from the log: it may be anything).
template <class Map>
int64_t missing_seqs(const Map& m, int64_t n, std::vector<int64_t>& first, size_t keep = 8) {
  int64_t count = 0, next = 0;  // next: the lowest seq not yet accounted for
  auto gap = [&](int64_t upto) {  // next .. upto-1 are missing
    if (upto <= next) return;
    count += upto - next;
    for (int64_t s = next; s < upto && first.size() < keep; ++s) first.push_back(s);
  };
  for (auto it = m.lower_bound(0); it != m.end() && it->first < n; ++it) {
    gap(it->first);
    next = it->first + 1;
  }
  gap(n);
  return count;
}

// ---- the 2-D and 3-D tasks -------------------------------------------------------------
struct Dim2 {
  static constexpr const char* kName = "2-D";
  static constexpr const char* kConfig = "CONFIG";
  static constexpr const char* kNav = "NAV";
  static constexpr const char* kNavs = "NAVS";
  using CfgMsg = ggins_nav2d_config_t;
  using BatchMsg = ggins_nav_output_batch_t;
  static int batch_decode(const void* d, int n, BatchMsg* m) { return ggins_nav_output_batch_t_decode(d, 0, n, m); }
  static void batch_cleanup(BatchMsg* m) { ggins_nav_output_batch_t_decode_cleanup(m); }
  using OutMsg = ggins_nav_output_t;
  using Cfg = gg_nav2d_config_t;
  using Nav = gg_nav2d_t;
  using Out = gg_nav_output_t;
  static int cfg_decode(const void* d, int n, CfgMsg* m) { return ggins_nav2d_config_t_decode(d, 0, n, m); }
  static void cfg_cleanup(CfgMsg* m) { ggins_nav2d_config_t_decode_cleanup(m); }
  static int cfg_encode(void* d, int n, const CfgMsg* m) { return ggins_nav2d_config_t_encode(d, 0, n, m); }
  static int cfg_size(const CfgMsg* m) { return ggins_nav2d_config_t_encoded_size(m); }
  static int out_decode(const void* d, int n, OutMsg* m) { return ggins_nav_output_t_decode(d, 0, n, m); }
  static int out_encode(void* d, int n, const OutMsg* m) { return ggins_nav_output_t_encode(d, 0, n, m); }
  static int out_size(const OutMsg* m) { return ggins_nav_output_t_encoded_size(m); }
  static void cfg_from_lcm(const CfgMsg* m, Cfg* c) { ggins_config_from_lcm(m, c); }
  static void out_to_lcm(const Out* o, int64_t run_id, OutMsg* m) { ggins_output_to_lcm(o, run_id, m); }
  static gg_status_t init(Nav* n, const Cfg* c) { return gg_nav2d_init(n, c); }
  static gg_status_t cycle(Nav* n, const gg_hal_t* h) { return gg_nav2d_task_cycle(n, h); }
  static const std::vector<Field>& fields() { return nav2d_fields(); }
};

struct Dim3 {
  static constexpr const char* kName = "3-D";
  static constexpr const char* kConfig = "CONFIG3D";
  static constexpr const char* kNav = "NAV3D";
  static constexpr const char* kNavs = "NAV3DS";
  using CfgMsg = ggins_nav3d_config_t;
  using BatchMsg = ggins_nav3d_output_batch_t;
  static int batch_decode(const void* d, int n, BatchMsg* m) { return ggins_nav3d_output_batch_t_decode(d, 0, n, m); }
  static void batch_cleanup(BatchMsg* m) { ggins_nav3d_output_batch_t_decode_cleanup(m); }
  using OutMsg = ggins_nav3d_output_t;
  using Cfg = gg_nav3d_config_t;
  using Nav = gg_nav3d_t;
  using Out = gg_nav3d_output_t;
  static int cfg_decode(const void* d, int n, CfgMsg* m) { return ggins_nav3d_config_t_decode(d, 0, n, m); }
  static void cfg_cleanup(CfgMsg* m) { ggins_nav3d_config_t_decode_cleanup(m); }
  static int cfg_encode(void* d, int n, const CfgMsg* m) { return ggins_nav3d_config_t_encode(d, 0, n, m); }
  static int cfg_size(const CfgMsg* m) { return ggins_nav3d_config_t_encoded_size(m); }
  static int out_decode(const void* d, int n, OutMsg* m) { return ggins_nav3d_output_t_decode(d, 0, n, m); }
  static int out_encode(void* d, int n, const OutMsg* m) { return ggins_nav3d_output_t_encode(d, 0, n, m); }
  static int out_size(const OutMsg* m) { return ggins_nav3d_output_t_encoded_size(m); }
  static void cfg_from_lcm(const CfgMsg* m, Cfg* c) { ggins_config3d_from_lcm(m, c); }
  static void out_to_lcm(const Out* o, int64_t run_id, OutMsg* m) { ggins_output3d_to_lcm(o, run_id, m); }
  static gg_status_t init(Nav* n, const Cfg* c) { return gg_nav3d_init(n, c); }
  static gg_status_t cycle(Nav* n, const gg_hal_t* h) { return gg_nav3d_task_cycle(n, h); }
  static const std::vector<Field>& fields() { return nav3d_fields(); }
};

// ---- the replay HAL --------------------------------------------------------------------
template <class O>
struct ReplayHal {
  const gg_frame_t* frame = nullptr;  // the frame read_frame hands out next
  O out{};
  bool have_out = false;
  uint32_t total = 0;      // recorded cycles[GG_MOD_TOTAL] of this step
  bool first_call = true;  // next cycle_count call is the step's first
  uint32_t base = 0;
};

template <class O>
gg_status_t hal_read_frame(void* ctx, gg_frame_t* f) {
  auto* h = static_cast<ReplayHal<O>*>(ctx);
  if (!h->frame) return GG_ERR_NO_DATA;
  *f = *h->frame;
  h->frame = nullptr;
  h->first_call = true;
  return GG_OK;
}

template <class O>
gg_status_t hal_write(void* ctx, const O* o) {
  auto* h = static_cast<ReplayHal<O>*>(ctx);
  h->out = *o;
  h->have_out = true;
  return GG_OK;
}
gg_status_t hal_write3d(void* ctx, const struct gg_nav3d_output_s* o) { return hal_write<gg_nav3d_output_t>(ctx, o); }

// The first reading of a step is `base`, every later one base + the recorded
// total: the step's measured total equals the recorded one (modules read 0).
template <class O>
uint32_t hal_cycle_count(void* ctx) {
  auto* h = static_cast<ReplayHal<O>*>(ctx);
  if (h->first_call) {
    h->first_call = false;
    h->base += 1000u;
    return h->base;
  }
  return h->base + h->total;
}

void set_writer(gg_hal_t& hal, Dim2) { hal.write_output = hal_write<gg_nav_output_t>; }
void set_writer(gg_hal_t& hal, Dim3) { hal.write_output3d = hal_write3d; }

// Encoded bytes of a message, for comparing copies.
template <class M>
std::vector<uint8_t> encoded(const M& m, int (*enc)(void*, int, const M*), int (*size)(const M*)) {
  std::vector<uint8_t> b(static_cast<size_t>(size(&m)));
  enc(b.data(), static_cast<int>(b.size()), &m);
  return b;
}

// A frame's encoding but for `resent` and its MAC (transport: they differ between
// copies of one frame; hal_sim/bus_auth.h).
std::vector<uint8_t> frame_bytes(ggins_sensor_frame_t m) {
  m.resent = 0;
  std::memset(m.mac, 0, sizeof m.mac);
  return encoded<ggins_sensor_frame_t>(
      m, [](void* d, int n, const ggins_sensor_frame_t* x) { return ggins_sensor_frame_t_encode(d, 0, n, x); },
      ggins_sensor_frame_t_encoded_size);
}

struct Options {
  std::string log;
  std::string prefix = "GGINS_";
  std::optional<int64_t> run_id;
  std::string json_out;
  int show = 20;
  bool quiet = false;
  std::string map_dir;  // 3-D: look the recorded map tiles up by file name here
};

// What the log holds apart from the task-specific configuration and outputs.
struct Common {
  int64_t run_id = 0;
  struct FrameCopies {
    ggins_sensor_frame_t first{};
    int copies = 0;
    bool differ = false;
  };
  std::map<int64_t, FrameCopies> frames;
  int64_t frame_undecodable = 0, frame_foreign = 0;
  std::vector<int64_t> start_n_steps;  // n_steps of every START of the run
  int64_t control_undecodable = 0, hal_undecodable = 0;
  std::optional<ggins_hal_status_t> hal_last;  // highest status seq of the run
};

Common read_common(const Options& o, const LcmLog& log, int64_t run_id) {
  Common c;
  c.run_id = run_id;
  const std::string ch_frame = o.prefix + "FRAME", ch_hal = o.prefix + "HAL", ch_control = o.prefix + "CONTROL";
  const std::string ch_frames = o.prefix + "FRAMES";
  auto take = [&](const ggins_sensor_frame_t& m) {
    if (m.run_id != run_id) {
      ++c.frame_foreign;
      return;
    }
    auto& fc = c.frames[m.seq];
    if (fc.copies == 0) {
      fc.first = m;
    } else if (frame_bytes(m) != frame_bytes(fc.first)) {
      fc.differ = true;
    }
    ++fc.copies;
  };
  for (const LogEvent& e : log.events) {
    if (e.channel == ch_frame) {
      ggins_sensor_frame_t m;
      if (ggins_sensor_frame_t_decode(e.data, 0, e.datalen, &m) < 0) {
        ++c.frame_undecodable;  // the run tool injects such payloads (transport faults)
        continue;
      }
      take(m);
    } else if (e.channel == ch_frames) {  // batched lockstep: several frames per message, in their order
      ggins_frame_batch_t b;
      if (ggins_frame_batch_t_decode(e.data, 0, e.datalen, &b) < 0) {
        ++c.frame_undecodable;
        continue;
      }
      if (b.run_id != run_id) {
        ++c.frame_foreign;
      } else {
        for (int i = 0; i < b.n; ++i) take(b.frames[i]);
      }
      ggins_frame_batch_t_decode_cleanup(&b);
    } else if (e.channel == ch_hal) {
      ggins_hal_status_t m;
      if (ggins_hal_status_t_decode(e.data, 0, e.datalen, &m) < 0) {
        ++c.hal_undecodable;
        continue;
      }
      if (m.run_id == run_id && (!c.hal_last || m.seq >= c.hal_last->seq)) c.hal_last = m;
    } else if (e.channel == ch_control) {
      ggins_run_control_t m;
      if (ggins_run_control_t_decode(e.data, 0, e.datalen, &m) < 0) {
        ++c.control_undecodable;
        continue;
      }
      if (m.run_id == run_id && m.command == GGINS_RUN_CONTROL_T_START) c.start_n_steps.push_back(m.n_steps);
    }
  }
  return c;
}

// ---- the replay of one task ------------------------------------------------------------
template <class D>
int replay(const Options& o, const LcmLog& log, std::vector<Problem> problems, int64_t run_id) {
  using OutMsg = typename D::OutMsg;
  const std::string ch_config = o.prefix + D::kConfig, ch_nav = o.prefix + D::kNav;
  const Common c = read_common(o, log, run_id);

  // configuration and outputs of the run
  std::vector<typename D::CfgMsg> configs;
  int64_t config_undecodable = 0, nav_undecodable = 0, nav_foreign = 0;
  struct OutCopies {
    OutMsg rec{};            // the first publication, else the first copy
    bool rec_first = false;  // rec is a first publication (republished == 0)
    int firsts = 0;          // copies with republished == 0
    int copies = 0;
    bool differ = false;     // copies differ beyond republished
  };
  auto out_bytes = [](OutMsg m) {
    m.republished = 0;
    std::memset(m.mac, 0, sizeof m.mac);
    return encoded<OutMsg>(m, D::out_encode, D::out_size);
  };
  std::map<int64_t, OutCopies> outs;
  const std::string ch_navs = o.prefix + D::kNavs;
  auto take_out = [&](const OutMsg& m) {
    if (m.run_id != run_id) {
      ++nav_foreign;
      return;
    }
    auto& oc = outs[m.seq];
    if (oc.copies == 0) {
      oc.rec = m;
      oc.rec_first = m.republished == 0;
    } else {
      if (out_bytes(m) != out_bytes(oc.rec)) oc.differ = true;
      if (m.republished == 0 && !oc.rec_first) {
        oc.rec = m;
        oc.rec_first = true;
      }
    }
    if (m.republished == 0) ++oc.firsts;
    ++oc.copies;
  };
  for (const LogEvent& e : log.events) {
    if (e.channel == ch_config) {
      typename D::CfgMsg m;
      if (D::cfg_decode(e.data, e.datalen, &m) < 0) {
        ++config_undecodable;
        continue;
      }
      if (m.run_id == run_id) configs.push_back(m);
      D::cfg_cleanup(&m);
    } else if (e.channel == ch_nav) {
      OutMsg m;
      if (D::out_decode(e.data, e.datalen, &m) < 0) {
        ++nav_undecodable;
        continue;
      }
      take_out(m);
    } else if (e.channel == ch_navs) {  // output batches (batched lockstep)
      typename D::BatchMsg b;
      if (D::batch_decode(e.data, e.datalen, &b) < 0) {
        ++nav_undecodable;
        continue;
      }
      if (b.run_id != run_id) {
        ++nav_foreign;
      } else {
        for (int i = 0; i < b.n; ++i) take_out(b.outputs[i]);
      }
      D::batch_cleanup(&b);
    }
  }

  json r;
  r["log"] = o.log;
  r["events"] = log.events.size();
  r["task"] = D::kName;
  r["run_id"] = run_id;
  auto finish = [&](int code) {
    json pl = json::array();
    for (const auto& p : problems) pl.push_back({{"exit", static_cast<int>(p.code)}, {"message", p.message}});
    r["problems"] = pl;
    r["exit"] = code;
    r["verdict"] = verdict_name(static_cast<Exit>(code));
    r["bit_exact"] = code == kExact;
    if (!o.json_out.empty()) {  // an output that cannot be written is an error (exit 2)
      std::ofstream jf(o.json_out);
      jf << r.dump(2, ' ', false, json::error_handler_t::replace) << "\n";  // a path need not be UTF-8
      jf.close();
      if (!jf) {
        std::fprintf(stderr, "ggins replay: cannot write %s\n", o.json_out.c_str());
        return static_cast<int>(kUnreadable);
      }
    }
    return code;
  };
  auto worst = [&](int base) {
    int code = base;
    for (const auto& p : problems)
      if (severity(p.code) > severity(static_cast<Exit>(code))) code = p.code;
    return code;
  };
  auto print_problems = [&] {
    for (const auto& p : problems) std::printf("  PROBLEM (%s): %s\n", verdict_name(p.code), p.message.c_str());
  };

  if (configs.empty() || c.frames.empty() || outs.empty()) {
    const std::string m = "nothing to compare in " + o.log + ": " + std::to_string(configs.size()) +
                          " configuration, " + std::to_string(c.frames.size()) + " frame and " +
                          std::to_string(outs.size()) + " output messages of run " + std::to_string(run_id) +
                          " (" + D::kName + ", channel prefix " + o.prefix + ")";
    problems.push_back({kNothing, m});
    const int code = worst(kNothing);
    print_problems();
    std::printf("replay: %s\n", verdict_name(static_cast<Exit>(code)));
    return finish(code);
  }

  // ---- the record: is it the whole run?
  if (config_undecodable)
    problems.push_back({kIncomplete, std::to_string(config_undecodable) + " undecodable payloads on " + ch_config});
  if (nav_undecodable)
    problems.push_back({kIncomplete, std::to_string(nav_undecodable) + " undecodable payloads on " + ch_nav +
                                         " (an output the log cannot give back)"});
  if (c.hal_undecodable)
    problems.push_back({kIncomplete, std::to_string(c.hal_undecodable) + " undecodable payloads on " + o.prefix + "HAL"});
  if (c.control_undecodable)
    problems.push_back(
        {kIncomplete, std::to_string(c.control_undecodable) + " undecodable payloads on " + o.prefix + "CONTROL"});
  std::optional<int64_t> n_steps;
  if (c.start_n_steps.empty()) {
    problems.push_back({kIncomplete, "no START message of run " + std::to_string(run_id) + " on " + o.prefix +
                                         "CONTROL: the run's step count (n_steps) is unknown"});
  } else {
    n_steps = c.start_n_steps.front();
    for (int64_t n : c.start_n_steps)
      if (n != *n_steps)
        problems.push_back({kIncomplete, "START messages disagree on n_steps (" + std::to_string(*n_steps) + " and " +
                                             std::to_string(n) + ")"});
    if (*n_steps < 1) problems.push_back({kIncomplete, "START gives n_steps = " + std::to_string(*n_steps)});
  }
  const int64_t frames_lost = c.hal_last ? c.hal_last->frames_lost : 0;
  if (!c.hal_last) {
    problems.push_back({kIncomplete, "no hal_sim status (" + o.prefix + "HAL) of run " + std::to_string(run_id)});
  } else if (c.hal_last->state != GGINS_HAL_STATUS_T_STOPPED) {
    problems.push_back({kIncomplete, "the log ends before hal_sim's final status (STOPPED): the last status (seq " +
                                         std::to_string(c.hal_last->seq) + ") is " +
                                         state_name(c.hal_last->state) + " after " +
                                         std::to_string(c.hal_last->steps) + " steps"});
  }
  // outputs: each seq of 0 .. n_steps-1 once (but for frames hal_sim gave up on), nothing else
  std::vector<int64_t> missing, beyond, twice, no_frame, frames_beyond;
  int64_t n_missing = 0;
  int64_t rejected = 0;
  uint32_t health_or = 0;  // of the recorded outputs (the report's health_seen)
  for (const auto& [seq, oc] : outs) {
    if (n_steps && (seq < 0 || seq >= *n_steps)) beyond.push_back(seq);
    if (oc.firsts > 1) twice.push_back(seq);
    if (!c.frames.count(seq)) no_frame.push_back(seq);
    if (oc.rec.status != 0) ++rejected;
    health_or |= static_cast<uint32_t>(oc.rec.health);
  }
  if (n_steps) n_missing = missing_seqs(outs, *n_steps, missing);
  for (const auto& [seq, fc] : c.frames) {
    (void)fc;
    if (n_steps && (seq < 0 || seq >= *n_steps)) frames_beyond.push_back(seq);
  }
  const std::string nst = n_steps ? std::to_string(*n_steps) : "?";
  if (n_missing > 0 && n_missing != frames_lost)
    problems.push_back({kIncomplete, "outputs missing: " + std::to_string(n_missing) + " of the " + nst +
                                         " steps of the run have no recorded output (seq " +
                                         seq_list(missing, 8, n_missing) +
                                         "); hal_sim reported " + std::to_string(frames_lost) + " frames lost"});
  if (!beyond.empty())
    problems.push_back({kIncomplete, "extra outputs: " + std::to_string(beyond.size()) +
                                         " recorded outputs of seqs outside the run's 0.." +
                                         std::to_string(n_steps ? *n_steps - 1 : 0) + " (seq " + seq_list(beyond) +
                                         ")"});
  if (!twice.empty())
    problems.push_back({kIncomplete, "extra outputs: " + std::to_string(twice.size()) +
                                         " outputs recorded more than once as a first publication (republished = 0; "
                                         "hal_sim publishes each step once) (seq " +
                                         seq_list(twice) + ")"});
  if (!no_frame.empty())
    problems.push_back({kIncomplete, std::to_string(no_frame.size()) + " recorded outputs have no frame in the log (seq " +
                                         seq_list(no_frame) + ")"});
  if (!frames_beyond.empty())
    problems.push_back({kIncomplete, "extra frames: " + std::to_string(frames_beyond.size()) +
                                         " frames of seqs outside the run's 0.." +
                                         std::to_string(n_steps ? *n_steps - 1 : 0) + " (seq " +
                                         seq_list(frames_beyond) + ")"});
  if (c.hal_last && c.hal_last->state == GGINS_HAL_STATUS_T_STOPPED) {
    const int64_t in_range = static_cast<int64_t>(outs.size() - beyond.size());
    if (c.hal_last->steps != in_range)
      problems.push_back({kIncomplete, "hal_sim stepped the firmware " + std::to_string(c.hal_last->steps) +
                                           " times; the log holds the outputs of " + std::to_string(in_range) +
                                           " steps"});
    if (c.hal_last->steps_rejected != rejected)
      problems.push_back({kIncomplete, "hal_sim counted " + std::to_string(c.hal_last->steps_rejected) +
                                           " rejected steps; the recorded outputs have " + std::to_string(rejected)});
  }
  // hal_sim applies the first configuration it receives; the repeats must be the same
  bool config_copies_differ = false;
  for (const auto& cm : configs) {
    typename D::CfgMsg a = cm, b = configs.front();
    a.utime = b.utime = 0;
    std::memset(a.mac, 0, sizeof a.mac);
    std::memset(b.mac, 0, sizeof b.mac);
    if (encoded(a, D::cfg_encode, D::cfg_size) != encoded(b, D::cfg_encode, D::cfg_size)) config_copies_differ = true;
  }

  // ---- the computer's map storage (3-D, aids with maps): the sources the configuration records
  // (map_storage.hpp), each read again and checked against its recorded tiles, bytes and
  // BLAKE2b-256 before its tiles are loaded in the recorded order
  struct MapStore {
    hal_map_store_t s;
    MapStore() { hal_map_init(&s); }
    ~MapStore() { hal_map_free(&s); }
  } maps;
  bool have_maps = false;
  if constexpr (std::is_same_v<D, Dim3>) {
    const auto& cm = configs.front();
    json sl = json::array(), tl = json::array();
    std::string bad;
    const int n_src = std::clamp<int>(cm.map_n_sources, 0, ggins::run3d::kMaxSources);
    if (cm.map_n_sources != n_src)
      bad = "the configuration records " + std::to_string(cm.map_n_sources) + " map storage sources (0.." +
            std::to_string(ggins::run3d::kMaxSources) + " allowed)";
    for (int i = 0; i < n_src && bad.empty(); ++i) {
      const char* p = reinterpret_cast<const char*>(cm.map_source_path[i]);
      ggins::run3d::MapSource src{std::string(p, strnlen(p, 256)),
                                  cm.map_source_kind[i] == 1 ? ggins::run3d::SourceKind::kDir
                                                             : ggins::run3d::SourceKind::kFile};
      if (!o.map_dir.empty())
        src.path = (std::filesystem::path(o.map_dir) / std::filesystem::path(src.path).filename()).string();
      std::array<uint8_t, 32> want{};
      std::memcpy(want.data(), cm.map_source_blake2b[i], 32);
      const std::string what = std::string("map storage ") + ggins::run3d::kind_name(src.kind) + " " + src.path;
      const std::string recorded = std::to_string(cm.map_source_tiles[i]) + " tiles, " +
                                   std::to_string(cm.map_source_bytes[i]) + " bytes, BLAKE2b " + ggins::run3d::hex(want);
      ggins::run3d::SourceRecord got;
      if (const std::string why = ggins::run3d::read_source(src, got); !why.empty())
        bad = what + " (recorded for the run: " + recorded + ") cannot be read: " + why;
      else if (got.tiles != cm.map_source_tiles[i] || got.bytes != cm.map_source_bytes[i] || got.blake2b != want)
        bad = what + " is not the one the run flew: " + std::to_string(got.tiles) + " tiles, " +
              std::to_string(got.bytes) + " bytes, BLAKE2b " + ggins::run3d::hex(got.blake2b) + "; recorded " + recorded;
      for (size_t k = 0; k < got.files.size() && bad.empty(); ++k) {
        char err[256] = "";
        if (hal_map_load(&maps.s, got.files[k].c_str(), err, sizeof err) != 0)
          bad = "map tile " + got.files[k] + ": " + err;
        else
          have_maps = true;
        tl.push_back(got.files[k]);
      }
      sl.push_back({{"path", src.path}, {"kind", ggins::run3d::kind_name(src.kind)}, {"tiles", cm.map_source_tiles[i]},
                    {"bytes", cm.map_source_bytes[i]}, {"blake2b", ggins::run3d::hex(want)}});
    }
    r["map_storage"] = sl;
    r["map_tiles"] = tl;
    if (!bad.empty()) {  // a replay over another storage would not be the run: refused
      problems.push_back({kUnreadable, bad});
      const int code = worst(kUnreadable);
      print_problems();
      std::printf("replay: %s\n", verdict_name(static_cast<Exit>(code)));
      return finish(code);
    }
  }

  // ---- replay
  typename D::Cfg cfg;
  D::cfg_from_lcm(&configs.front(), &cfg);
  static typename D::Nav nav;  // large: static storage
  const gg_status_t init_st = D::init(&nav, &cfg);
  using FwOut = typename D::Out;
  ReplayHal<FwOut> rh;
  gg_hal_t hal{};
  hal.ctx = &rh;
  hal.read_frame = hal_read_frame<FwOut>;
  set_writer(hal, D{});
  hal.cycle_count = hal_cycle_count<FwOut>;
  hal.cycles_per_second = 1000000000u;
  if (have_maps) hal.map = &maps.s.ops;

  Comparer cmp;
  cmp.keep = static_cast<size_t>(std::max(0, o.show));
  int64_t replayed = 0, compared = 0, no_recorded = 0, skipped = 0, frame_copies_differ = 0, out_copies_differ = 0;
  for (const auto& [seq, fc] : c.frames) {
    const auto it = outs.find(seq);
    const bool recorded = it != outs.end();
    if (fc.differ) ++frame_copies_differ;
    if (!recorded && frames_lost > 0) {  // hal_sim may have given up on it: not consumed
      ++skipped;
      continue;
    }
    gg_frame_t f;
    ggins_frame_from_lcm(&fc.first, &f);
    rh.frame = &f;
    rh.have_out = false;
    rh.total = recorded ? static_cast<uint32_t>(it->second.rec.cycles[GG_MOD_TOTAL]) : 0u;
    D::cycle(&nav, &hal);
    ++replayed;
    if (!rh.have_out) {
      cmp.note(seq, "(no output from the replay)", "an output", "none");
      continue;
    }
    if (!recorded) {
      ++no_recorded;
      continue;
    }
    const OutCopies& oc = it->second;
    if (oc.differ) ++out_copies_differ;
    OutMsg rep;
    D::out_to_lcm(&rh.out, run_id, &rep);
    cmp.message(D::fields(), seq, oc.rec, rep);
    ++compared;
  }
  const int32_t rec_init = c.hal_last ? c.hal_last->init_status : -1;
  const bool init_ok = rec_init < 0 || rec_init == static_cast<int32_t>(init_st);
  if (cmp.count)
    problems.push_back({kDifferent, std::to_string(cmp.count) + " mismatching fields in " + std::to_string(compared) +
                                        " outputs compared"});
  if (frame_copies_differ)
    problems.push_back({kDifferent, std::to_string(frame_copies_differ) + " frames have copies that differ (beyond `resent`)"});
  if (out_copies_differ)
    problems.push_back({kDifferent, std::to_string(out_copies_differ) + " outputs were republished with different contents"});
  if (config_copies_differ) problems.push_back({kDifferent, "the configuration messages differ from one another"});
  if (!init_ok)
    problems.push_back({kDifferent, "init: recorded status " + std::to_string(rec_init) + ", replayed " +
                                        std::to_string(static_cast<int>(init_st))});
  const int code = worst(kExact);

  r["n_steps"] = n_steps ? json(*n_steps) : json(nullptr);
  r["init_status"] = {{"replayed", static_cast<int>(init_st)}, {"recorded", rec_init}};
  r["frames"] = {{"seqs", c.frames.size()},
                 {"replayed", replayed},
                 {"skipped_not_consumed", skipped},
                 {"copies_differing", frame_copies_differ},
                 {"undecodable_payloads", c.frame_undecodable},
                 {"other_run", c.frame_foreign},
                 {"beyond_n_steps", frames_beyond.size()}};
  r["outputs"] = {{"recorded_seqs", outs.size()},
                  {"compared", compared},
                  {"missing", n_missing},
                  {"beyond_n_steps", beyond.size()},
                  {"first_publication_twice", twice.size()},
                  {"replayed_without_recorded_output", no_recorded},
                  {"recorded_without_frame", no_frame.size()},
                  {"republished_copies_differing", out_copies_differ},
                  {"undecodable", nav_undecodable},
                  {"other_run", nav_foreign},
                  {"rejected_steps", rejected}};
  r["health_seen"] = ggins::hil::health_word(health_or);  // raw and named bits, as in the run's report
  r["configuration_copies_differ"] = config_copies_differ;
  r["hal_frames_lost"] = frames_lost;
  r["hal_final"] = c.hal_last && c.hal_last->state == GGINS_HAL_STATUS_T_STOPPED;
  r["mismatching_fields"] = cmp.count;
  r["not_compared"] = "cycles[] (HAL cycle-counter timing) and republished (transport); the recorded "
                      "cycles[GG_MOD_TOTAL] is fed back so the DEADLINE health bit is reproduced and compared";
  json ml = json::array();
  for (const auto& m : cmp.list)
    ml.push_back({{"seq", m.seq}, {"field", m.field}, {"recorded", m.recorded}, {"replayed", m.replayed}});
  r["mismatches"] = ml;

  if (!o.quiet) {
    std::printf("log %s: %zu events, run %" PRId64 " (%s), n_steps %s\n", o.log.c_str(), log.events.size(), run_id,
                D::kName, nst.c_str());
    std::printf("frames: %zu seqs, %" PRId64 " replayed, %" PRId64 " skipped (not consumed), %" PRId64
                " undecodable payloads and %" PRId64 " of other runs ignored\n",
                c.frames.size(), replayed, skipped, c.frame_undecodable, c.frame_foreign);
    std::printf("outputs: %" PRId64 " compared field by field, bit for bit (all but cycles[], the timing)\n", compared);
    if (no_recorded) std::printf("  %" PRId64 " replayed steps had no recorded output (not compared)\n", no_recorded);
    if (frames_lost && n_missing == frames_lost)
      std::printf("  %" PRId64 " frames hal_sim gave up on (no output, not flown)\n", frames_lost);
    for (const auto& m : cmp.list)
      std::printf("  MISMATCH seq %" PRId64 " %s: recorded %s, replayed %s\n", m.seq, m.field.c_str(), m.recorded.c_str(),
                  m.replayed.c_str());
    if (cmp.count > static_cast<int64_t>(cmp.list.size()))
      std::printf("  ... %" PRId64 " mismatching fields in all\n", cmp.count);
  }
  print_problems();
  // what the run itself did, so that a bit-exact replay of a run that went wrong does not read as a good run
  std::string flown = "every step of the run";
  if (frames_lost > 0)
    flown = std::to_string(frames_lost) + " of the " + nst + " steps not flown (frames hal_sim gave up on)";
  if (rejected > 0) flown += "; " + std::to_string(rejected) + " steps rejected by the firmware (status != GG_OK)";
  {
    // the last step flown: a run that ends in an outage ends on held inputs
    auto last = outs.end();
    for (auto it = outs.begin(); it != outs.end(); ++it)
      if (!n_steps || (it->first >= 0 && it->first < *n_steps)) last = it;
    if (last != outs.end() && (last->second.rec.outage_s > 0 || last->second.rec.resync_count > 0)) {
      char b[160];
      std::snprintf(b, sizeof b, "; at the last step (seq %" PRId64 "): outage %.6g s, %" PRId64 " resyncs, %" PRId64
                    " coast steps",
                    last->first, last->second.rec.outage_s, static_cast<int64_t>(last->second.rec.resync_count),
                    static_cast<int64_t>(last->second.rec.coast_steps));
      flown += b;
    }
  }
  if (code == kExact)
    std::printf("replay: BIT-EXACT (%" PRId64 " outputs, %s)\n", compared, flown.c_str());
  else
    std::printf("replay: %s (%zu problem%s; %" PRId64 " mismatching fields in %" PRId64 " outputs compared)\n",
                verdict_name(static_cast<Exit>(code)), problems.size(), problems.size() == 1 ? "" : "s", cmp.count,
                compared);
  return finish(code);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "ggins replay: feed a recorded run's sensor frames through the firmware again and\n"
      "compare every navigation output with the recorded one, bit for bit.\n\n"
      "Reads the LCM log of a run (`ggins run` and `ggins run3d` write run.lcmlog: every\n"
      "message of the run), checking every event header against the file before using it\n"
      "(sync word, channel and data lengths within the bytes left, event numbers 0, 1, 2,\n"
      "...). From it: the configuration (<prefix>CONFIG: the 2-D task; <prefix>CONFIG3D:\n"
      "the 3-D task), the sensor frames (<prefix>FRAME) and the navigation outputs\n"
      "(<prefix>NAV or <prefix>NAV3D) of one run id. The frames go through gg_nav2d_init /\n"
      "gg_nav2d_task_cycle (gg_nav3d_*) of this build in-process, via the same message\n"
      "conversions as hal_sim (hal_sim/hal_lcm.c, hal_lcm3d.c): in seq order, each seq\n"
      "once, as hal_sim's reorder window delivered them (duplicates, reordering,\n"
      "undecodable frame payloads and other runs' messages are counted and skipped; copies\n"
      "of one frame must be identical but for `resent`). If hal_sim reported frames it gave\n"
      "up on (hal_status_t.frames_lost > 0), only the frames with a recorded output are\n"
      "replayed.\n\n"
      "3-D runs with aids that read maps: the computer's map storage is loaded again from the\n"
      "sources the configuration message records (each a tile file or a directory of *.gmap\n"
      "tiles, with the number of tiles, their bytes and one BLAKE2b-256 over their names and\n"
      "contents; from --map-dir by name if they moved); a source that cannot be read or whose\n"
      "tiles, size or digest differ is refused (exit 2): a replay over another storage is not\n"
      "the run.\n\n"
      "Compared: every field of the output message (doubles by bit pattern) except cycles[],\n"
      "the HAL cycle-counter timing, and republished. The recorded cycles[GG_MOD_TOTAL] is\n"
      "fed back through the replay HAL's cycle counter so the firmware's deadline check\n"
      "reproduces the recorded GG_HEALTH_DEADLINE bit, which is compared with the rest of\n"
      "health. Republished copies of an output (answers to duplicate frames) must equal the\n"
      "first publication.\n\n"
      "The log must be the whole record of the run: the START message (<prefix>CONTROL)\n"
      "gives n_steps, and every seq 0 .. n_steps-1 must have its recorded output (but for\n"
      "frames hal_sim reported lost: exactly that many may be missing); no output may be\n"
      "undecodable, outside 0 .. n_steps-1 or recorded twice as a first publication; and\n"
      "hal_sim's final status (STOPPED) must be there and agree with the outputs (steps,\n"
      "rejected steps).\n\n"
      "Exit status: 0 bit-exact and complete; 1 a difference (listed); 2 bad arguments, a\n"
      "file that cannot be read or is not an LCM log (or a comparison table of this build\n"
      "out of step with its message type); 3 nothing to compare (no\n"
      "configuration, frames or outputs of the run); 4 corrupt or truncated log (an event\n"
      "header with a bad sync word or impossible lengths, an event cut off by the end of\n"
      "the file, event numbers that skip); 5 incomplete record (outputs missing,\n"
      "undecodable or extra, fewer steps than n_steps, no START or final status). With\n"
      "several problems (all are listed): 4, then 3, then 1, then 5.",
      "ggins replay"};
  app.add_option("log", o.log, "LCM log of the run (run.lcmlog)")->required()->check(CLI::ExistingFile);
  app.add_option("--prefix", o.prefix, "channel prefix of the run")->capture_default_str();
  app.add_option("--run-id", o.run_id, "run id to replay (default: the run id of the first configuration message)")
      ->check(ggins::cli::IntRange(0, INT64_MAX));
  app.add_option("--json", o.json_out, "also write the result as JSON to this file")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            const std::string dir = std::filesystem::path(v).parent_path().string();
            const std::string why = ggins::cli::output_dir_problem(dir.empty() ? "." : dir);
            return why.empty() ? why : "cannot write '" + v + "': " + why;
          },
          "FILE (writable)", "WritableFile"));
  app.add_option("--show", o.show, "mismatches listed in full")->capture_default_str()->check(ggins::cli::IntRange(0, 1000000));
  app.add_option("--map-dir", o.map_dir,
                 "3-D: take the map storage's sources the run recorded (tile files and directories of tiles) "
                 "from this folder, by name (a source whose tiles, size or digest differ is refused)");
  app.add_flag("-q,--quiet", o.quiet, "print only the problems and the verdict line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  // the comparison tables must cover their messages (a field added to the .lcm file and not to fields.hpp)
  {
    ggins_nav_output_t m2{};
    ggins_nav3d_output_t m3{};
    const std::string e2 = covers_message(nav2d_fields(), ggins_nav_output_t_encoded_size(&m2), sizeof m2);
    const std::string e3 = covers_message(nav3d_fields(), ggins_nav3d_output_t_encoded_size(&m3), sizeof m3);
    if (!e2.empty() || !e3.empty()) {
      std::fprintf(stderr, "ggins replay: internal error: the comparison table of %s: %s\n",
                   e2.empty() ? "nav3d_output_t" : "nav_output_t", (e2.empty() ? e3 : e2).c_str());
      return kUnreadable;
    }
  }

  const LcmLog log = read_lcm_log(o.log);
  if (log.error == LcmLog::Error::kOpen || log.error == LcmLog::Error::kNotLog) {
    std::fprintf(stderr, "ggins replay: %s: %s\n", o.log.c_str(), log.message.c_str());
    std::printf("replay: UNREADABLE\n");
    return kUnreadable;
  }
  std::vector<Problem> problems;
  if (log.error != LcmLog::Error::kNone)
    problems.push_back({kCorrupt, log.message + " (" + std::to_string(log.events.size()) +
                                      " events read before it; the rest of the file is not used)"});
  if (log.numbering_breaks)
    problems.push_back({kCorrupt, log.numbering_message +
                                      (log.numbering_breaks > 1
                                           ? " (" + std::to_string(log.numbering_breaks) + " breaks in all)"
                                           : std::string())});

  // the run and its task: the first configuration message (2-D or 3-D) of the run id
  std::optional<int64_t> run_id = o.run_id;
  std::set<std::string> kinds;
  for (const LogEvent& e : log.events) {
    std::optional<int64_t> id;
    std::string kind;
    if (e.channel == o.prefix + Dim2::kConfig) {
      ggins_nav2d_config_t m;
      if (ggins_nav2d_config_t_decode(e.data, 0, e.datalen, &m) < 0) continue;
      id = m.run_id;
      kind = Dim2::kName;
      ggins_nav2d_config_t_decode_cleanup(&m);
    } else if (e.channel == o.prefix + Dim3::kConfig) {
      ggins_nav3d_config_t m;
      if (ggins_nav3d_config_t_decode(e.data, 0, e.datalen, &m) < 0) continue;
      id = m.run_id;
      kind = Dim3::kName;
      ggins_nav3d_config_t_decode_cleanup(&m);
    } else {
      continue;
    }
    if (!run_id) run_id = id;
    if (*id == *run_id) kinds.insert(kind);
  }
  if (!run_id) {
    for (const auto& p : problems) std::printf("  PROBLEM (%s): %s\n", verdict_name(p.code), p.message.c_str());
    std::fprintf(stderr,
                 "ggins replay: nothing to compare in %s: no configuration message (%s%s or %s%s) in %zu events\n",
                 o.log.c_str(), o.prefix.c_str(), Dim2::kConfig, o.prefix.c_str(), Dim3::kConfig, log.events.size());
    const Exit code = problems.empty() ? kNothing : kCorrupt;
    std::printf("replay: %s\n", verdict_name(code));
    return code;
  }
  if (kinds.size() > 1)
    problems.push_back({kIncomplete, "run " + std::to_string(*run_id) + " has both 2-D and 3-D configurations"});
  if (kinds.count(Dim3::kName) && !kinds.count(Dim2::kName)) return replay<Dim3>(o, log, problems, *run_id);
  return replay<Dim2>(o, log, problems, *run_id);
}
