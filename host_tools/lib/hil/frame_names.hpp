// Names of the firmware's health bits and cycle-accounting modules for the
// host's reports: the one table the runners, replay and the plots take them
// from (the values are frame.h's; tests/unit/check_health_names.py checks that
// every GG_HEALTH_* bit of frame.h is named here, once, with its own name).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "ggins/frame.h"

namespace ggins::hil {

struct HealthBitName {
  uint32_t bit;
  const char* name;
};

// One row per GG_HEALTH_* bit of frame.h, name = the macro without GG_HEALTH_.
inline constexpr HealthBitName kHealthBits[] = {
    {GG_HEALTH_NOT_INIT, "NOT_INIT"},
    {GG_HEALTH_ACC_NONFINITE, "ACC_NONFINITE"},
    {GG_HEALTH_ACC_RANGE, "ACC_RANGE"},
    {GG_HEALTH_ACC_SENSOR, "ACC_SENSOR"},
    {GG_HEALTH_SEQ_GAP, "SEQ_GAP"},
    {GG_HEALTH_SEQ_REPEAT, "SEQ_REPEAT"},
    {GG_HEALTH_TIME_JUMP, "TIME_JUMP"},
    {GG_HEALTH_GAMMA_ASYM, "GAMMA_ASYM"},
    {GG_HEALTH_FRAME_REJECTED, "FRAME_REJECTED"},
    {GG_HEALTH_DEADLINE, "DEADLINE"},
    {GG_HEALTH_BARO_INVALID, "BARO_INVALID"},
    {GG_HEALTH_BARO_STALE, "BARO_STALE"},
    {GG_HEALTH_BARO_OUTLIER, "BARO_OUTLIER"},
    {GG_HEALTH_BARO_RECAPTURE, "BARO_RECAPTURE"},
    {GG_HEALTH_BARO_COAST, "BARO_COAST"},
    {GG_HEALTH_ACC_FAULT, "ACC_FAULT"},
    {GG_HEALTH_ACC_REBUILT, "ACC_REBUILT"},
    {GG_HEALTH_GRAD_COAST, "GRAD_COAST"},
    {GG_HEALTH_MODEL_OUTSIDE, "MODEL_OUTSIDE"},
    {GG_HEALTH_GYRO_INVALID, "GYRO_INVALID"},
    {GG_HEALTH_RESYNC, "RESYNC"},
    {GG_HEALTH_COAST, "COAST"},
    {GG_HEALTH_PF_SHOT_INVALID, "PF_SHOT_INVALID"},
    {GG_HEALTH_PF_FAIL, "PF_FAIL"},
    {GG_HEALTH_ACC_DEGRADED, "ACC_DEGRADED"},
    {GG_HEALTH_FORCE_COAST, "FORCE_COAST"},
    {GG_HEALTH_ACC_FROZEN, "ACC_FROZEN"},
    {GG_HEALTH_MM_BAD_MEAS, "MM_BAD_MEAS"},
    {GG_HEALTH_MM_NO_MAP, "MM_NO_MAP"},
    {GG_HEALTH_MM_GATED, "MM_GATED"},
    {GG_HEALTH_MM_FAIL, "MM_FAIL"},
    {GG_HEALTH_AID_INTEGRITY, "AID_INTEGRITY"},
};

// The name of one bit, or its hex value if frame.h's table here does not name it.
inline std::string health_bit_name(uint32_t bit) {
  for (const auto& b : kHealthBits)
    if (b.bit == bit) return b.name;
  char x[16];
  std::snprintf(x, sizeof x, "0x%08x", static_cast<unsigned>(bit));
  return x;
}

// The names of the bits set in a health word, lowest bit first (unnamed bits as hex).
inline nlohmann::json health_bit_names(uint32_t word) {
  nlohmann::json j = nlohmann::json::array();
  for (int b = 0; b < 32; ++b)
    if (word & (1u << b)) j.push_back(health_bit_name(1u << b));
  return j;
}

// A health word for a report: the raw value beside its decoded bits.
inline nlohmann::json health_word(uint32_t word) {
  char x[16];
  std::snprintf(x, sizeof x, "0x%08x", static_cast<unsigned>(word));
  return {{"raw", word}, {"hex", x}, {"bits", health_bit_names(word)}};
}

// The decoded bits of a health word as one CSV field ("ACC_FAULT|ACC_REBUILT", empty for 0).
inline std::string health_csv(uint32_t word) {
  std::string s;
  for (int b = 0; b < 32; ++b)
    if (word & (1u << b)) {
      if (!s.empty()) s += '|';
      s += health_bit_name(1u << b);
    }
  return s;
}

// The cycle-accounting modules (frame.h GG_MOD_*), by index up to GG_MOD_COUNT.
inline std::string module_name(int j) {
  static const char* const kNames[] = {"diff", "gravdr", "mech", "vchan", "total", "aid_mm", "aid_pf"};
  static_assert(GG_MOD_DIFF == 0 && GG_MOD_GRAVDR == 1 && GG_MOD_MECH == 2 && GG_MOD_VCHAN == 3 && GG_MOD_TOTAL == 4 &&
                    GG_MOD_AID_MM == 5 && GG_MOD_AID_PF == 6 && GG_MOD_COUNT == 7,
                "module names follow frame.h's GG_MOD_* order");
  if (j >= 0 && j < static_cast<int>(sizeof kNames / sizeof kNames[0])) return kNames[j];
  return "module" + std::to_string(j);
}

}  // namespace ggins::hil
