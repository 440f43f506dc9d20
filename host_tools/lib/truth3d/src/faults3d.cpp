// Sensor fault injection in 3-D scenarios (see ggins/truth3d/faults3d.hpp).
#include "ggins/truth3d/faults3d.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "ggins/truth/generator.hpp"
#include "ggins/truth/sensor_faults.hpp"
#include "ggins/truth3d/generator3d.hpp"

namespace ggins::truth3d {

namespace {

constexpr uint64_t kStreamFaultProb = 51, kStreamFaultNoise = 52;  // distinct from the generator's streams


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
                                              "m/s^2, rad/s",
                                              0,
                                              5,
                                              true,
                                              kFaultGyro};
  return f;
}

SensorFaults3 parse_sensor_faults3(const toml::table& t, const truth::sch::Ctx& c) {
  return truth::keys::read_sensor_faults<SensorFaults3>(t, c, fault_instrument3d());
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
