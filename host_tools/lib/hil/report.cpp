#include "report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "frame_names.hpp"
#include "hil_common.hpp"

namespace ggins::hil {

using nlohmann::json;

json report_head(const std::string& tool, const std::string& task, const std::string& scenario, const std::string& source,
                 const std::string& description, const std::string& mode, double rate_hz, double duration_s,
                 const FlightCounts& c, const FlightEnd& e) {
  const bool interrupted = e.code == 130;
  const bool completed = e.error.empty() && c.steps_flown == c.steps_expected;
  json s;
  s["report"] = "ggins flight report";
  s["report_version"] = kReportVersion;
  s["tool"] = tool;
  s["task"] = task;
  s["scenario"] = scenario;
  s["scenario_source"] = source;
  s["description"] = description;
  s["status"] = interrupted ? "interrupted" : (!completed ? "failed" : (e.degraded ? "degraded" : "completed"));
  s["completed"] = completed;
  s["degraded"] = completed && e.degraded;
  s["degraded_reasons"] = (completed && e.degraded) ? json(e.reasons) : json::array();
  s["interrupted"] = interrupted;
  if (!e.error.empty()) {
    s["error"] = e.error;
    s["error_code"] = e.code;  // the exit status it gives (1 failed, 3 no multicast, 130 interrupted)
  }
  s["mode"] = mode;
  s["rate_hz"] = rate_hz;
  s["dt_s"] = c.dt_s;
  s["duration_s"] = duration_s;
  s["flown_s"] = c.final_seq >= 0 ? static_cast<double>(c.final_seq) * c.dt_s : 0.0;
  s["steps_expected"] = c.steps_expected;
  s["steps_flown"] = c.steps_flown;
  // steps without an output: not flown (interrupted, or after a failure of the transport)
  s["steps_unflown"] = c.steps_expected - c.steps_flown;
  s["steps_rejected"] = c.steps_rejected;
  // frames the transport failed on (sent, never answered despite resends); an
  // interruption loses none: its remaining steps are unflown
  s["frames_lost"] = (!e.error.empty() && !interrupted && e.code != 3) ? c.steps_expected - c.steps_flown : 0;
  s["frames_recovered"] = c.frames_recovered;
  s["final_seq"] = c.final_seq;
  return s;
}

int exit_status(const json& r) {
  const std::string st = r.value("status", "failed");
  if (st == "completed") return 0;
  if (st == "degraded") return 4;
  if (st == "interrupted") return 130;
  return r.value("error_code", 1) == 3 ? 3 : 1;
}

void write_json(const std::filesystem::path& p, const json& j) {
  std::ofstream o(p);
  o << j.dump(2) << "\n";
  o.close();
  if (!o) throw Fail("cannot write " + p.string());
}

namespace {

void set_dotted(toml::table& root, const std::string& key, const json& v) {
  toml::table* t = &root;
  std::string rest = key;
  for (size_t dot; (dot = rest.find('.')) != std::string::npos; rest = rest.substr(dot + 1)) {
    const std::string part = rest.substr(0, dot);
    if (!t->contains(part) || !(*t)[part].is_table()) t->insert_or_assign(part, toml::table{});
    t = (*t)[part].as_table();
  }
  if (v.is_boolean())
    t->insert_or_assign(rest, v.get<bool>());
  else if (v.is_number_unsigned())
    t->insert_or_assign(rest, static_cast<int64_t>(v.get<uint64_t>()));
  else if (v.is_number_integer())
    t->insert_or_assign(rest, v.get<int64_t>());
  else if (v.is_number())
    t->insert_or_assign(rest, v.get<double>());
  else if (v.is_string())
    t->insert_or_assign(rest, v.get<std::string>());
}

}  // namespace

void write_effective_scenario(const std::filesystem::path& p, const std::string& name, const std::string& source,
                              const std::string& text, const json& set) {
  std::ostringstream os;
  os << "# scenario " << name << " from " << source << ", as flown: the values below are the effective ones\n"
     << "# (the runner's defaults filled in, command-line overrides applied)\n";
  toml::table t;
  try {
    t = toml::parse(text);
  } catch (const toml::parse_error&) {
    t = toml::table{};
  }
  for (const auto& [k, v] : set.items()) set_dotted(t, k, v);
  os << t << "\n";
  std::ofstream f(p);
  f << os.str();
  f.close();
  if (!f) throw Fail("cannot write " + p.string());
}

json consistency_block(const std::vector<ConsistencyState>& states, int dof, double z, double ratio_lo, double ratio_hi,
                       const std::string& statistic) {
  json c;
  c["statistic"] = statistic;
  c["dof"] = dof;
  c["z"] = z;
  c["ratio_lo"] = ratio_lo;
  c["ratio_hi"] = ratio_hi;
  c["method"] = "two-sided chi-square interval at +-z standard normal quantiles, Wilson-Hilferty (truth/stats.hpp)";
  bool all = !states.empty();
  json st = json::object();
  for (const auto& x : states) {
    const double r = x.sample_rms / x.predicted_sigma;
    const bool in = r >= ratio_lo && r <= ratio_hi;  // a NaN ratio is outside
    all = all && in;
    st[x.key] = {{"sample_rms", x.sample_rms}, {"predicted_sigma", x.predicted_sigma}, {"ratio", r}, {"within", in}};
  }
  c["states"] = st;
  c["all_within"] = all;
  return c;
}

namespace {
bool is_final_max(const json& v) { return v.is_object() && v.contains("final") && v.contains("max"); }
bool is_axes(const json& v) {
  if (!v.is_object() || v.empty()) return false;
  for (const auto& [k, x] : v.items())
    if (!x.is_number()) return false;
  return true;
}
}  // namespace

json ensemble_report(const std::string& tool, const std::string& task, const std::string& scenario,
                     const std::string& source, const std::string& description, const std::string& mode, double rate_hz,
                     double duration_s, const std::vector<EnsembleRun>& runs, int runs_requested, const FlightEnd& end,
                     const std::string& frame, const std::string& definition, const json& consistency,
                     const json& extra) {
  FlightCounts c;
  uint32_t health_or = 0;
  std::map<std::string, int64_t> hc;
  int64_t least_seq = -1;
  for (size_t i = 0; i < runs.size(); ++i) {
    const FlightCounts& r = runs[i].counts;
    c.steps_expected += r.steps_expected;
    c.steps_flown += r.steps_flown;
    c.steps_rejected += r.steps_rejected;
    c.frames_recovered += r.frames_recovered;
    if (r.dt_s > 0) c.dt_s = r.dt_s;
    least_seq = i == 0 ? r.final_seq : std::min(least_seq, r.final_seq);
    health_or |= runs[i].health_or;
    for (const auto& [k, n] : runs[i].health_counts) hc[k] += n;
  }
  c.final_seq = least_seq;
  json s = report_head(tool, task, scenario, source, description, mode, rate_hz, duration_s, c, end);
  s["health_seen"] = health_word(health_or);
  json hcj = json::object();
  for (const auto& [k, n] : hc) hcj[k] = n;
  s["health_counts"] = hcj;

  // errors over the runs: the keys of the first run's block
  json e;
  e["frame"] = frame;
  e["definition"] = definition;
  json per_run = json::array();
  json rms = json::object();
  const EnsembleRun* first = nullptr;  // the first run with errors gives the keys
  for (const auto& r : runs)
    if (!first && !r.errors.empty()) first = &r;
  if (first) {
    for (const auto& [k, v0] : first->errors.items()) {
      if (is_final_max(v0)) {
        double ss = 0, mx = 0;
        int n = 0;
        for (const auto& r : runs) {
          if (!r.errors.contains(k)) continue;
          const double f = r.errors[k].value("final", std::nan("")), m = r.errors[k].value("max", std::nan(""));
          ss += f * f;
          mx = (std::isnan(m) || std::isnan(mx)) ? std::nan("") : std::max(mx, m);
          ++n;
        }
        const double q = n > 0 ? std::sqrt(ss / n) : std::nan("");
        e[k] = {{"final", q}, {"max", mx}};
        rms[k] = q;
      } else if (is_axes(v0)) {
        json ax;
        for (const auto& [a, x0] : v0.items()) {
          (void)x0;
          double ss = 0;
          int n = 0;
          for (const auto& r : runs)
            if (r.errors.contains(k) && r.errors[k].contains(a)) {
              const double x = r.errors[k][a].get<double>();
              ss += x * x;
              ++n;
            }
          ax[a] = n > 0 ? std::sqrt(ss / n) : std::nan("");
        }
        e[k] = ax;
        rms[k] = ax;
      }
    }
  }
  for (const auto& r : runs) {  // every run, also those that flew no output
    json pr = {{"run", r.index}, {"seed", r.seed}, {"status", r.status}, {"steps_flown", r.counts.steps_flown},
               {"health_seen_raw", r.health_or}};
    for (const auto& [k, v] : r.errors.items()) {
      if (is_final_max(v)) {
        // position_error_m -> position_error_final_m: the unit stays last
        const auto us = k.rfind('_');
        pr[k.substr(0, us) + "_final" + k.substr(us)] = v["final"];
      }
    }
    per_run.push_back(pr);
  }
  s["errors"] = e;
  s["aids"] = json::array();
  int failed = 0, flown = 0;
  for (const auto& r : runs) {
    if (r.status != "completed" && r.status != "degraded") ++failed;
    if (r.counts.steps_flown > 0) ++flown;
  }
  json en = {{"runs", runs_requested},
             {"runs_flown", flown},  // runs with a step flown
             {"runs_failed", failed + (runs_requested - static_cast<int>(runs.size()))},  // not completed
             {"errors_over_runs", "final: RMS over the runs of each run's final value; max: the largest of any run"},
             {"rms", rms},
             {"per_run", per_run},
             {"consistency", consistency}};
  for (const auto& [k, v] : extra.items()) en[k] = v;
  s["ensemble"] = en;
  return s;
}

}  // namespace ggins::hil
