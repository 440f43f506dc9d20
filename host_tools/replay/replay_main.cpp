// ggins replay: deterministic replay of a recorded host-in-the-loop run.
//
// Reads the LCM log a run wrote (run.lcmlog: every message of the run), takes
// the navigation configuration (GGINS_CONFIG) and the sensor frames
// (GGINS_FRAME) of one run id, feeds the frames through the firmware again in
// this process -- the same gg_nav2d_init / gg_nav2d_task_cycle /
// gg_nav2d_step of the same build, through the same message -> struct
// conversions as hal_sim (hal_sim/hal_lcm.c) -- in seq order, each seq once,
// as hal_sim's reorder window delivered them, and compares every navigation
// output with the recorded one (GGINS_NAV) bit for bit.
//
// Not compared: cycles[] (the HAL cycle counter: wall-clock timing). The
// recorded step time cycles[GG_MOD_TOTAL] is fed back through the replay
// HAL's cycle counter, so the firmware's own deadline check reproduces the
// recorded GG_HEALTH_DEADLINE bit, which is compared like every other bit.
// Everything else in nav_output_t is compared: doubles by their bit pattern
// (so -0.0 != +0.0 and NaN payloads count), integers exactly.
#include <lcm/eventlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "ggins_hal_status_t.h"
#include "ggins_nav2d_config_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_sensor_frame_t.h"
#include "hal_lcm.h"

using json = nlohmann::json;

namespace {

// ---- the replay HAL --------------------------------------------------------------------
struct ReplayHal {
  const gg_frame_t* frame = nullptr;  // the frame read_frame hands out next
  gg_nav_output_t out{};
  bool have_out = false;
  uint32_t total = 0;       // recorded cycles[GG_MOD_TOTAL] of this step
  bool first_call = true;   // next cycle_count call is the step's first
  uint32_t base = 0;
};

gg_status_t hal_read_frame(void* ctx, gg_frame_t* f) {
  auto* h = static_cast<ReplayHal*>(ctx);
  if (!h->frame) return GG_ERR_NO_DATA;
  *f = *h->frame;
  h->frame = nullptr;
  h->first_call = true;
  return GG_OK;
}

gg_status_t hal_write_output(void* ctx, const gg_nav_output_t* o) {
  auto* h = static_cast<ReplayHal*>(ctx);
  h->out = *o;
  h->have_out = true;
  return GG_OK;
}

// The first reading of a step is `base`, every later one base + the recorded
// total: the step's measured total equals the recorded one (modules read 0).
uint32_t hal_cycle_count(void* ctx) {
  auto* h = static_cast<ReplayHal*>(ctx);
  if (h->first_call) {
    h->first_call = false;
    h->base += 1000u;
    return h->base;
  }
  return h->base + h->total;
}

// ---- comparison ---------------------------------------------------------------------------
struct Mismatch {
  int64_t seq;
  std::string field;
  std::string recorded, replayed;
};

std::string fmt_double(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  char s[96];
  std::snprintf(s, sizeof s, "%.17g (0x%016" PRIx64 ")", x, b);
  return s;
}

std::string fmt_int(int64_t x) {
  char s[64];
  std::snprintf(s, sizeof s, "%" PRId64 " (0x%" PRIx64 ")", x, static_cast<uint64_t>(x));
  return s;
}

class Comparer {
 public:
  std::vector<Mismatch> list;
  int64_t count = 0;
  size_t keep = 20;
  void dbl(int64_t seq, const std::string& name, double rec, double rep) {
    if (std::memcmp(&rec, &rep, sizeof rec) != 0) add(seq, name, fmt_double(rec), fmt_double(rep));
  }
  void i64(int64_t seq, const std::string& name, int64_t rec, int64_t rep) {
    if (rec != rep) add(seq, name, fmt_int(rec), fmt_int(rep));
  }
  // every field of nav_output_t but cycles[] (timing) and republished (transport)
  void output(const ggins_nav_output_t& rec, const ggins_nav_output_t& rep) {
    const int64_t s = rec.seq;
    i64(s, "utime", rec.utime, rep.utime);
    i64(s, "seq", rec.seq, rep.seq);
    i64(s, "run_id", rec.run_id, rep.run_id);
    i64(s, "status", rec.status, rep.status);
    i64(s, "health", rec.health, rep.health);
    for (int j = 0; j < 3; ++j) {
      const std::string ix = "[" + std::to_string(j) + "]";
      dbl(s, "r_i" + ix, rec.r_i[j], rep.r_i[j]);
      dbl(s, "v_i" + ix, rec.v_i[j], rep.v_i[j]);
      dbl(s, "g_i" + ix, rec.g_i[j], rep.g_i[j]);
      dbl(s, "f_i" + ix, rec.f_i[j], rep.f_i[j]);
      for (int k = 0; k < 3; ++k)
        dbl(s, "gamma_i" + ix + "[" + std::to_string(k) + "]", rec.gamma_i[j][k], rep.gamma_i[j][k]);
    }
    dbl(s, "gamma_asym", rec.gamma_asym, rep.gamma_asym);
    dbl(s, "h_ins_m", rec.h_ins_m, rep.h_ins_m);
    dbl(s, "baro_innov_m", rec.baro_innov_m, rep.baro_innov_m);
    dbl(s, "g_up_corr", rec.g_up_corr, rep.g_up_corr);
    i64(s, "n_cycles", rec.n_cycles, rep.n_cycles);
    dbl(s, "parity_f[0]", rec.parity_f[0], rep.parity_f[0]);
    dbl(s, "parity_f[1]", rec.parity_f[1], rep.parity_f[1]);
    i64(s, "acc_excluded", rec.acc_excluded, rep.acc_excluded);
    i64(s, "acc_rebuilt", rec.acc_rebuilt, rep.acc_rebuilt);
    i64(s, "resync_count", rec.resync_count, rep.resync_count);
    i64(s, "coast_steps", rec.coast_steps, rep.coast_steps);
    dbl(s, "outage_s", rec.outage_s, rep.outage_s);
    dbl(s, "state_lag_s", rec.state_lag_s, rep.state_lag_s);
  }

 private:
  void add(int64_t seq, const std::string& f, std::string a, std::string b) {
    ++count;
    if (list.size() < keep) list.push_back({seq, f, std::move(a), std::move(b)});
  }
};

// Encoded bytes of a message, for comparing copies.
template <class M, int (*Enc)(void*, int, int, const M*), int (*Size)(const M*)>
std::vector<uint8_t> bytes(const M& m) {
  std::vector<uint8_t> b(static_cast<size_t>(Size(&m)));
  Enc(b.data(), 0, static_cast<int>(b.size()), &m);
  return b;
}

std::vector<uint8_t> frame_bytes(ggins_sensor_frame_t m) {
  m.resent = 0;  // transport: differs between copies of one frame
  std::memset(m.mac, 0, sizeof m.mac);  // and so does its MAC (hal_sim/bus_auth.h)
  return bytes<ggins_sensor_frame_t, ggins_sensor_frame_t_encode, ggins_sensor_frame_t_encoded_size>(m);
}
std::vector<uint8_t> output_bytes(ggins_nav_output_t m) {
  m.republished = 0;
  std::memset(m.mac, 0, sizeof m.mac);
  return bytes<ggins_nav_output_t, ggins_nav_output_t_encode, ggins_nav_output_t_encoded_size>(m);
}

struct Options {
  std::string log;
  std::string prefix = "GGINS_";
  std::optional<int64_t> run_id;
  std::string json_out;
  int show = 20;
  bool quiet = false;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "ggins replay: feed a recorded run's sensor frames through the firmware again and\n"
      "compare every navigation output with the recorded one, bit for bit.\n\n"
      "Reads the LCM log of a run (`ggins run` writes run.lcmlog: every message of the\n"
      "run). From it: the configuration message (<prefix>CONFIG), the sensor frames\n"
      "(<prefix>FRAME) and the navigation outputs (<prefix>NAV) of one run id. The frames\n"
      "go through gg_nav2d_init / gg_nav2d_task_cycle of this build in-process, via the same\n"
      "message conversions as hal_sim (hal_sim/hal_lcm.c): in seq order, each seq once, as\n"
      "hal_sim's reorder window delivered them (duplicates, reordering, undecodable payloads\n"
      "and other runs' messages in the log are counted and skipped; copies of one frame must\n"
      "be identical but for `resent`). If hal_sim reported frames it gave up on\n"
      "(hal_status_t.frames_lost > 0), only the frames with a recorded output are replayed.\n\n"
      "Compared: every field of nav_output_t (doubles by bit pattern) except cycles[], the\n"
      "HAL cycle-counter timing. The recorded cycles[GG_MOD_TOTAL] is fed back through the\n"
      "replay HAL's cycle counter so the firmware's deadline check reproduces the recorded\n"
      "GG_HEALTH_DEADLINE bit, which is compared with the rest of health. Republished copies\n"
      "of an output (answers to duplicate frames) must equal the first publication.\n\n"
      "Exit status: 0 bit-exact; 1 a difference (listed); 2 bad arguments or unreadable log;\n"
      "3 nothing to compare (no configuration, no frames or no outputs of the run).",
      "ggins replay"};
  app.add_option("log", o.log, "LCM log of the run (run.lcmlog)")->required()->check(CLI::ExistingFile);
  app.add_option("--prefix", o.prefix, "channel prefix of the run")->capture_default_str();
  app.add_option("--run-id", o.run_id, "run id to replay (default: the run id of the first configuration message)");
  app.add_option("--json", o.json_out, "also write the result as JSON to this file");
  app.add_option("--show", o.show, "mismatches listed in full")->capture_default_str();
  app.add_flag("-q,--quiet", o.quiet, "print only the verdict line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  const std::string ch_frame = o.prefix + "FRAME", ch_nav = o.prefix + "NAV", ch_config = o.prefix + "CONFIG",
                    ch_hal = o.prefix + "HAL";
  lcm_eventlog_t* log = lcm_eventlog_create(o.log.c_str(), "r");
  if (!log) {
    std::fprintf(stderr, "ggins replay: cannot open %s as an LCM log\n", o.log.c_str());
    return 2;
  }
  // ---- read the log
  std::vector<ggins_nav2d_config_t> configs;
  struct FrameCopies {
    ggins_sensor_frame_t first{};
    std::vector<uint8_t> bytes;
    int copies = 0;
    bool differ = false;
  };
  std::map<int64_t, FrameCopies> frames;
  struct OutCopies {
    ggins_nav_output_t first{};
    bool have_first = false;  // republished == 0 seen
    ggins_nav_output_t any{};
    std::vector<uint8_t> bytes;
    int copies = 0;
    bool differ = false;
  };
  std::map<int64_t, OutCopies> outs;
  std::optional<ggins_hal_status_t> hal_last;
  int64_t events = 0, frame_undecodable = 0, frame_foreign = 0, nav_undecodable = 0, nav_foreign = 0,
          config_undecodable = 0;
  // pass 1: configuration (run id)
  std::vector<lcm_eventlog_event_t*> evs;
  for (lcm_eventlog_event_t* e; (e = lcm_eventlog_read_next_event(log)) != nullptr;) {
    evs.push_back(e);
    ++events;
  }
  lcm_eventlog_destroy(log);
  for (auto* e : evs) {
    const std::string ch(e->channel, static_cast<size_t>(e->channellen));
    if (ch != ch_config) continue;
    ggins_nav2d_config_t m;
    if (ggins_nav2d_config_t_decode(e->data, 0, static_cast<int>(e->datalen), &m) < 0) {
      ++config_undecodable;
      continue;
    }
    if (!o.run_id) o.run_id = m.run_id;
    if (m.run_id == *o.run_id) configs.push_back(m);
    ggins_nav2d_config_t_decode_cleanup(&m);
  }
  for (auto* e : evs) {
    const std::string ch(e->channel, static_cast<size_t>(e->channellen));
    const int n = static_cast<int>(e->datalen);
    if (ch == ch_frame) {
      ggins_sensor_frame_t m;
      if (ggins_sensor_frame_t_decode(e->data, 0, n, &m) < 0) {
        ++frame_undecodable;
        continue;
      }
      if (!o.run_id || m.run_id != *o.run_id) {
        ++frame_foreign;
        continue;
      }
      auto& fc = frames[m.seq];
      auto b = frame_bytes(m);
      if (fc.copies == 0) {
        fc.first = m;
        fc.bytes = std::move(b);
      } else if (b != fc.bytes) {
        fc.differ = true;
      }
      ++fc.copies;
    } else if (ch == ch_nav) {
      ggins_nav_output_t m;
      if (ggins_nav_output_t_decode(e->data, 0, n, &m) < 0) {
        ++nav_undecodable;
        continue;
      }
      if (!o.run_id || m.run_id != *o.run_id) {
        ++nav_foreign;
        continue;
      }
      auto& oc = outs[m.seq];
      auto b = output_bytes(m);
      if (oc.copies == 0) {
        oc.any = m;
        oc.bytes = std::move(b);
      } else if (b != oc.bytes) {
        oc.differ = true;
      }
      if (m.republished == 0 && !oc.have_first) {
        oc.first = m;
        oc.have_first = true;
      }
      ++oc.copies;
    } else if (ch == ch_hal) {
      ggins_hal_status_t m;
      if (ggins_hal_status_t_decode(e->data, 0, n, &m) < 0) continue;
      if (o.run_id && m.run_id == *o.run_id && (!hal_last || m.seq >= hal_last->seq)) hal_last = m;
    }
  }
  for (auto* e : evs) lcm_eventlog_free_event(e);

  json r;
  r["log"] = o.log;
  r["events"] = events;
  if (configs.empty() || frames.empty() || outs.empty()) {
    std::fprintf(stderr,
                 "ggins replay: nothing to compare in %s: %zu configuration, %zu frame and %zu output messages of run %s "
                 "(channel prefix %s)\n",
                 o.log.c_str(), configs.size(), frames.size(), outs.size(),
                 o.run_id ? std::to_string(*o.run_id).c_str() : "(none)", o.prefix.c_str());
    return 3;
  }
  r["run_id"] = *o.run_id;
  // hal_sim applies the first configuration it receives; the repeats must be the same
  bool config_copies_differ = false;
  for (const auto& c : configs) {
    ggins_nav2d_config_t a = c, b = configs.front();
    a.utime = b.utime = 0;
    std::memset(a.mac, 0, sizeof a.mac);
    std::memset(b.mac, 0, sizeof b.mac);
    if (bytes<ggins_nav2d_config_t, ggins_nav2d_config_t_encode, ggins_nav2d_config_t_encoded_size>(a) !=
        bytes<ggins_nav2d_config_t, ggins_nav2d_config_t_encode, ggins_nav2d_config_t_encoded_size>(b))
      config_copies_differ = true;
  }

  // ---- replay
  gg_nav2d_config_t cfg;
  ggins_config_from_lcm(&configs.front(), &cfg);
  static gg_nav2d_t nav;  // large: static storage
  const gg_status_t init_st = gg_nav2d_init(&nav, &cfg);
  ReplayHal rh;
  gg_hal_t hal{};
  hal.ctx = &rh;
  hal.read_frame = hal_read_frame;
  hal.write_output = hal_write_output;
  hal.cycle_count = hal_cycle_count;
  hal.cycles_per_second = 1000000000u;

  const int64_t frames_lost = hal_last ? hal_last->frames_lost : 0;
  Comparer cmp;
  cmp.keep = static_cast<size_t>(std::max(0, o.show));
  int64_t replayed = 0, compared = 0, no_recorded = 0, skipped = 0, frame_copies_differ = 0, out_copies_differ = 0,
          outputs_without_frame = 0;
  for (const auto& [seq, fc] : frames) {
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
    rh.total = recorded ? static_cast<uint32_t>(it->second.any.cycles[GG_MOD_TOTAL]) : 0u;
    gg_nav2d_task_cycle(&nav, &hal);
    ++replayed;
    if (!rh.have_out) {
      cmp.i64(seq, "(no output from the replay)", 1, 0);
      continue;
    }
    if (!recorded) {
      ++no_recorded;
      continue;
    }
    const OutCopies& oc = it->second;
    if (oc.differ) ++out_copies_differ;
    ggins_nav_output_t rep;
    ggins_output_to_lcm(&rh.out, *o.run_id, &rep);
    cmp.output(oc.have_first ? oc.first : oc.any, rep);
    ++compared;
  }
  for (const auto& [seq, oc] : outs) {
    (void)oc;
    if (!frames.count(seq)) ++outputs_without_frame;
  }

  const int32_t rec_init = hal_last ? hal_last->init_status : -1;
  const bool init_ok = rec_init < 0 || rec_init == static_cast<int32_t>(init_st);
  const bool exact = cmp.count == 0 && frame_copies_differ == 0 && out_copies_differ == 0 && !config_copies_differ &&
                     outputs_without_frame == 0 && init_ok;
  r["bit_exact"] = exact;
  r["init_status"] = {{"replayed", static_cast<int>(init_st)}, {"recorded", rec_init}};
  r["frames"] = {{"seqs", frames.size()},
                 {"replayed", replayed},
                 {"skipped_not_consumed", skipped},
                 {"copies_differing", frame_copies_differ},
                 {"undecodable_payloads", frame_undecodable},
                 {"other_run", frame_foreign}};
  r["outputs"] = {{"recorded_seqs", outs.size()},
                  {"compared", compared},
                  {"replayed_without_recorded_output", no_recorded},
                  {"recorded_without_frame", outputs_without_frame},
                  {"republished_copies_differing", out_copies_differ},
                  {"undecodable", nav_undecodable},
                  {"other_run", nav_foreign}};
  r["configuration_copies_differ"] = config_copies_differ;
  r["hal_frames_lost"] = frames_lost;
  r["mismatching_fields"] = cmp.count;
  r["not_compared"] = "cycles[] (HAL cycle-counter timing); the recorded cycles[GG_MOD_TOTAL] is fed back so the "
                      "DEADLINE health bit is reproduced and compared";
  json ml = json::array();
  for (const auto& m : cmp.list)
    ml.push_back({{"seq", m.seq}, {"field", m.field}, {"recorded", m.recorded}, {"replayed", m.replayed}});
  r["mismatches"] = ml;
  if (!o.json_out.empty()) {
    std::ofstream jf(o.json_out);
    jf << r.dump(2) << "\n";
  }
  if (!o.quiet) {
    std::printf("log %s: %" PRId64 " events, run %" PRId64 "\n", o.log.c_str(), events, *o.run_id);
    std::printf("frames: %zu seqs, %" PRId64 " replayed, %" PRId64 " skipped (not consumed), %" PRId64
                " undecodable payloads and %" PRId64 " of other runs ignored\n",
                frames.size(), replayed, skipped, frame_undecodable, frame_foreign);
    std::printf("outputs: %" PRId64 " compared field by field, bit for bit (all but cycles[], the timing)\n", compared);
    if (no_recorded) std::printf("  %" PRId64 " replayed steps had no recorded output (not compared)\n", no_recorded);
    if (outputs_without_frame) std::printf("  %" PRId64 " recorded outputs have no frame in the log\n", outputs_without_frame);
    if (frame_copies_differ) std::printf("  %" PRId64 " frames have copies that differ (beyond `resent`)\n", frame_copies_differ);
    if (out_copies_differ) std::printf("  %" PRId64 " outputs were republished with different contents\n", out_copies_differ);
    if (config_copies_differ) std::printf("  the configuration messages differ from one another\n");
    if (!init_ok) std::printf("  gg_nav2d_init: recorded status %d, replayed %d\n", rec_init, static_cast<int>(init_st));
    for (const auto& m : cmp.list)
      std::printf("  MISMATCH seq %" PRId64 " %s: recorded %s, replayed %s\n", m.seq, m.field.c_str(), m.recorded.c_str(),
                  m.replayed.c_str());
    if (cmp.count > static_cast<int64_t>(cmp.list.size()))
      std::printf("  ... %" PRId64 " mismatching fields in all\n", cmp.count);
  }
  if (exact)
    std::printf("replay: BIT-EXACT (%" PRId64 " outputs)\n", compared);
  else
    std::printf("replay: DIFFERENT (%" PRId64 " mismatching fields in %" PRId64 " outputs compared)\n", cmp.count, compared);
  return exact ? 0 : 1;
}
