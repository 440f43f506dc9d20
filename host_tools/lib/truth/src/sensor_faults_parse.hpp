// Parser of the [sensor_faults] scenario table (internal to ggins_truth).
#pragma once

#include <string>
#include <toml++/toml.h>

#include "ggins/truth/scenario_keys.hpp"
#include "ggins/truth/sensor_faults.hpp"

namespace ggins::truth {
// The 2-D instrument of [sensor_faults]: accelerometers 1..4, axes x and z.
const keys::FaultInstrument& fault_instrument2d();
// keys::read_sensor_faults for this instrument: errors name file:line and the key.
SensorFaultParams parse_sensor_faults(const toml::table& t, const sch::Ctx& c);
}  // namespace ggins::truth
