// Sensor fault injection in 3-D scenarios: faults laid over the error-model
// readings of each gg_frame_t the 3-D truth generator makes (generator3d.hpp),
// set per scenario and seeded (a pure function of seed, step and fault index,
// like the rest of the generator: a frame is the same however often it is
// made). The kinds and keys are the 2-D generator's (truth/sensor_faults.hpp)
// with the 3-D sensor numbering, a third axis, the gyros and a noise burst.
//
// Scenario (TOML):
//   [sensor_faults]
//   seed = 1                       # seed of the per-step probabilities and of "noise"
//   [[sensor_faults.fault]]
//   kind = "step"                  # see below
//   sensor = 2                     # accelerometer 0..5 (diff3d.h layout: 0 (+a,0,0), 1 (0,+b,0),
//                                  #   2 (0,0,+c), 3 (-a,0,0), 4 (0,-b,0), 5 (0,0,-c)) or "gyro"
//   axis = "x"                     # "x", "y" or "z" (body axes of the reading)
//   start_s = 10.0                 # first faulty step: the first at t >= start_s
//   duration_s = 0.0               # 0: to the end of the run; else the fault lasts this long
//   size = 1e-9                    # meaning depends on the kind (below); m/s^2 or rad/s
//   prob = 1.0                     # per-step probability while active (seeded); 1: every step
//
// Kinds (on one axis of one accelerometer, or of the gyro):
//   "nan", "inf"  the reading is NaN / +Inf ("inf" takes the sign of size if < 0)
//   "range"       the reading is `size` (beyond the firmware's f_max: out of range)
//   "saturate"    the reading is pinned at `size` (a rail inside the range: only parity sees it)
//   "stuck"       the reading keeps its (fault-free) value of the first faulty step
//   "step"        a bias of `size` is added
//   "drift"       a bias growing by `size` per second from start_s is added
//   "noise"       a noise burst: white Gaussian noise of standard deviation `size` is added
//   "status_bad"  the sensor flags its sample bad (acc_status[sensor] or gyro_status = GG_SENSOR_BAD;
//                 axis unused)
// Time-stamp faults (sensor and axis unused):
//   "time_jump"   utime += size microseconds
//   "time_repeat" utime of the step = utime of the step before
//   "time_back"   utime -= size microseconds
// Faults apply in the order listed; the truth (Truth3) is never touched.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "ggins/truth/scenario_keys.hpp"

extern "C" {
#include "ggins/frame.h"
}

namespace ggins::truth3d {

constexpr int kFaultGyro = -1;  // SensorFault3::sensor of a gyro fault

struct SensorFault3 {
  std::string kind;
  int sensor = 0;  // 0..5, or kFaultGyro
  int axis = 0;    // 0 = x, 1 = y, 2 = z
  double start_s = 0.0;
  double duration_s = 0.0;  // 0: to the end
  double size = 0.0;
  double prob = 1.0;
};

struct SensorFaults3 {
  uint64_t seed = 1;
  std::vector<SensorFault3> faults;
  bool empty() const { return faults.empty(); }
};

// The 3-D instrument of [sensor_faults] (the rows of the scenario reference and the
// reader's checks): accelerometers 0..5 or the gyro, axes x, y, z.
const truth::keys::FaultInstrument& fault_instrument3d();

// The [sensor_faults] table (truth::keys::read_sensor_faults for this instrument); throws
// std::runtime_error("scenario <source>:<line>: ...") naming the offending key.
SensorFaults3 parse_sensor_faults3(const toml::table& t, const truth::sch::Ctx& c);

// Whether fault idx acts on step k (dt_us per step), seeded.
bool sensor_fault3_active(const SensorFaults3& p, size_t idx, int64_t k, int64_t dt_us);
// First step of a fault: the first k with k dt >= start_s.
int64_t sensor_fault3_first_step(const SensorFault3& f, int64_t dt_us);

class Generator3;
// Apply every active fault to frame k of generator g (called at the end of
// Generator3::frame). "stuck" reads the fault-free frame of its first step
// from g (remade on every stuck step: a frame is a pure function of k).
void apply_sensor_faults3(const SensorFaults3& p, const Generator3& g, int64_t k, gg_frame_t& out);

}  // namespace ggins::truth3d
