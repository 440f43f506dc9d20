// The integrity verdict of one aid over a flight, from the task's outputs: the
// monitor's state at each step (firmware aid_integ.h: OK / SUSPECT / ISOLATED) and the
// measurements the aid refused for want of a map. What summary.json states per aid
// ("integrity") and why a flight whose aid was inconsistent or refused for part of it
// ends degraded (degraded_reasons, exit 4).
//
//   integrity = {
//     enabled      the monitor ran (scenario key integrity)
//     state_final  OK | SUSPECT | ISOLATED at the last step
//     flagged      the monitor left OK at some step, or measurements were refused
//     suspect_s, isolated_s   time spent in each state, s
//     ratio_max    largest test ratio (window sum / chi-square band; > 1 outside)
//     refused      measurements without a covering map tile (not updated)
//     events       [{t_s, state, ratio, why}] at every change of state (the first 64)
//   }
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ggins/aid_integ.h"

namespace ggins::hil {

class IntegrityTrack {
 public:
  static const char* state_name(int32_t s) {
    return s == GG_INTEG_SUSPECT ? "SUSPECT" : (s == GG_INTEG_ISOLATED ? "ISOLATED" : "OK");
  }
  // One output step: time since t = 0 (s), the step (s), the monitor's state and test
  // ratio, its counters so far (tests, windows outside) and the refusals so far.
  void take(double t_s, double dt_s, int32_t state, double ratio, int64_t refused) {
    if (state == GG_INTEG_SUSPECT) suspect_s_ += dt_s;
    if (state == GG_INTEG_ISOLATED) isolated_s_ += dt_s;
    if (std::isfinite(ratio)) ratio_max_ = std::max(ratio_max_, ratio);
    if (state != state_) {
      std::string why;
      if (state > state_)
        why = state == GG_INTEG_SUSPECT ? "test ratio above 1: innovations outside their chi-square band, de-weighted"
                                        : "still outside the band while SUSPECT: corrections stopped (dead reckoning)";
      else
        why = "consistency returned: back one rung";
      add_event(t_s, state, ratio, why);
      if (state != GG_INTEG_OK) left_ok_ = true;
      state_ = state;
    }
    if (refused > refused_) {
      if (refused_ == 0) first_refused_s_ = t_s;
      refused_ = refused;
    }
  }
  void set_enabled(bool on) { enabled_ = on; }
  bool flagged() const { return left_ok_ || refused_ > 0; }
  int64_t refused() const { return refused_; }
  // The degraded reasons of this aid ("map aid", "particle filter"), of `total` measurements.
  void reasons(const std::string& aid, const std::string& unit, int64_t total, std::vector<std::string>& out) const {
    char b[320];
    if (left_ok_) {
      std::snprintf(b, sizeof b,
                    "%s inconsistent: integrity monitor SUSPECT for %.1f s, ISOLATED for %.1f s (first at t = %.1f s; "
                    "largest test ratio %.3g), ending %s",
                    aid.c_str(), suspect_s_, isolated_s_, first_left_s_, ratio_max_, state_name(state_));
      out.push_back(b);
    }
    if (refused_ > 0) {
      std::snprintf(b, sizeof b, "%s refused %lld of %lld %s: no map tile covers the position at its height (first at t = %.1f s)",
                    aid.c_str(), static_cast<long long>(refused_), static_cast<long long>(total), unit.c_str(),
                    first_refused_s_);
      out.push_back(b);
    }
  }
  nlohmann::json json() const {
    return {{"enabled", enabled_},      {"state_final", state_name(state_)}, {"flagged", flagged()},
            {"suspect_s", suspect_s_}, {"isolated_s", isolated_s_},       {"ratio_max", ratio_max_},
            {"refused", refused_},      {"events", events_}};
  }

 private:
  void add_event(double t_s, int32_t state, double ratio, const std::string& why) {
    if (!left_ok_ && state != GG_INTEG_OK) first_left_s_ = t_s;
    if (events_.size() < kMaxEvents)
      events_.push_back({{"t_s", t_s}, {"state", state_name(state)}, {"ratio", ratio}, {"why", why}});
  }
  static constexpr size_t kMaxEvents = 64;
  bool enabled_ = false, left_ok_ = false;
  int32_t state_ = GG_INTEG_OK;
  double suspect_s_ = 0, isolated_s_ = 0, ratio_max_ = 0, first_left_s_ = 0, first_refused_s_ = 0;
  int64_t refused_ = 0;
  nlohmann::json events_ = nlohmann::json::array();
};

}  // namespace ggins::hil
