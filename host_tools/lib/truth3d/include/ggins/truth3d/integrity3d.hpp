// The integrity monitor of an aiding source (firmware aid_integ.h) as a scenario states it:
// the same keys in every aid's table ([aid_ukf], [aid_pf]), mapped onto gg_integ_config_t.
//
//   integrity = true              # the aid watches its own consistency (windowed normalised
//                                 # innovations against their chi-square band): outside it the
//                                 # aid is flagged (AID_INTEGRITY), de-weighted, then isolated
//   integrity_window = 8          # measurements per window (map epochs, weighed shots)
//   integrity_z = 4.265           # the band's standard-normal quantile (1e-5 per window)
//   integrity_isolate_after = 3   # windows outside while SUSPECT before ISOLATED
//   integrity_recover_after = 8   # windows inside per rung of recovery
//   map_uncovered = "refuse"      # a route the map storage does not cover (area or height) is
//                                 # refused before take-off, naming the stretches; "fly": flown
//                                 # with no update over them (counted, the flight ends degraded)
#pragma once

#include <string>

#include "ggins/aid_integ.h"
#include "ggins/truth/scenario_schema.hpp"

namespace ggins::truth3d {

struct Integrity3 {
  Integrity3() {}  // user-provided: the aids' tables value-initialise this base through it (GCC 12's
                   // -Wmaybe-uninitialized misreads aggregate-initialising a std::string in a base)
  bool integrity = true;
  int integrity_window = GG_INTEG_WINDOW_DEFAULT;
  double integrity_z = GG_INTEG_Z_DEFAULT;
  int integrity_isolate_after = GG_INTEG_ISOLATE_AFTER_DEFAULT;
  int integrity_recover_after = GG_INTEG_RECOVER_AFTER_DEFAULT;
  std::string map_uncovered = "refuse";  // "refuse" | "fly" (ggins run3d: map_coverage.hpp)
};

inline gg_integ_config_t integrity_config(const Integrity3& a) {
  gg_integ_config_t c{};
  c.enable = a.integrity ? 1 : 0;
  c.window = a.integrity_window;
  c.z = a.integrity_z;
  c.isolate_after = a.integrity_isolate_after;
  c.recover_after = a.integrity_recover_after;
  return c;
}

// The keys of Integrity3 in an aid's table (A derives from Integrity3); `what` names the
// aid's measurement ("map epochs", "weighed shots").
template <class A>
void integrity_keys(truth::sch::Table<A>& t, const std::string& what) {
  namespace sch = truth::sch;
  t.boolean("integrity", static_cast<bool A::*>(&Integrity3::integrity),
            "integrity monitor (aid_integ.h): the aid tests its normalised innovations over a window against "
            "their chi-square band; outside it the aid is flagged (AID_INTEGRITY), de-weighted, then isolated "
            "(no correction fed, gravity dead reckoning) until consistency returns; the flight then ends degraded")
      .integer("integrity_window", static_cast<int A::*>(&Integrity3::integrity_window), "",
               sch::in(1, GG_INTEG_WINDOW_MAX), what + " per window of the integrity test")
      .num("integrity_z", static_cast<double A::*>(&Integrity3::integrity_z), "1", sch::in(1, 10),
           "standard-normal quantile of the band (4.265: 1e-5 false alarms per window)")
      .integer("integrity_isolate_after", static_cast<int A::*>(&Integrity3::integrity_isolate_after), "",
               sch::in(1, 1000), "windows outside the band while SUSPECT before the aid is isolated")
      .integer("integrity_recover_after", static_cast<int A::*>(&Integrity3::integrity_recover_after), "",
               sch::in(1, 1000), "windows inside the band per rung of recovery (ISOLATED -> SUSPECT -> OK)")
      .str("map_uncovered", static_cast<std::string A::*>(&Integrity3::map_uncovered), {"refuse", "fly"},
           "a route the map storage does not cover (outside every tile of the aid's kind, or at a height no layer "
           "holds), checked every 10 s of the route before take-off: refuse names the stretches and does not fly; "
           "fly flies them with no update there (each refused measurement counted; the flight ends degraded)");
}

}  // namespace ggins::truth3d
