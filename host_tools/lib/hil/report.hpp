// The report of a flight (summary.json), one shape for every command that flies
// (`ggins run`, `ggins run3d`, aided runs, and the Monte Carlo ensembles `ggins
// montecarlo` / `ggins montecarlo3d`):
//
//   report, report_version, tool, task ("2-D" | "3-D"), scenario, scenario_source, description
//   status             "completed" | "degraded" | "failed" | "interrupted"
//   completed, degraded, interrupted (booleans); error, error_code (text and exit status, when not completed)
//   degraded_reasons   why a completed flight is degraded (list of sentences; empty otherwise)
//   mode               "lockstep" | "realtime" | "direct"
//   rate_hz, dt_s, duration_s (the scenario as flown), flown_s (time of the last step flown)
//   steps_expected, steps_flown, steps_unflown, steps_rejected, frames_lost, frames_recovered, final_seq
//   health_seen        {raw, hex, bits}: the OR of every output's health word, decoded (frame_names.hpp)
//   health_counts      {BIT_NAME: outputs with the bit set}
//   errors             the task's error metrics against truth, final (last step flown) and max;
//                      "frame" names the axes, every key carries its unit
//   aids               a list of aid blocks ({"name": ..., counters}), empty without aids
//   map_build_s (3-D: wall time of the maps built before the flight, map_tiles {built,
//   from_cache, cache_dir} of map_from_field: run3d field_map.hpp; setup_s: the link and
//   processes; wall_s: the flight), recovery, wall_s, setup_s, cpu_s, realtime_factor, steps_per_s, firmware_step_ns,
//   transport, bus_auth, realtime, hal_sim, log, lcm_url(s), channel_prefix, run_id, files, output_dir
//   and the task's own blocks (2-D: vertical, horizontal, gravimeter, baro; 3-D: parity, acceptance).
//
// A Monte Carlo ensemble (ensemble_report) has the same head, health and errors, its
// steps summed over the runs and its errors taken over them (final: RMS over the runs
// of each run's final value; max: the largest of any run), and the block
//   ensemble           runs, runs_flown, runs_failed, seeds, per_run [{run, seed, status,
//                      steps_flown, health_seen_raw, <quantity>_final_<unit> ...}], rms {..},
//                      consistency {statistic, dof, z, ratio_lo, ratio_hi, states {key:
//                      {sample_rms, predicted_sigma, ratio, within}}, all_within}
//
// Exit status from the report (exit_status): 0 completed; 4 completed but degraded;
// 1 failed; 130 interrupted (3: no multicast on loopback, 2: bad arguments, before a report).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ggins::hil {

constexpr int kReportVersion = 2;

// What every flight counts, whatever its task.
struct FlightCounts {
  int64_t steps_expected = 0;  // steps of the scenario as flown
  int64_t steps_flown = 0;     // outputs taken (in seq order, once per step)
  int64_t final_seq = -1;      // seq of the last step flown
  int64_t steps_rejected = 0;  // outputs with a status other than GG_OK
  int64_t frames_recovered = 0;
  double dt_s = 0;
};

// How the flight ended.
struct FlightEnd {
  std::string error;  // empty: flown to the end
  int code = 0;       // Fail code (130 interrupted, 3 no multicast, 1 otherwise)
  bool degraded = false;
  std::vector<std::string> reasons;  // why degraded, one sentence each (summary.json degraded_reasons)
};

// The head of the report: identity, status and step accounting (see above).
nlohmann::json report_head(const std::string& tool, const std::string& task, const std::string& scenario,
                           const std::string& source, const std::string& description, const std::string& mode,
                           double rate_hz, double duration_s, const FlightCounts& c, const FlightEnd& e);

// The exit status of a report (see above).
int exit_status(const nlohmann::json& report);

// Write a JSON file; an output that cannot be written is an error (Fail).
void write_json(const std::filesystem::path& p, const nlohmann::json& j);

// The scenario as flown: the file's TOML with the effective values (defaults the
// runner uses filled in, command-line overrides applied) set in its tables,
// written to scenario.toml; `set` holds dotted keys ("time.duration_s") and values.
void write_effective_scenario(const std::filesystem::path& p, const std::string& name, const std::string& source,
                              const std::string& text, const nlohmann::json& set);

// ---- Monte Carlo ensembles ----------------------------------------------------------------

// One flight of an ensemble, as the report counts it.
struct EnsembleRun {
  int index = 0;
  uint64_t seed = 0;
  std::string status;  // the flight's own status (completed, degraded, failed, interrupted)
  FlightCounts counts;
  uint32_t health_or = 0;
  std::map<std::string, int64_t> health_counts;  // {BIT_NAME: outputs with the bit set}
  // the flight's errors as in its report: {<quantity>_<unit>: {final, max}} and the
  // per-axis finals {<quantity>_final_<unit>: {axis: value}}
  nlohmann::json errors = nlohmann::json::object();
};

// One state of the consistency check: the sample one-sigma over the runs against the
// covariance's prediction (key with its unit).
struct ConsistencyState {
  std::string key;
  double sample_rms = 0, predicted_sigma = 0;
};

// The consistency block: ratio = sample_rms / predicted_sigma against the chi-square
// band [ratio_lo, ratio_hi] for `dof` degrees of freedom at +-z (truth/stats.hpp).
nlohmann::json consistency_block(const std::vector<ConsistencyState>& states, int dof, double z, double ratio_lo,
                                 double ratio_hi, const std::string& statistic);

// The report of an ensemble: report_head with the runs' steps summed (final_seq: the
// least any run reached), health seen over every run, the errors over the runs (frame,
// definition), and the ensemble block (per_run, rms, `consistency`, `extra` merged in).
nlohmann::json ensemble_report(const std::string& tool, const std::string& task, const std::string& scenario,
                               const std::string& source, const std::string& description, const std::string& mode,
                               double rate_hz, double duration_s, const std::vector<EnsembleRun>& runs,
                               int runs_requested, const FlightEnd& end, const std::string& frame,
                               const std::string& definition, const nlohmann::json& consistency,
                               const nlohmann::json& extra);

}  // namespace ggins::hil
