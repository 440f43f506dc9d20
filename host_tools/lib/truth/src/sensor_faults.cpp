// Sensor fault injection (see ggins/truth/sensor_faults.hpp).
#include "ggins/truth/sensor_faults.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "ggins/truth/generator.hpp"
#include "sensor_faults_parse.hpp"

namespace ggins::truth {

namespace {

constexpr uint64_t kStreamFault = 40;  // counter_uniform stream of the per-step probabilities

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error("scenario " + source + ": " + what);
}


bool is_time_kind(const std::string& k) { return k.rfind("time_", 0) == 0; }

// reading (hi, lo) += d, exactly to long double, re-split into double + residual
void add_to_reading(double& hi, double& lo, long double d) {
  const long double x = static_cast<long double>(hi) + static_cast<long double>(lo) + d;
  hi = static_cast<double>(x);
  lo = static_cast<double>(x - static_cast<long double>(hi));
}

}  // namespace

const keys::FaultInstrument& fault_instrument2d() {
  static const keys::FaultInstrument f{
      {"nan", "inf", "range", "saturate", "stuck", "step", "drift", "status_bad", "time_jump", "time_repeat", "time_back"},
      "integer",
      "[1, 4]",
      "accelerometer",
      {"x", "z"},
      "(required, not time_*, status_bad)",
      "m/s^2"};
  return f;
}

SensorFaultParams parse_sensor_faults(const toml::table& t, const std::string& source) {
  static const std::set<std::string> kKinds(fault_instrument2d().kinds.begin(), fault_instrument2d().kinds.end());
  SensorFaultParams p;
  for (const auto& [k, v] : t) {
    (void)v;
    const std::string key(k.str());
    if (key != "seed" && key != "fault")
      fail(source, "unknown key 'sensor_faults." + key + "' (allowed: fault, seed)");
  }
  if (const toml::node* n = t.get("seed")) {
    if (!n->is_integer() || n->as_integer()->get() < 0) fail(source, "sensor_faults.seed must be an integer >= 0");
    p.seed = static_cast<uint64_t>(n->as_integer()->get());
  }
  const toml::node* arr = t.get("fault");
  if (!arr) return p;
  const toml::array* a = arr->as_array();
  if (!a) fail(source, "sensor_faults.fault must be an array of tables ([[sensor_faults.fault]])");
  for (size_t i = 0; i < a->size(); ++i) {
    const std::string where = "sensor_faults.fault[" + std::to_string(i) + "]";
    const toml::table* ft = (*a)[i].as_table();
    if (!ft) fail(source, where + " must be a table");
    static const std::set<std::string> allowed = {"kind", "sensor", "axis", "start_s", "duration_s", "size", "prob"};
    for (const auto& [k, v] : *ft) {
      (void)v;
      const std::string key(k.str());
      if (!allowed.count(key))
        fail(source, "unknown key '" + where + "." + key + "' (allowed: axis, duration_s, kind, prob, sensor, size, start_s)");
    }
    SensorFault f;
    auto num = [&](const char* key, double dflt) {
      const toml::node* n = ft->get(key);
      if (!n) return dflt;
      auto d = n->value<double>();
      if (!d || !std::isfinite(*d)) fail(source, where + "." + key + " must be a finite number");
      return *d;
    };
    const toml::node* kn = ft->get("kind");
    if (!kn || !kn->is_string()) fail(source, where + ".kind (a string) is required");
    f.kind = kn->as_string()->get();
    if (!kKinds.count(f.kind)) {
      std::string list;
      for (const auto& x : kKinds) list += (list.empty() ? "" : ", ") + x;
      fail(source, where + ".kind '" + f.kind + "' unknown (known: " + list + ")");
    }
    if (const toml::node* n = ft->get("sensor")) {
      if (!n->is_integer() || n->as_integer()->get() < 1 || n->as_integer()->get() > 4)
        fail(source, where + ".sensor must be an integer 1..4");
      f.sensor = static_cast<int>(n->as_integer()->get());
    } else if (!is_time_kind(f.kind)) {
      fail(source, where + ".sensor (1..4) is required for kind '" + f.kind + "'");
    }
    if (const toml::node* n = ft->get("axis")) {
      const auto s = n->value<std::string>();
      if (!s || (*s != "x" && *s != "z")) fail(source, where + ".axis must be \"x\" or \"z\"");
      f.axis = *s == "x" ? 0 : 1;
    } else if (!is_time_kind(f.kind) && f.kind != "status_bad") {
      fail(source, where + ".axis (\"x\" or \"z\") is required for kind '" + f.kind + "'");
    }
    f.start_s = num("start_s", 0.0);
    f.duration_s = num("duration_s", 0.0);
    f.size = num("size", 0.0);
    f.prob = num("prob", 1.0);
    if (f.start_s < 0 || f.duration_s < 0) fail(source, where + ".start_s and duration_s must be >= 0");
    if (!(f.prob > 0.0 && f.prob <= 1.0)) fail(source, where + ".prob must be in (0, 1]");
    if ((f.kind == "time_jump" || f.kind == "time_back") &&
        !(f.size >= 1.0 && f.size <= 1e12 && f.size == std::floor(f.size)))
      fail(source, where + ".size must be a whole number of microseconds in [1, 1e12] for " + f.kind);
    if ((f.kind == "range" || f.kind == "saturate") && f.size == 0.0)
      fail(source, where + ".size (the reading, m/s^2) is required for " + f.kind);
    p.faults.push_back(f);
  }
  return p;
}

int64_t fault_window_first_step(double start_s, int64_t dt_us) {
  const auto start_us = static_cast<int64_t>(std::llround(start_s * 1e6));
  return (start_us + dt_us - 1) / dt_us;
}

bool fault_window_active(double start_s, double duration_s, double prob, uint64_t seed, uint64_t stream, size_t idx,
                         int64_t k, int64_t dt_us) {
  const auto start_us = static_cast<int64_t>(std::llround(start_s * 1e6));
  const auto dur_us = static_cast<int64_t>(std::llround(duration_s * 1e6));
  const int64_t t_us = k * dt_us;
  if (t_us < start_us) return false;
  if (dur_us > 0 && t_us >= start_us + dur_us) return false;
  if (prob >= 1.0) return true;
  return counter_uniform(seed, stream, static_cast<uint64_t>(k), idx, 0) < prob;
}

int64_t sensor_fault_first_step(const SensorFault& f, int64_t dt_us) { return fault_window_first_step(f.start_s, dt_us); }

bool sensor_fault_active(const SensorFaultParams& p, size_t idx, int64_t k, int64_t dt_us) {
  const SensorFault& f = p.faults[idx];
  return fault_window_active(f.start_s, f.duration_s, f.prob, p.seed, kStreamFault, idx, k, dt_us);
}

void apply_one_sensor_fault(const SensorFault& f, int64_t k, int64_t dt_us, gg_frame_t& fr) {
  const int s = f.sensor - 1, j = f.axis == 0 ? 0 : 2;
  if (f.kind == "nan") {
    fr.f[s][j] = std::numeric_limits<double>::quiet_NaN();
    fr.f_lo[s][j] = 0.0;
  } else if (f.kind == "inf") {
    fr.f[s][j] = f.size < 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    fr.f_lo[s][j] = 0.0;
  } else if (f.kind == "range" || f.kind == "saturate") {
    fr.f[s][j] = f.size;
    fr.f_lo[s][j] = 0.0;
  } else if (f.kind == "step") {
    add_to_reading(fr.f[s][j], fr.f_lo[s][j], static_cast<long double>(f.size));
  } else if (f.kind == "drift") {
    const long double el = static_cast<long double>(k * dt_us - std::llround(f.start_s * 1e6)) * 1e-6L;  // s
    add_to_reading(fr.f[s][j], fr.f_lo[s][j], static_cast<long double>(f.size) * el);
  } else if (f.kind == "status_bad") {
    fr.acc_status[s] = GG_SENSOR_BAD;
  } else if (f.kind == "time_jump") {
    fr.utime += static_cast<int64_t>(f.size);
  } else if (f.kind == "time_back") {
    fr.utime -= static_cast<int64_t>(f.size);
  } else if (f.kind == "time_repeat") {
    fr.utime -= dt_us;
  }
}

}  // namespace ggins::truth
