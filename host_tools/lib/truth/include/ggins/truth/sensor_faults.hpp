// Sensor fault injection in the truth generator: faults a real vehicle's
// sensors produce, laid over the error-model readings of each frame, set per
// scenario and seeded (a pure function of seed, step and fault index, like
// the rest of the generator, so a frame is the same however often it is
// generated: resends, replays).
//
// Scenario (TOML):
//   [sensor_faults]
//   seed = 1                       # seed of the per-step probabilities
//   [[sensor_faults.fault]]
//   kind = "step"                  # see below
//   sensor = 2                     # accelerometer 1..4 (the paper's numbering: 1 (+a,0), 2 (0,+b), 3 (-a,0), 4 (0,-b))
//   axis = "x"                     # "x" or "z"
//   start_s = 10.0                 # first faulty step: the first at t >= start_s
//   duration_s = 0.0               # 0: to the end of the run; else the fault lasts this long
//   size = 1e-9                    # meaning depends on the kind (below)
//   prob = 1.0                     # per-step probability while active (seeded); 1: every step
//
// Kinds (accelerometer faults act on one axis of one sensor):
//   "nan", "inf"  the reading is NaN / +Inf (size: unused; "inf" takes the sign of size if < 0)
//   "range"       the reading is `size` m/s^2 (beyond the firmware's f_max: out of range)
//   "saturate"    the reading is pinned at `size` m/s^2 (a rail inside f_max: only parity sees it)
//   "stuck"       the reading stays at its value of the first faulty step
//   "step"        a bias of `size` m/s^2 is added
//   "drift"       a bias growing by `size` m/s^2 per second from start_s is added
//   "status_bad"  the sensor flags its sample bad (acc_status = GG_SENSOR_BAD; axis unused)
// Time-stamp faults (sensor and axis unused):
//   "time_jump"   utime += size microseconds
//   "time_repeat" utime of the step = utime of the step before
//   "time_back"   utime -= size microseconds
// Barometer faults are not here: the barometer model belongs to the truth
// generator's barometer; outliers/dropouts go on top of it there.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ggins/frame.h"

namespace ggins::truth {

struct SensorFault {
  std::string kind;
  int sensor = 1;   // 1..4
  int axis = 0;     // 0 = x, 1 = z
  double start_s = 0.0;
  double duration_s = 0.0;  // 0: to the end
  double size = 0.0;
  double prob = 1.0;
};

struct SensorFaultParams {
  uint64_t seed = 1;
  std::vector<SensorFault> faults;
};

// (The [sensor_faults] table is parsed by scenario.cpp through src/sensor_faults_parse.hpp.)

// The time window of an injected fault, shared by the 2-D and 3-D fault models, in integer
// microseconds (no rounding at the window edges): the first step k with k dt >= start_s, and
// whether step k lies in [start_s, start_s + duration_s) (duration 0: to the end of the run)
// and is drawn with probability prob from counter_uniform(seed, stream, k, idx).
int64_t fault_window_first_step(double start_s, int64_t dt_us);
bool fault_window_active(double start_s, double duration_s, double prob, uint64_t seed, uint64_t stream, size_t idx,
                         int64_t k, int64_t dt_us);

// Whether fault `f` (index `idx`) acts on step k (time t_s), seeded.
bool sensor_fault_active(const SensorFaultParams& p, size_t idx, int64_t k, int64_t dt_us);

// Apply every active fault to frame k. `stuck_value(k0, sensor, axis, hi, lo)` gives the
// fault-free reading (hi, lo) of step k0, for "stuck". Faults apply in the order listed.
template <class StuckFn>
void apply_sensor_faults(const SensorFaultParams& p, int64_t k, int64_t dt_us, gg_frame_t& f, StuckFn stuck_value);

// Step index of the first faulty step of a fault (the first k with k dt >= start_s).
int64_t sensor_fault_first_step(const SensorFault& f, int64_t dt_us);

// Implementation detail of apply_sensor_faults for one fault (everything but "stuck").
void apply_one_sensor_fault(const SensorFault& f, int64_t k, int64_t dt_us, gg_frame_t& fr);

template <class StuckFn>
void apply_sensor_faults(const SensorFaultParams& p, int64_t k, int64_t dt_us, gg_frame_t& fr, StuckFn stuck_value) {
  for (size_t i = 0; i < p.faults.size(); ++i) {
    if (!sensor_fault_active(p, i, k, dt_us)) continue;
    const SensorFault& f = p.faults[i];
    if (f.kind == "stuck") {
      const int s = f.sensor - 1, j = f.axis == 0 ? 0 : 2;
      double hi = 0, lo = 0;
      stuck_value(sensor_fault_first_step(f, dt_us), s, j, hi, lo);
      fr.f[s][j] = hi;
      fr.f_lo[s][j] = lo;
    } else {
      apply_one_sensor_fault(f, k, dt_us, fr);
    }
  }
}

}  // namespace ggins::truth
