// Sensor fault injection in 3-D scenarios (see ggins/truth3d/faults3d.hpp).
#include "ggins/truth3d/faults3d.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "ggins/truth/generator.hpp"
#include "ggins/truth/sensor_faults.hpp"
#include "ggins/truth3d/generator3d.hpp"

namespace ggins::truth3d {

namespace {

constexpr uint64_t kStreamFaultProb = 51, kStreamFaultNoise = 52;  // distinct from the generator's streams


bool is_time_kind(const std::string& k) { return k.rfind("time_", 0) == 0; }

std::string at_line(const toml::node& n) { return " (line " + std::to_string(n.source().begin.line) + ")"; }

// reading (hi, lo) += d, exactly to long double, re-split into double + residual
void add_to_reading(double& hi, double& lo, long double d) {
  const long double x = static_cast<long double>(hi) + static_cast<long double>(lo) + d;
  hi = static_cast<double>(x);
  lo = static_cast<double>(x - static_cast<long double>(hi));
}

// set when making the fault-free reference frame of a stuck reading
thread_local bool t_reference = false;

}  // namespace

const truth::keys::FaultInstrument& fault_instrument3d() {
  static const truth::keys::FaultInstrument f{{"nan", "inf", "range", "saturate", "stuck", "step", "drift", "noise",
                                               "status_bad", "time_jump", "time_repeat", "time_back"},
                                              "integer or \"gyro\"",
                                              "[0, 5], \"gyro\"",
                                              "accelerometer or the gyro",
                                              {"x", "y", "z"},
                                              "(required, not time_*, status_bad)",
                                              "m/s^2, rad/s"};
  return f;
}

SensorFaults3 parse_sensor_faults3(const toml::table& t, const std::string& source) {
  static const std::set<std::string> kKinds(fault_instrument3d().kinds.begin(), fault_instrument3d().kinds.end());
  auto fail = [&](const std::string& what) -> void { throw std::runtime_error("scenario " + source + ": " + what); };
  SensorFaults3 p;
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    if (key != "seed" && key != "fault")
      fail("unknown key 'sensor_faults." + key + "'" + at_line(v) + " (allowed: fault, seed)");
  }
  if (const toml::node* n = t.get("seed")) {
    if (!n->is_integer() || n->as_integer()->get() < 0)
      fail("sensor_faults.seed" + at_line(*n) + " must be an integer >= 0");
    p.seed = static_cast<uint64_t>(n->as_integer()->get());
  }
  const toml::node* arr = t.get("fault");
  if (!arr) return p;
  const toml::array* a = arr->as_array();
  if (!a) fail("sensor_faults.fault" + at_line(*arr) + " must be an array of tables ([[sensor_faults.fault]])");
  for (size_t i = 0; i < a->size(); ++i) {
    const std::string where = "sensor_faults.fault[" + std::to_string(i) + "]";
    const std::string loc = where + at_line((*a)[i]);
    const toml::table* ft = (*a)[i].as_table();
    if (!ft) fail(loc + " must be a table");
    static const std::set<std::string> allowed = {"kind", "sensor", "axis", "start_s", "duration_s", "size", "prob"};
    for (const auto& [k, v] : *ft) {
      const std::string key(k.str());
      if (!allowed.count(key))
        fail("unknown key '" + where + "." + key + "'" + at_line(v) +
             " (allowed: axis, duration_s, kind, prob, sensor, size, start_s)");
    }
    SensorFault3 f;
    auto num = [&](const char* key, double dflt) {
      const toml::node* n = ft->get(key);
      if (!n) return dflt;
      auto d = n->value<double>();
      if (!d || !std::isfinite(*d)) fail(where + "." + key + at_line(*n) + " must be a finite number");
      return *d;
    };
    const toml::node* kn = ft->get("kind");
    if (!kn || !kn->is_string()) fail(loc + ": kind (a string) is required");
    f.kind = kn->as_string()->get();
    if (!kKinds.count(f.kind)) {
      std::string list;
      for (const auto& x : kKinds) list += (list.empty() ? "" : ", ") + x;
      fail(where + ".kind '" + f.kind + "'" + at_line(*kn) + " unknown (known: " + list + ")");
    }
    if (const toml::node* n = ft->get("sensor")) {
      if (n->is_string() && n->as_string()->get() == "gyro") {
        f.sensor = kFaultGyro;
      } else if (n->is_integer() && n->as_integer()->get() >= 0 && n->as_integer()->get() <= 5) {
        f.sensor = static_cast<int>(n->as_integer()->get());
      } else {
        fail(where + ".sensor" + at_line(*n) + " must be an accelerometer 0..5 or \"gyro\"");
      }
    } else if (!is_time_kind(f.kind)) {
      fail(loc + ": sensor (0..5 or \"gyro\") is required for kind '" + f.kind + "'");
    }
    if (const toml::node* n = ft->get("axis")) {
      const auto s = n->value<std::string>();
      if (!s || (*s != "x" && *s != "y" && *s != "z")) fail(where + ".axis" + at_line(*n) + " must be \"x\", \"y\" or \"z\"");
      f.axis = *s == "x" ? 0 : (*s == "y" ? 1 : 2);
    } else if (!is_time_kind(f.kind) && f.kind != "status_bad") {
      fail(loc + ": axis (\"x\", \"y\" or \"z\") is required for kind '" + f.kind + "'");
    }
    f.start_s = num("start_s", 0.0);
    f.duration_s = num("duration_s", 0.0);
    f.size = num("size", 0.0);
    f.prob = num("prob", 1.0);
    if (f.start_s < 0 || f.duration_s < 0) fail(loc + ": start_s and duration_s must be >= 0");
    if (!(f.prob > 0.0 && f.prob <= 1.0)) fail(loc + ": prob must be in (0, 1]");
    if ((f.kind == "time_jump" || f.kind == "time_back") &&
        !(f.size >= 1.0 && f.size <= 1e12 && f.size == std::floor(f.size)))
      fail(loc + ": size must be a whole number of microseconds in [1, 1e12] for " + f.kind);
    if ((f.kind == "range" || f.kind == "saturate") && f.size == 0.0)
      fail(loc + ": size (the reading) is required for " + f.kind);
    if (f.kind == "noise" && !(f.size > 0)) fail(loc + ": size (the noise's standard deviation) must be > 0");
    p.faults.push_back(f);
  }
  return p;
}

int64_t sensor_fault3_first_step(const SensorFault3& f, int64_t dt_us) {
  return truth::fault_window_first_step(f.start_s, dt_us);
}

bool sensor_fault3_active(const SensorFaults3& p, size_t idx, int64_t k, int64_t dt_us) {
  const SensorFault3& f = p.faults[idx];
  return truth::fault_window_active(f.start_s, f.duration_s, f.prob, p.seed, kStreamFaultProb, idx, k, dt_us);
}

void apply_sensor_faults3(const SensorFaults3& p, const Generator3& g, int64_t k, gg_frame_t& fr) {
  if (p.faults.empty() || t_reference) return;
  const int64_t dt_us = g.dt_us();
  for (size_t i = 0; i < p.faults.size(); ++i) {
    if (!sensor_fault3_active(p, i, k, dt_us)) continue;
    const SensorFault3& f = p.faults[i];
    if (f.kind == "time_jump") {
      fr.utime += static_cast<int64_t>(f.size);
      continue;
    }
    if (f.kind == "time_back") {
      fr.utime -= static_cast<int64_t>(f.size);
      continue;
    }
    if (f.kind == "time_repeat") {
      fr.utime -= dt_us;
      continue;
    }
    const bool gyro = f.sensor == kFaultGyro;
    const auto s = static_cast<size_t>(gyro ? 0 : f.sensor), j = static_cast<size_t>(f.axis);
    if (f.kind == "status_bad") {
      if (gyro)
        fr.gyro_status = GG_SENSOR_BAD;
      else
        fr.acc_status[s] = GG_SENSOR_BAD;
      continue;
    }
    double dummy_lo = 0;
    double& hi = gyro ? fr.omega_b[j] : fr.f[s][j];
    double& lo = gyro ? dummy_lo : fr.f_lo[s][j];
    if (f.kind == "nan") {
      hi = std::numeric_limits<double>::quiet_NaN();
      lo = 0;
    } else if (f.kind == "inf") {
      hi = f.size < 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
      lo = 0;
    } else if (f.kind == "range" || f.kind == "saturate") {
      hi = f.size;
      lo = 0;
    } else if (f.kind == "step") {
      add_to_reading(hi, lo, static_cast<long double>(f.size));
    } else if (f.kind == "drift") {
      const long double el = static_cast<long double>(k * dt_us - std::llround(f.start_s * 1e6)) * 1e-6L;  // s
      add_to_reading(hi, lo, static_cast<long double>(f.size) * el);
    } else if (f.kind == "noise") {
      add_to_reading(hi, lo,
                     static_cast<long double>(f.size * truth::counter_normal(p.seed, kStreamFaultNoise,
                                                                             static_cast<uint64_t>(k), i, j)));
    } else if (f.kind == "stuck") {
      gg_frame_t ref;
      t_reference = true;
      try {
        g.frame(sensor_fault3_first_step(f, dt_us), ref);
      } catch (...) {
        t_reference = false;
        throw;
      }
      t_reference = false;
      hi = gyro ? ref.omega_b[j] : ref.f[s][j];
      lo = gyro ? 0.0 : ref.f_lo[s][j];
    }
    if (gyro) fr.omega_b[j] = hi;
  }
}

}  // namespace ggins::truth3d
