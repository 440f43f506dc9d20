#include "ggins/truth/scenario.hpp"
#include "ggins/truth/fdi_thresholds.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "ggins/gravity/normal.hpp"
#include "ggins/truth/scenario_keys.hpp"
#include "ggins/truth/scenario_schema.hpp"
#include "ggins/truth/scenario_toml.hpp"
#include "sensor_faults_parse.hpp"

namespace ggins::truth {

// Generated at configure time from scenarios/*.toml (builtin_scenarios.cpp).
struct BuiltinScenario {
  const char* name;
  const char* text;
};
extern const BuiltinScenario kBuiltinScenarios[];
extern const int kBuiltinScenarioCount;


int64_t Scenario::dt_us() const { return static_cast<int64_t>(std::llround(1e6 / rate_hz)); }

int64_t Scenario::baro_every() const {
  return std::max<int64_t>(1, static_cast<int64_t>(std::llround(rate_hz / baro.rate_hz)));
}

NavModelParams Scenario::nav_model() const {
  if (navigation.model.set) return navigation.model;
  NavModelParams m;
  m.set = true;
  if (gravity.model == "point-mass") {
    m.gm_m3ps2 = gravity.gm_m3ps2;
    m.a_m = trajectory.radius_m;
  } else {  // the WGS-84 normal field's zonal series: GM, a, J2, J4, J6, J8
    const gravity::NormalField n;
    m.gm_m3ps2 = static_cast<double>(n.params().gm);
    m.a_m = static_cast<double>(n.params().a);
    for (int k = 1; 2 * k <= 8; ++k) m.j[static_cast<size_t>(2 * k)] = static_cast<double>(n.j2n(k));
  }
  return m;
}

int64_t Scenario::n_steps() const {
  return static_cast<int64_t>(std::llround(duration_s * 1e6 / static_cast<double>(dt_us()))) + 1;
}

namespace {

namespace sch = ggins::truth::sch;
using S = Scenario;

std::vector<std::pair<std::string, std::optional<std::string>>> write_sensor_faults(const SensorFaultParams& p) {
  std::vector<std::pair<std::string, std::optional<std::string>>> out;
  out.emplace_back("seed", std::to_string(p.seed));
  if (p.faults.empty()) return out;
  std::string a = "[";
  for (size_t i = 0; i < p.faults.size(); ++i) {
    const SensorFault& f = p.faults[i];
    a += std::string(i ? ",\n  " : "\n  ") + "{kind = " + sch::str_text(f.kind) +
         ", sensor = " + std::to_string(f.sensor) + ", axis = " + (f.axis == 0 ? "\"x\"" : "\"z\"") +
         ", start_s = " + sch::num_text(f.start_s) + ", duration_s = " + sch::num_text(f.duration_s) +
         ", size = " + sch::num_text(f.size) + ", prob = " + sch::num_text(f.prob) + "}";
  }
  out.emplace_back("fault", a + "\n]");
  return out;
}

sch::Schema<S> build_schema() {
  sch::Schema<S> sc;
  sc.title = "2-D scenario (ggins run, covariance, montecarlo)";
  auto& secs = sc.secs;
  {
    sch::Table<S> t("", "Name and description.");
    t.custom(truth::keys::name_key<S>()).str("description", &S::description, {}, "one line shown by --list-scenarios");
    secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<TrajectoryParams> t("trajectory", "The analytic trajectory (truth/trajectory.hpp).");
    using T = TrajectoryParams;
    t.str("type", &T::type, {"north-flight"}, "northward great-circle flight at constant speed and height")
        .num("speed_mps", &T::speed_mps, "m/s", sch::in(-3e4, 3e4), "ground speed")
        .num("height_m", &T::height_m, "m", sch::in(-1e4, 1e8), "height above radius_m")
        .num("lat0_deg", &T::lat0_deg, "deg", sch::in(-90, 90), "start latitude")
        .num("radius_m", &T::radius_m, "m", sch::in_lopen(0, 1e9), "Earth radius of the flight (the paper's R_e)");
    secs.push_back(sch::section<S>(t, &S::trajectory));
  }
  {
    sch::Table<GravityParams> t("gravity", "The truth gravity field.");
    using G = GravityParams;
    t.str("model", &G::model, {"point-mass", "wgs84-normal", "rw-anomaly"},
          "point mass; WGS-84 normal field; WGS-84 normal field + buried point masses ([gravity.anomaly])")
        .num("gm_m3ps2", &G::gm_m3ps2, "m^3/s^2", sch::in_lopen(0, 1e21), "GM of the point-mass model");
    secs.push_back(sch::section<S>(t, &S::gravity));
    secs.push_back(sch::section<S>(keys::anomaly_table("the trajectory's mid-latitude", "0"),
                                   std::function<AnomalyParams&(S&)>([](S& s) -> AnomalyParams& { return s.gravity.anomaly; }),
                                   [](const S& s) { return s.gravity.model == "rw-anomaly"; }));
  }
  {
    sch::Table<S> t("platform", "The gradiometer's geometry (four accelerometers).");
    t.num("a_m", &S::a_m, "m", sch::in_lopen(0, 100), "half-baseline along x")
        .num("b_m", &S::b_m, "m", sch::in_lopen(0, 100), "half-baseline along z");
    secs.push_back(sch::section<S>(t));
  }
  secs.push_back(sch::section<S>(keys::time_table<S>()));
  {
    auto t = keys::accel_table(0, kMaxAcc);
    t.custom(keys::per_axis_key<AccelErrorParams>("scale", &AccelErrorParams::scale, "1", 0, kMaxAcc,
                                                  "fixed scale-factor error per accelerometer axis"));
    secs.push_back(sch::section<S>(t, &S::accel));
  }
  {
    sch::Table<FirmwareParams> t("firmware", "The firmware's configuration (nav2d.h, fdi2d.h).");
    using F = FirmwareParams;
    keys::firmware_keys(t);
    t.boolean("gravdr_trapezoid_only", &F::gravdr_trapezoid_only, "gravity integration by the trapezoid rule only")
        .num("fdi_parity_f_max_mps2", &F::fdi_parity_f_max_mps2, "m/s^2", sch::in(0, 1e6),
             "accelerometer parity fault detection threshold (0: off)")
        .derived_unless_given(&F::fdi_parity_f_max_set,
                              "derived from the sensor errors drawn for the flight, baseline and field (fdi_thresholds.hpp)")
        .num("fdi_asym_max_ps2", &F::fdi_asym_max_ps2, "1/s^2", sch::in(0, 1),
             "gradient-symmetry fault detection threshold (0: off)")
        .derived_unless_given(&F::fdi_asym_max_set,
                              "derived from the sensor errors drawn for the flight, baseline and field (fdi_thresholds.hpp)");
    secs.push_back(sch::section<S>(t, &S::firmware));
  }
  {
    sch::Table<TransportParams> t("transport", "Faults of the frame transport to the firmware (hal_sim).");
    using P = TransportParams;
    t.seed("seed", &P::seed, "seed of the transport faults")
        .num("drop_prob", &P::drop_prob, "1", sch::prob(), "a frame's first transmission is dropped")
        .num("duplicate_prob", &P::duplicate_prob, "1", sch::prob(), "a frame is sent twice")
        .num("reorder_prob", &P::reorder_prob, "1", sch::prob(), "frame k+1 is sent before frame k")
        .num("output_drop_prob", &P::output_drop_prob, "1", sch::prob(), "hal_sim does not send a navigation output")
        .num("garbage_prob", &P::garbage_prob, "1", sch::prob(), "an undecodable payload precedes a frame");
    secs.push_back(sch::section<S>(t, &S::transport));
  }
  {
    sch::Table<NavigationParams> t("navigation", "What the firmware navigates with beyond the sensors (nav2d.h).");
    using N = NavigationParams;
    t.str("gravity", &N::gravity, {"gradiometer", "model"},
          "gravity from the gradiometer's integrated gradient, or from the onboard model")
        .num("r_ref_m", &N::r_ref_m, "m", sch::in(0, 1e9),
             "reference radius of the altitude h = |r| - r_ref_m (0: trajectory.radius_m)");
    secs.push_back(sch::section<S>(t, &S::navigation));
  }
  {
    sch::Table<NavModelParams> t("navigation.model",
                                 "The onboard zonal gravity model (gmodel.h), model mode. Without this table: the "
                                 "truth field's normal part (point mass: GM, J = 0; else WGS-84 GM, a, J2..J8).");
    using M = NavModelParams;
    t.num("gm_m3ps2", &M::gm_m3ps2, "m^3/s^2", sch::in_lopen(0, 1e21), "GM of the model")
        .default_doc("gm_m3ps2", "gravity.gm_m3ps2")
        .num("a_m", &M::a_m, "m", sch::in_lopen(0, 1e9), "its reference radius")
        .default_doc("a_m", "trajectory.radius_m");
    sch::Key<M> j = sch::mk<M>("j", "array of 0..7 numbers", "1", "each finite", "zonal coefficients J2, ..., J8", "");
    j.read = [](M& m, const toml::node& n, const sch::Ctx& c, const std::string& p) {
      const std::vector<double> v = sch::read_nums(n, c, p, 0, 7, sch::any(), "");
      for (size_t i = 0; i < v.size(); ++i) m.j[i + 2] = v[i];
    };
    j.write = [](const M& m) -> std::optional<std::string> {
      std::string s = "[";
      for (size_t i = 2; i < m.j.size(); ++i) s += (i > 2 ? ", " : "") + sch::num_text(m.j[i]);
      return s + "]";
    };
    t.custom(j).default_doc("j", "[] (all zero)");
    secs.push_back(sch::section<S>(
        t, std::function<M&(S&)>([](S& s) -> M& { return s.navigation.model; }),
        [](const S& s) { return s.navigation.model.set; },
        [](S& s) {
          s.navigation.model.set = true;
          s.navigation.model.gm_m3ps2 = s.gravity.gm_m3ps2;
          s.navigation.model.a_m = s.trajectory.radius_m;
        }));
    secs.back().presence_matters = true;
  }
  {
    sch::Table<SurveyParams> t("navigation.survey",
                               "The anomaly grid programmed into the onboard model (gmodel.h polar grid; "
                               "truth/survey.hpp): the truth disturbance at the nodes plus seeded survey noise.");
    using V = SurveyParams;
    t.boolean("enable", &V::enable, "program the grid")
        .default_doc("enable", "true when the table is present")
        .on_present([](V& v) { v.enable = true; })
        .seed("seed", &V::seed, "seed of the survey noise")
        .num("spacing_m", &V::spacing_m, "m", sch::in(10, 1e6), "along-track node spacing at the flight radius")
        .num("margin_m", &V::margin_m, "m", sch::in(0, 1e6), "the grid extends this far before the start and after the end")
        .integer("n_rho", &V::n_rho, "", sch::in(2, 64), "nodes in radius, centred on the flight radius")
        .num("drho_m", &V::drho_m, "m", sch::in(1, 1e5), "their spacing")
        .num("noise_gravity_mgal", &V::noise_gravity_mgal, "mGal", sch::in(0, 1e6), "radial component noise, 1 sigma")
        .num("noise_deflection_arcsec", &V::noise_deflection_arcsec, "arcsec", sch::in(0, 3600),
             "tangential component noise, 1 sigma, as g x deflection");
    secs.push_back(sch::section<S>(t, std::function<V&(S&)>([](S& s) -> V& { return s.navigation.survey; }),
                                   [](const S& s) { return s.navigation.survey.enable; }));
  }
  secs.push_back(sch::section<S>(keys::baro_loop_table(),
                                 std::function<BaroLoopParams&(S&)>([](S& s) -> BaroLoopParams& { return s.navigation.baro; })));
  {
    auto t = keys::baro_table();
    using B = BaroParams;
    t.num("dropout_prob", &B::dropout_prob, "1", sch::prob(), "a sample is missing (status ABSENT)")
        .custom([] {
          sch::Key<B> k = sch::mk<B>("dropouts", "array of [t0_s, t1_s]", "s", "finite, t1_s > t0_s",
                                     "scheduled windows [t0, t1) without samples", "");
          k.read = [](B& b, const toml::node& n, const sch::Ctx& c, const std::string& p) {
            const toml::array* rows = n.as_array();
            if (!rows) c.fail_at(&n, p, p + " = " + sch::value_text(n) + ": must be an array of [t0_s, t1_s] pairs");
            for (size_t i = 0; i < rows->size(); ++i) {
              const std::string pi = p + "[" + std::to_string(i) + "]";
              const auto v = sch::read_nums((*rows)[i], c, pi, 2, 2, sch::any(), "s");
              if (!(v[1] > v[0])) c.fail_at(&(*rows)[i], pi, pi + " = " + sch::value_text((*rows)[i]) + ": needs t1_s > t0_s");
              b.dropouts.push_back({v[0], v[1]});
            }
          };
          k.write = [](const B& b) -> std::optional<std::string> {
            std::string s = "[";
            for (size_t i = 0; i < b.dropouts.size(); ++i)
              s += (i ? ", [" : "[") + sch::num_text(b.dropouts[i][0]) + ", " + sch::num_text(b.dropouts[i][1]) + "]";
            return s + "]";
          };
          return k;
        }())
        .default_doc("dropouts", "[] (none)")
        .num("outlier_prob", &B::outlier_prob, "1", sch::prob(), "a sample is off by +-outlier_m")
        .num("outlier_m", &B::outlier_m, "m", sch::in(0, 1e6), "size of an outlier")
        .num("invalid_prob", &B::invalid_prob, "1", sch::prob(), "a sample is NaN with status OK (the firmware must notice)")
        .num("latency_s", &B::latency_s, "s", sch::in(0, 3600),
             "the sample is the altitude latency_s before its frame, stamped so (whole microseconds)");
    secs.push_back(sch::section<S>(t, &S::baro, [](const S& s) { return s.baro.enable; }));
  }
  secs.push_back(sch::delegated_section<S>(
      "sensor_faults", "Injected sensor faults (sensor_faults.hpp).", keys::sensor_fault_rows(fault_instrument2d()),
      [](S& s, const toml::table& t, const sch::Ctx& c) { s.sensor_faults = parse_sensor_faults(t, c); },
      [](const S& s) { return write_sensor_faults(s.sensor_faults); },
      [](const S& s) { return !s.sensor_faults.faults.empty(); }));
  {
    sch::Table<OutputParams> t("output", "What the run writes.");
    using O = OutputParams;
    t.num("csv_rate_hz", &O::csv_rate_hz, "Hz", sch::in_lopen(0, 1e6), "rows per second of timeseries.csv")
        .num("truth_rate_hz", &O::truth_rate_hz, "Hz", sch::in(0, 1e6), "truth messages on LCM per second (0: every step)");
    secs.push_back(sch::section<S>(t, &S::output));
  }
  return sc;
}

}  // namespace

const sch::Schema<Scenario>& scenario_schema() {
  static const sch::Schema<Scenario> s = build_schema();
  return s;
}

std::string scenario_to_toml(const Scenario& s, bool template_comments) {
  std::string head = template_comments ? "# 2-D scenario: every key with its default (ggins run --print-scenario --defaults;\n"
                                         "# docs/scenario-reference.md). A commented key is derived unless given.\n"
                                       : "# scenario " + s.name + " as flown (defaults filled in, overrides applied)\n";
  return head + scenario_schema().to_toml(s, template_comments);
}

Scenario parse_scenario(const std::string& text, const std::string& fallback_name, const std::string& source,
                        const ScenarioAdjust& adjust) {
  return parse_scenario_table(sch::parse_toml(text, source), text, fallback_name, source, adjust);
}

Scenario parse_scenario_table(const toml::table& root, const std::string& text, const std::string& fallback_name,
                              const std::string& source, const ScenarioAdjust& adjust) {
  const sch::Ctx c{source};
  Scenario s;
  s.source = source;
  s.text = text;
  s.name = fallback_name;
  scenario_schema().read(s, root, c);
  if (s.name.empty() || s.name.size() > 63) c.fail("name must have 1..63 characters (give name = \"...\")");

  // relations between keys
  if (!(s.trajectory.radius_m + s.trajectory.height_m > 1.0))
    c.fail_key(root, "trajectory.height_m", "trajectory.radius_m + height_m must be > 1 m");
  {
    const double dt = 1e6 / s.rate_hz;
    if (std::fabs(dt - std::round(dt)) > 1e-9 * dt)
      c.fail_key(root, "time.rate_hz",
                 "time.rate_hz = " + sch::num_text(s.rate_hz) +
                     ": must make 1e6/rate_hz an integer number of microseconds");
  }
  const auto& l = s.navigation.baro;
  if (!(l.alt_max_m > l.alt_min_m))
    c.fail_key(root, "navigation.baro.alt_max_m", "navigation.baro: alt_max_m must be > alt_min_m");
  const auto& b = s.baro;
  if (std::fabs(b.latency_s * 1e6 - std::round(b.latency_s * 1e6)) > 1e-6)
    c.fail_key(root, "baro.latency_s", "baro.latency_s = " + sch::num_text(b.latency_s) +
                                           ": must be a whole number of microseconds");
  if (s.baro.enable) {
    const double every = s.rate_hz / s.baro.rate_hz;
    if (!(every >= 1.0) || std::fabs(every - std::round(every)) > 1e-9 * every)
      c.fail_key(root, "baro.rate_hz", "baro.rate_hz must divide time.rate_hz (an integer number of steps per sample)");
  }
  if (s.baro_loop_enabled()) {
    const double pmax = std::max({l.poles_radps[0], l.poles_radps[1], l.poles_radps[2]});
    if (pmax * s.baro_period_s() > 1.0)
      c.fail_key(root, "navigation.baro.poles_radps",
                 "navigation.baro: largest pole times period_s must be <= 1 (vchan.h)");
  }
  if (adjust) adjust(s);
  // the fault thresholds and the frozen-reading window the file did not give, derived for the
  // flight as flown (the drawn biases, the duration)
  apply_default_fdi_thresholds(s);
  return s;
}


std::vector<std::string> builtin_scenario_names() {
  std::vector<std::string> v;
  for (int i = 0; i < kBuiltinScenarioCount; ++i) v.emplace_back(kBuiltinScenarios[i].name);
  return v;
}

static void refuse_empty(const std::string& text, const std::string& path) {
  if (toml::parse(text).empty())
    throw std::runtime_error("scenario " + path +
                             ": sets no key (allowed: a scenario that sets at least one key; an empty file would fly "
                             "every default: start from ggins run --print-scenario --defaults)");
}

Scenario load_scenario(const std::string& name_or_path, const std::vector<std::string>& search_dirs,
                       const ScenarioAdjust& adjust) {
  namespace fs = std::filesystem;
  auto read_file = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read scenario file " + p.string());
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  std::error_code ec;
  const fs::path p(name_or_path);
  if (fs::is_regular_file(p, ec)) {
    Scenario s = parse_scenario(read_file(p), p.stem().string(), p.string(), adjust);
    refuse_empty(s.text, p.string());
    return s;
  }
  const bool looks_like_path =
      name_or_path.find('/') != std::string::npos || p.extension() == ".toml";
  if (looks_like_path) throw std::runtime_error("scenario file not found: " + name_or_path);
  for (const auto& d : search_dirs) {
    const fs::path f = fs::path(d) / (name_or_path + ".toml");
    if (fs::is_regular_file(f, ec)) {
      Scenario s = parse_scenario(read_file(f), name_or_path, f.string(), adjust);
      refuse_empty(s.text, f.string());
      return s;
    }
  }
  for (int i = 0; i < kBuiltinScenarioCount; ++i)
    if (name_or_path == kBuiltinScenarios[i].name)
      return parse_scenario(kBuiltinScenarios[i].text, name_or_path, "built-in:" + name_or_path, adjust);
  std::string known;
  for (const auto& n : builtin_scenario_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::runtime_error("unknown scenario '" + name_or_path + "' (built-in: " + known +
                           "; or give a path to a .toml file)");
}

}  // namespace ggins::truth
