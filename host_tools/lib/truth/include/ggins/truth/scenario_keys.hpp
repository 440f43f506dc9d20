// Scenario tables shared by the 2-D and 3-D scenarios (scenario_schema.hpp): the keys
// both read, defined once. A builder returns the table with the keys in common; a
// parser adds its own (e.g. the 2-D barometer's dropouts) before binding it.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ggins/limits.h"
#include "ggins/truth/scenario.hpp"
#include "ggins/truth/scenario_schema.hpp"

namespace ggins::truth::keys {

// The top-level `name` key of every scenario kind (S has a std::string name): 1..63
// characters; not written while empty (the file name stands for it).
template <class S>
sch::Key<S> name_key() {
  sch::Key<S> name = sch::mk<S>("name", "string", "", "1..63 characters", "the scenario's name (report, output folder)",
                                "the file name without .toml");
  name.read = [](S& s, const toml::node& n, const sch::Ctx& c, const std::string& p) {
    s.name = sch::read_str(n, c, p, {});
    if (s.name.empty() || s.name.size() > 63)
      c.fail_at(&n, p, p + " = " + sch::value_text(n) + ": must have 1..63 characters");
  };
  name.write = [](const S& s) -> std::optional<std::string> {
    if (s.name.empty()) return std::nullopt;
    return sch::str_text(s.name);
  };
  return name;
}

// [gravity.anomaly]: the Rubenstein & Winter buried point masses (gravity/point_anomaly.hpp).
inline sch::Table<AnomalyParams> anomaly_table(const std::string& centre_doc, const std::string& lon_doc) {
  sch::Table<AnomalyParams> t("gravity.anomaly",
                              "Gravity anomaly field of model \"rw-anomaly\": the WGS-84 normal field plus buried "
                              "point masses with Rubenstein & Winter statistics on a lattice (gravity/point_anomaly.hpp).");
  using A = AnomalyParams;
  t.seed("seed", &A::seed, "seed of the point-mass draw")
      .num("lat_deg", &A::lat_deg, "deg", sch::in(-90, 90), "latitude of the region's centre", NAN, centre_doc)
      .num("lon_deg", &A::lon_deg, "deg", sch::in(-360, 360), "longitude of the region's centre", NAN, lon_doc)
      .num("half_size_m", &A::half_size_m, "m", sch::in_lopen(0, 2e7), "half the side of the square region")
      .num("ref_height_m", &A::ref_height_m, "m", sch::in(-1e4, 1e6),
           "height at which the statistics hold (rms deflection)", NAN, "trajectory.height_m")
      .num("rms_arcsec", &A::rms_arcsec, "arcsec", sch::in(0, 3600),
           "rms vertical deflection at ref_height_m (Rubenstein & Winter eq. (5))")
      .num("corr_length_m", &A::corr_length_m, "m", sch::in_lopen(0, 1e7), "correlation length of the deflection")
      .num("ewald_sigma_m", &A::ewald_sigma_m, "m", sch::in_lopen(0, 1e7),
           "Ewald split length of the lattice sum (gravity/lattice.hpp)")
      .num("lattice_spacing_m", &A::lattice_spacing_m, "m", sch::in_lopen(0, 1e7), "spacing of the point masses")
      .integer("lattice_points", &A::lattice_points, "", sch::in(2, 16), "points per lattice cell edge", true);
  return t;
}

// [navigation.baro]: the firmware's barometric vertical loop (vchan.h).
inline sch::Table<BaroLoopParams> baro_loop_table() {
  sch::Table<BaroLoopParams> t("navigation.baro", "The firmware's barometric vertical channel loop (vchan.h).");
  using B = BaroLoopParams;
  t.tristate("enable", &B::enable, "loop on", "baro.enable")
      .vec<3>("poles_radps", &B::poles_radps, "rad/s", sch::in_lopen(0, 1e3),
              "the loop's poles are -p (third-order loop)")
      .num("period_s", &B::period_s, "s", sch::in(0, 3600), "loop update period (0: 1 / baro.rate_hz)")
      .num("omega_s2", &B::omega_s2, "1/s^2", sch::in(0, 1),
           "vertical gravity gradient of the loop (0: |G(r0)| / |r0| from the truth at t0)")
      .num("max_age_s", &B::max_age_s, "s", sch::in(0, 3600), "oldest barometer sample the loop takes")
      .num("coast_s", &B::coast_s, "s", sch::in_lopen(0, 1e6), "coasting time without samples before the loop drops out")
      .num("alt_min_m", &B::alt_min_m, "m", sch::in(-1e5, 1e6), "lowest valid barometric altitude")
      .num("alt_max_m", &B::alt_max_m, "m", sch::in(-1e5, 1e6), "highest valid barometric altitude (> alt_min_m)")
      .num("gate_m", &B::gate_m, "m", sch::in_lopen(0, 1e6), "innovation gate")
      .integer("max_rejects", &B::max_rejects, "", sch::in(1, 1e6), "rejections in a row before the loop resets");
  return t;
}

// [baro]: the truth generator's barometer (keys both scenarios have).
inline sch::Table<BaroParams> baro_table() {
  sch::Table<BaroParams> t("baro", "The truth barometer (none without this table).");
  using B = BaroParams;
  t.boolean("enable", &B::enable, "a barometer flies")
      .default_doc("enable", "true when the table is present")
      .on_present([](B& b) { b.enable = true; })
      .seed("seed", &B::seed, "seed of the barometer's errors")
      .num("rate_hz", &B::rate_hz, "Hz", sch::in_lopen(0, 1e6), "sample rate (divides time.rate_hz)")
      .num("bias_m", &B::bias_m, "m", sch::in(-1e5, 1e5), "constant bias")
      .num("gm_sigma_m", &B::gm_sigma_m, "m", sch::in(0, 1e5), "first-order Gauss-Markov error, stationary sigma")
      .num("gm_tau_s", &B::gm_tau_s, "s", sch::in_lopen(0, 1e9), "its correlation time")
      .num("noise_sigma_m", &B::noise_sigma_m, "m", sch::in(0, 1e5), "white noise per sample, 1 sigma");
  return t;
}

// [firmware]: the keys of the firmware configuration both scenarios set. asym_derived: how
// asym_max_ps2 is derived unless given (3-D: scenario3d.hpp); empty: a fixed default (2-D).
template <class F>
void firmware_keys(sch::Table<F>& t, const std::string& asym_derived = "") {
  t.num("f_max_mps2", &F::f_max_mps2, "m/s^2", sch::in_lopen(0, 1e6), "largest accepted specific force reading")
      .num("asym_max_ps2", &F::asym_max_ps2, "1/s^2", sch::in_lopen(0, 1), "largest accepted gradient asymmetry");
  if (!asym_derived.empty()) t.derived_unless_given(&F::asym_max_set, asym_derived);
  t.integer("dt_tol_us", &F::dt_tol_us, "us", sch::in(0, 1e9), "accepted deviation of a frame's time step");
  sch::Key<F> frozen = sch::mk<F>("acc_frozen_frames", "integer", "frames",
                                  "0 (off) or 2.." + std::to_string(GG_LIM_FROZEN_FRAMES_MAX),
                                  "used frames in a row in which an accelerometer reading keeps one value "
                                  "before it is set aside as stuck (navtask.h)",
                                  "");
  frozen.read = [](F& f, const toml::node& n, const sch::Ctx& c, const std::string& p) {
    const int64_t v = sch::read_int(n, c, p, sch::in(0, GG_LIM_FROZEN_FRAMES_MAX), "frames");
    if (v == 1)
      c.fail_at(&n, p, p + " = 1: must be 0 (off) or 2.." + std::to_string(GG_LIM_FROZEN_FRAMES_MAX) +
                           " (a run of one frame is every reading)");
    f.acc_frozen_frames = v;
  };
  frozen.write = [](const F& f) -> std::optional<std::string> { return std::to_string(f.acc_frozen_frames); };
  t.custom(frozen).derived_unless_given(
      &F::acc_frozen_frames_set, "10 when [accel] noise_sigma_mps2 >= 10 ulp(f_max_mps2), else 0 (fdi_thresholds.hpp)");
}

// [time] of a scenario struct R with members duration_s and rate_hz.
template <class R>
sch::Table<R> time_table() {
  sch::Table<R> t("time", "Flight duration and frame rate.");
  t.num("duration_s", &R::duration_s, "s", sch::in_lopen(0, 1e7), "flight duration (frames at t = 0 .. duration_s)")
      .num("rate_hz", &R::rate_hz, "Hz", sch::in_lopen(0, 1e6),
           "frame rate (1e6 / rate_hz must be a whole number of microseconds)");
  return t;
}

// An accelerometer's per-axis array: rows [x, y, z], n_min..n_max rows (one per accelerometer).
template <class T>
sch::Key<T> per_axis_key(const std::string& name, std::array<std::array<double, 3>, kMaxAcc> T::*m,
                         const std::string& unit, size_t n_min, size_t n_max, const std::string& meaning) {
  const std::string rows = n_min == n_max ? std::to_string(n_min) : "up to " + std::to_string(n_max);
  sch::Key<T> k = sch::mk<T>(name, "array of " + rows + " [x, y, z]", unit, "finite", meaning, "");
  k.read = [m, n_min, n_max, unit](T& t, const toml::node& n, const sch::Ctx& c, const std::string& p) {
    const toml::array* a = n.as_array();
    if (!a || a->size() < n_min || a->size() > n_max)
      c.fail_at(&n, p,
                p + " = " + sch::value_text(n) + ": must be an array of " +
                    (n_min == n_max ? std::to_string(n_min) : "up to " + std::to_string(n_max)) +
                    " [x, y, z] arrays (one per accelerometer)");
    for (size_t i = 0; i < a->size(); ++i) {
      const auto v = sch::read_nums((*a)[i], c, p + "[" + std::to_string(i) + "]", 3, 3, sch::any(), unit);
      for (size_t j = 0; j < 3; ++j) (t.*m)[i][j] = v[j];
    }
  };
  k.write = [m, n_min](const T& t) -> std::optional<std::string> {
    // the rows up to the last non-zero one (at least n_min)
    size_t n = n_min;
    for (size_t i = 0; i < (t.*m).size(); ++i)
      if ((t.*m)[i] != std::array<double, 3>{0, 0, 0}) n = std::max(n, i + 1);
    std::string s = "[";
    for (size_t i = 0; i < n; ++i) {
      s += i ? ", [" : "[";
      for (size_t j = 0; j < 3; ++j) s += (j ? ", " : "") + sch::num_text((t.*m)[i][j]);
      s += "]";
    }
    return s + "]";
  };
  return k;
}

// [accel]: the accelerometers' errors, keys both scenarios have.
inline sch::Table<AccelErrorParams> accel_table(size_t bias_rows_min, size_t bias_rows_max) {
  sch::Table<AccelErrorParams> t("accel", "The accelerometers' errors (every accelerometer axis alike).");
  using A = AccelErrorParams;
  t.seed("seed", &A::seed, "seed of the random errors")
      .num("bias_sigma_mps2", &A::bias_sigma_mps2, "m/s^2", sch::in(0, 1), "constant random bias per axis, 1 sigma")
      .num("noise_sigma_mps2", &A::noise_sigma_mps2, "m/s^2", sch::in(0, 1), "white noise per sample, 1 sigma")
      .num("scale_sigma", &A::scale_sigma, "1", sch::in(0, 0.1), "constant random scale-factor error, 1 sigma")
      .custom(per_axis_key<A>("bias_mps2", &A::bias_mps2, "m/s^2", bias_rows_min, bias_rows_max,
                              "fixed bias added per accelerometer axis"));
  return t;
}

// [sensor_faults]: injected sensor faults, one table in 2-D and 3-D; what differs is the
// task's instrument: the fault kinds its injector has, the sensors and axes a fault names.
// The rows document the keys its reader (2-D: sensor_faults.cpp, 3-D: faults3d.cpp) checks
// with the same instrument description.
struct FaultInstrument {
  std::vector<std::string> kinds;  // fault kinds, in documented order
  std::string sensor_type;         // "integer", "integer or \"gyro\""
  std::string sensor_range;        // "[1, 4]"
  std::string sensor_meaning;
  std::vector<std::string> axes;   // {"x", "z"}: a fault's axis is its index here
  std::string axis_required;       // when the axis is required
  std::string size_unit;           // the unit of a reading's fault size
  int sensor_min = 0, sensor_max = 0;  // the accelerometers a fault names
  bool gyro = false;                   // a fault may name sensor = "gyro", read as gyro_id
  int gyro_id = 0;
};

inline std::vector<sch::Row> sensor_fault_rows(const FaultInstrument& f) {
  std::string kinds, axes;
  for (const auto& k : f.kinds) kinds += (kinds.empty() ? "" : ", ") + sch::str_text(k);
  for (const auto& a : f.axes) axes += (axes.empty() ? "" : ", ") + sch::str_text(a);
  return {{"seed", "integer", "", "1", ">= 0", "seed of the faults' random occurrence (prob < 1)"},
          {"fault", "array of tables", "", "none", "[[sensor_faults.fault]]", "one entry per injected fault:"},
          {"fault.kind", "string", "", "(required)", kinds,
           "what happens to the reading (time_*: to the frame's time stamp)"},
          {"fault.sensor", f.sensor_type, "", "(required, not time_*)", f.sensor_range, f.sensor_meaning},
          {"fault.axis", "string", "", f.axis_required, axes, "its axis"},
          {"fault.start_s", "number", "s", "0.0", ">= 0", "onset"},
          {"fault.duration_s", "number", "s", "0.0", ">= 0", "length (0: to the end)"},
          {"fault.size", "number", f.size_unit + " (time_*: us)", "0.0", "finite; time_jump/back: whole us in [1, 1e12]",
           "the fault's size: reading, step, drift rate, noise sigma, or time jump"},
          {"fault.prob", "number", "1", "1.0", "(0, 1]", "probability per frame while active"}};
}

// The one reader of [sensor_faults] (the rows above), for the instrument f: P has `seed`
// and `faults`, a vector of entries with kind, sensor, axis, start_s, duration_s, size and
// prob (their defaults those of a default entry). Errors name file:line, the key, the
// value and what is allowed, through c.
template <class P>
P read_sensor_faults(const toml::table& t, const sch::Ctx& c, const FaultInstrument& f) {
  using F = typename decltype(P::faults)::value_type;
  auto list = [](const std::vector<std::string>& v, bool quote) {
    std::string l;
    for (const auto& x : v) l += (l.empty() ? "" : ", ") + (quote ? sch::str_text(x) : x);
    return l;
  };
  auto is_time = [](const std::string& k) { return k.rfind("time_", 0) == 0; };
  const std::string sensors = f.sensor_range, axes = list(f.axes, true);
  P p;
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    if (key != "seed" && key != "fault")
      c.fail_at(&v, "sensor_faults." + key, "unknown key 'sensor_faults." + key + "' (allowed: fault, seed)");
  }
  if (const toml::node* n = t.get("seed"))
    p.seed = static_cast<uint64_t>(sch::read_int(*n, c, "sensor_faults.seed", sch::ge(0), ""));
  const toml::node* arr = t.get("fault");
  if (!arr) return p;
  const toml::array* a = arr->as_array();
  if (!a)
    c.fail_at(arr, "sensor_faults.fault",
              "sensor_faults.fault = " + sch::value_text(*arr) + ": must be an array of tables ([[sensor_faults.fault]])");
  static const char* kKeys[] = {"axis", "duration_s", "kind", "prob", "sensor", "size", "start_s"};
  for (size_t i = 0; i < a->size(); ++i) {
    const std::string where = "sensor_faults.fault[" + std::to_string(i) + "]";
    const toml::node& en = (*a)[i];
    const toml::table* ft = en.as_table();
    if (!ft) c.fail_at(&en, where, where + " = " + sch::value_text(en) + ": must be a table");
    for (const auto& [k, v] : *ft) {
      const std::string key(k.str());
      bool known = false;
      for (const char* x : kKeys) known = known || key == x;
      if (!known)
        c.fail_at(&v, where + "." + key,
                  "unknown key '" + where + "." + key + "' (allowed: axis, duration_s, kind, prob, sensor, size, start_s)");
    }
    F e;
    const toml::node* kn = ft->get("kind");
    if (!kn) c.fail_at(&en, where, where + ".kind is required (allowed: " + list(f.kinds, true) + ")");
    e.kind = sch::read_str(*kn, c, where + ".kind", f.kinds);
    if (const toml::node* n = ft->get("sensor")) {
      if (f.gyro && n->is_string() && n->as_string()->get() == "gyro") {
        e.sensor = f.gyro_id;
      } else if (n->is_integer() && n->as_integer()->get() >= f.sensor_min && n->as_integer()->get() <= f.sensor_max) {
        e.sensor = static_cast<int>(n->as_integer()->get());
      } else {
        c.fail_at(n, where + ".sensor",
                  where + ".sensor = " + sch::value_text(*n) + ": must be an " + f.sensor_meaning + " (allowed: " + sensors + ")");
      }
    } else if (!is_time(e.kind)) {
      c.fail_at(&en, where, where + ".sensor is required for kind '" + e.kind + "' (allowed: " + sensors + ")");
    }
    if (const toml::node* n = ft->get("axis")) {
      const std::string ax = sch::read_str(*n, c, where + ".axis", f.axes);
      for (size_t j = 0; j < f.axes.size(); ++j)
        if (f.axes[j] == ax) e.axis = static_cast<int>(j);
    } else if (!is_time(e.kind) && e.kind != "status_bad") {
      c.fail_at(&en, where, where + ".axis is required for kind '" + e.kind + "' (allowed: " + axes + ")");
    }
    auto num = [&](const char* key, double dflt, sch::Range r, const std::string& unit) {
      const toml::node* n = ft->get(key);
      return n ? sch::read_num(*n, c, where + "." + key, r, unit) : dflt;
    };
    e.start_s = num("start_s", e.start_s, sch::ge(0), "s");
    e.duration_s = num("duration_s", e.duration_s, sch::ge(0), "s");
    e.size = num("size", e.size, sch::any(), "");
    e.prob = num("prob", e.prob, sch::in_lopen(0, 1), "");
    const toml::node* sn = ft->get("size");
    if ((e.kind == "time_jump" || e.kind == "time_back") &&
        !(e.size >= 1.0 && e.size <= 1e12 && e.size == std::floor(e.size)))
      c.fail_at(sn ? sn : &en, where + ".size",
                where + ".size = " + (sn ? sch::value_text(*sn) : std::string("0.0")) +
                    ": must be a whole number of microseconds for " + e.kind + " (allowed: [1, 1e12] us)");
    if ((e.kind == "range" || e.kind == "saturate") && e.size == 0.0)
      c.fail_at(sn ? sn : &en, where + ".size",
                where + ".size: the reading (" + f.size_unit + ") is required for " + e.kind + " (allowed: != 0)");
    if (e.kind == "noise" && !(e.size > 0))
      c.fail_at(sn ? sn : &en, where + ".size",
                where + ".size: the noise's standard deviation must be > 0 (allowed: > 0)");
    p.faults.push_back(e);
  }
  return p;
}

}  // namespace ggins::truth::keys
