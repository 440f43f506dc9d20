// Sensor fault injection (see ggins/truth/sensor_faults.hpp).
#include "ggins/truth/sensor_faults.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "ggins/truth/generator.hpp"
#include "sensor_faults_parse.hpp"

namespace ggins::truth {

namespace {

constexpr uint64_t kStreamFault = 40;  // counter_uniform stream of the per-step probabilities

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
      "m/s^2",
      1,
      4};
  return f;
}

SensorFaultParams parse_sensor_faults(const toml::table& t, const sch::Ctx& c) {
  return keys::read_sensor_faults<SensorFaultParams>(t, c, fault_instrument2d());
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
