#include "report.hpp"

#include <fstream>
#include <sstream>

#include <toml++/toml.h>

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

}  // namespace ggins::hil
