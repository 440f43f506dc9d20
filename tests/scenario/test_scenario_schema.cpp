// The scenario schema's checks against hand-written cases: each bad value is refused
// with file:line, the key, the value and the allowed range; values on the edges of the
// ranges are taken or refused as the ranges say; every documented default is accepted.
#include <cstdio>
#include <stdexcept>
#include <string>

#include "ggins/truth/fdi_thresholds.hpp"
#include "ggins/truth/scenario_schema.hpp"
#include "ggins/truth3d/scenario3d.hpp"

using namespace ggins;

static int g_fail = 0;

template <class Parse>
static void refused(Parse parse, const std::string& text, const std::string& want) {
  std::string msg;
  try {
    parse(text);
  } catch (const std::runtime_error& e) {
    msg = e.what();
  }
  const bool ok = !msg.empty() && msg.find(want) != std::string::npos;
  std::printf("%s refused %-45s -> %s\n", ok ? "ok  " : "FAIL", ("'" + want + "'").c_str(),
              msg.empty() ? "(accepted)" : msg.c_str());
  if (!ok) ++g_fail;
}

template <class Parse>
static void accepted(Parse parse, const std::string& text, const std::string& what) {
  try {
    parse(text);
    std::printf("ok   accepted %s\n", what.c_str());
  } catch (const std::runtime_error& e) {
    std::printf("FAIL accepted %s -> %s\n", what.c_str(), e.what());
    ++g_fail;
  }
}

// every row with a plain default: "[section]\nkey = default" parses
template <class R, class Parse>
static void defaults_accepted(const truth::sch::Schema<R>& sc, Parse parse, const std::string& extra) {
  int n = 0;
  for (const auto& s : sc.secs) {
    if (s.delegated) continue;
    for (const auto& row : s.rows) {
      if (row.derived_default || row.dflt.empty() || row.dflt[0] == '(' || row.meaning.find("(a key ") != std::string::npos)
        continue;
      const std::string text = extra + (s.name.empty() ? "" : "[" + s.name + "]\n") + row.key + " = " + row.dflt + "\n";
      try {
        parse(text);
        ++n;
      } catch (const std::runtime_error& e) {
        std::printf("FAIL default of %s.%s = %s refused: %s\n", s.name.c_str(), row.key.c_str(), row.dflt.c_str(),
                    e.what());
        ++g_fail;
      }
      if (row.type.empty() || row.range.empty() || row.meaning.empty()) {
        std::printf("FAIL %s.%s: type, range and meaning must be documented\n", s.name.c_str(), row.key.c_str());
        ++g_fail;
      }
    }
  }
  std::printf("ok   %s: %d documented defaults accepted\n", sc.title.c_str(), n);
}

// every fault kind the reference documents for [sensor_faults] is one the reader takes
// (with a sensor and axis the reference allows; status_bad without an axis, as documented)
template <class R, class Parse>
static void documented_fault_kinds_accepted(const truth::sch::Schema<R>& sc, Parse parse, const std::string& sensor) {
  const auto* sec = sc.find("sensor_faults");
  std::string kinds;
  for (const auto& row : sec ? sec->rows : std::vector<truth::sch::Row>{})
    if (row.key == "fault.kind") kinds = row.range;
  if (kinds.empty()) {
    std::printf("FAIL %s: no documented fault.kind\n", sc.title.c_str());
    ++g_fail;
    return;
  }
  int n = 0;
  for (size_t p = 0; (p = kinds.find('"', p)) != std::string::npos;) {
    const size_t q = kinds.find('"', p + 1);
    const std::string k = kinds.substr(p + 1, q - p - 1);
    p = q + 1;
    const bool time = k.rfind("time_", 0) == 0;
    const std::string text = "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"" + k + "\"\n" +
                             (time ? "" : "sensor = " + sensor + "\n") + (time || k == "status_bad" ? "" : "axis = \"x\"\n") +
                             "size = 1.0\n";
    accepted(parse, text, sc.title.substr(0, 3) + " documented fault kind " + k);
    ++n;
  }
  if (n < 5) {
    std::printf("FAIL %s: %d documented fault kinds\n", sc.title.c_str(), n);
    ++g_fail;
  }
}

int main() {
  auto p2 = [](const std::string& t) { return truth::parse_scenario(t, "t", "test"); };
  auto p3 = [](const std::string& t) { return truth3d::parse_scenario3(t, "t", "test"); };

  // 2-D: finiteness, ranges (open and closed ends), types, unknown keys and sections
  refused(p2, "[time]\nrate_hz = nan\n", "test:2: time.rate_hz = nan: must be finite (allowed: (0, 1e6] Hz)");
  refused(p2, "[time]\nrate_hz = inf\n", "test:2: time.rate_hz = inf: must be finite");
  refused(p2, "\n[time]\nduration_s = -5\n", "test:3: time.duration_s = -5: out of range (allowed: (0, 1e7] s)");
  refused(p2, "[time]\nduration_s = 0.0\n", "time.duration_s = 0.0: out of range");
  refused(p2, "[transport]\ndrop_prob = 1.0\n", "test:2: transport.drop_prob = 1.0: out of range (allowed: [0, 1))");
  accepted(p2, "[transport]\ndrop_prob = 0.0\n", "transport.drop_prob = 0 (closed end)");
  accepted(p2, "[time]\nrate_hz = 1e6\n", "time.rate_hz = 1e6 (closed end)");
  refused(p2, "[time]\nrate_hz = 1000001.0\n", "time.rate_hz = 1000001.0: out of range");
  accepted(p2, "[platform]\na_m = 100.0\n", "platform.a_m = 100 (closed end)");
  refused(p2, "[platform]\na_m = 100.5\n", "platform.a_m = 100.5: out of range (allowed: (0, 100] m)");
  refused(p2, "[accel]\nbias_sigma_mps2 = 1e6\n", "accel.bias_sigma_mps2 = 1000000.0: out of range (allowed: [0, 1] m/s^2)");
  refused(p2, "[accel]\nseed = -1\n", "test:2: accel.seed = -1: out of range (allowed: >= 0)");
  refused(p2, "[accel]\nseed = 1.5\n", "accel.seed = 1.5: must be an integer");
  refused(p2, "[accel]\nbias = 1\n", "test:2: unknown key 'accel.bias' (allowed: bias_mps2, bias_sigma_mps2,");
  refused(p2, "name = \"x\"\n[acel]\n", "test:2: unknown key 'acel' (allowed: accel, baro,");
  refused(p2, "[navigation.modell]\n", "unknown key 'navigation.modell'");
  refused(p2, "[platform]\na_m = \"x\"\n", "test:2: platform.a_m = \"x\": must be a number");
  refused(p2, "[platform]\na_m = true\n", "platform.a_m = true: must be a number");
  refused(p2, "trajectory = 3\n", "test:1: 'trajectory' must be a table");
  refused(p2, "[firmware]\ngravdr_trapezoid_only = 1\n", "firmware.gravdr_trapezoid_only = 1: must be true or false");
  refused(p2, "[gravity]\nmodel = \"egm2008\"\n",
          "gravity.model = \"egm2008\": unknown value (allowed: \"point-mass\", \"wgs84-normal\", \"rw-anomaly\")");
  refused(p2, "[gravity.anomaly]\nlattice_points = 7\n", "gravity.anomaly.lattice_points = 7: must be even");
  refused(p2, "[navigation.baro]\npoles_radps = [0.01, 0.0, 0.03]\n",
          "test:2: navigation.baro.poles_radps[1] = 0.0: out of range (allowed: (0, 1000] rad/s)");
  refused(p2, "[navigation.baro]\npoles_radps = [1.0]\n", "navigation.baro.poles_radps = [1.0]: must be an array of 3 numbers");
  refused(p2, "[accel]\nbias_mps2 = [[1.0, 2.0]]\n", "accel.bias_mps2[0] = [1.0, 2.0]: must be an array of 3 numbers");
  refused(p2, "[baro]\ndropouts = [[5.0, 1.0]]\n", "baro.dropouts[0] = [5.0, 1.0]: needs t1_s > t0_s");
  refused(p2, "[time]\nrate_hz = 7.0\n", "test:2: time.rate_hz = 7.0: must make 1e6/rate_hz an integer number of microseconds");
  refused(p2, "name = \"\"\n", "test:1: name = \"\": must have 1..63 characters");
  refused(p2, "[time\n", "test:1:");
  // [sensor_faults]: the one reader of both tasks names file:line, the key, the value and what is allowed
  refused(p2, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 5\naxis = \"x\"\n",
          "test:4: sensor_faults.fault[0].sensor = 5: must be an accelerometer (allowed: [1, 4])");
  refused(p2, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 1\naxis = \"y\"\n",
          "test:5: sensor_faults.fault[0].axis = \"y\": unknown value (allowed: \"x\", \"z\")");
  refused(p2, "\n[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 1\n",
          "test:3: sensor_faults.fault[0].axis is required for kind 'step' (allowed: \"x\", \"z\")");
  refused(p2, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 1\naxis = \"x\"\nprob = 0.0\n",
          "test:6: sensor_faults.fault[0].prob = 0.0: out of range (allowed: (0, 1])");
  refused(p2, "[sensor_faults]\nseed = -3\n", "test:2: sensor_faults.seed = -3: out of range (allowed: >= 0)");
  refused(p2, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"time_jump\"\nsize = 0.5\n",
          "test:4: sensor_faults.fault[0].size = 0.5: must be a whole number of microseconds");
  refused(p3, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"noise\"\nsensor = \"gyro\"\naxis = \"z\"\n",
          "test:2: sensor_faults.fault[0].size: the noise's standard deviation must be > 0");
  accepted(p3, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = \"gyro\"\naxis = \"y\"\nsize = 1e-9\n",
           "3-D sensor = \"gyro\"");
  refused(p2, "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = \"gyro\"\naxis = \"x\"\n",
          "test:4: sensor_faults.fault[0].sensor = \"gyro\": must be an accelerometer (allowed: [1, 4])");

  // 3-D: the same checks through the shared tables, and its own keys
  refused(p3, "[time]\nrate_hz = nan\n", "test:2: time.rate_hz = nan: must be finite (allowed: (0, 1e6] Hz)");
  refused(p3, "[accel]\nbias_mps2 = [[0.0, 0.0, 0.0]]\n", "accel.bias_mps2 = [[0.0, 0.0, 0.0]]: must be an array of 6 [x, y, z]");
  refused(p3, "[trajectory]\ntype = \"flight\"\nturn_rate_dps = 2.0\n",
          "test:3: trajectory.turn_rate_dps is a key of type = \"route\"");
  refused(p3, "[aid_ukf]\nmax_passes = 0\n", "test:2: aid_ukf.max_passes = 0: out of range (allowed: [1, 100])");
  refused(p3, "[aid_ukf]\nsigma_meas_E = nan\n", "aid_ukf.sigma_meas_E = nan: must be finite");
  refused(p3, "[aid_ukf]\nenabled = true\n", "test:2: aid_ukf.enabled needs aid_ukf.map");
  refused(p3, "[firmware]\nfdi_parity_f_max_mps2 = 1e-13\n", "firmware.fdi_parity_f_max_mps2 = 1e-13: must be 0 (off) or >=");
  refused(p3, "[firmware]\nacc_frozen_frames = 1\n", "test:2: firmware.acc_frozen_frames = 1: must be 0 (off) or 2..60000");
  refused(p2, "[firmware]\nacc_frozen_frames = 60001\n", "firmware.acc_frozen_frames = 60001: out of range (allowed: [0, 60000] frames)");
  refused(p2, "[firmware]\nacc_frozen_frames = -1\n", "firmware.acc_frozen_frames = -1: out of range");
  refused(p3, "[firmware]\nf_max_mps2 = -1.0\n", "firmware.f_max_mps2 = -1.0: out of range (allowed: (0, 1e6] m/s^2)");
  refused(p3, "[gyro]\nscale = [0.0, 0.0]\n", "gyro.scale = [0.0, 0.0]: must be an array of 3 numbers");
  refused(p3, "[platform]\nkind = \"gimbal\"\n", "platform.kind = \"gimbal\": unknown value (allowed: \"stabilized\", \"strapdown\")");
  refused(p3, "[navigation.baro]\nalt_min_m = 100.0\nalt_max_m = 50.0\n", "test:3: navigation.baro: alt_max_m must be > alt_min_m");
  refused(p3, "[[trajectory.maneuver]]\nduration_s = 0.0\n",
          "test:2: trajectory.maneuver[1].duration_s = 0.0: out of range (allowed: (0, 1e8] s)");
  refused(p3, "[gravity.sh]\nnmax = 361\n", "gravity.sh.nmax = 361: out of range (allowed: [2, 360])");
  accepted(p3, "[aid_ukf]\nenabled = false\nmax_passes = 100\n", "aid_ukf.max_passes = 100 (closed end)");

  {  // values derived from [accel] stay derived in a printed scenario: edit its noise and the
     // fault thresholds follow (a campaign that sweeps the noise starts from a printed scenario)
    const auto base = p3("[accel]\nnoise_sigma_mps2 = 5.5e-10\n");
    truth3d::Scenario3 edited = base;
    edited.accel.noise_sigma_mps2 = 5.5e-8;
    const std::string printed = truth3d::scenario3_to_toml(edited);
    const auto again = p3(printed);
    const auto direct = p3("[accel]\nnoise_sigma_mps2 = 5.5e-8\n");
    const bool derived_again = again.fdi_parity_f_max_mps2 == direct.fdi_parity_f_max_mps2 &&
                               again.fdi_parity_f_max_mps2 != base.fdi_parity_f_max_mps2 &&
                               again.firmware.acc_frozen_frames == direct.firmware.acc_frozen_frames;
    std::printf("%s printed, noise edited, read again: fdi_parity_f_max %.4g (the edited noise's %.4g, the printed "
                "one's %.4g)\n", derived_again ? "ok  " : "FAIL", again.fdi_parity_f_max_mps2,
                direct.fdi_parity_f_max_mps2, base.fdi_parity_f_max_mps2);
    if (!derived_again) ++g_fail;
    const auto given = p3("[firmware]\nfdi_parity_f_max_mps2 = 1e-9\nacc_frozen_frames = 20\n");
    const std::string kept = truth3d::scenario3_to_toml(given);
    const bool written = kept.find("fdi_parity_f_max_mps2 = 1e-09") != std::string::npos &&
                         kept.find("acc_frozen_frames = 20") != std::string::npos &&
                         printed.find("fdi_parity_f_max_mps2") == std::string::npos &&
                         printed.find("acc_frozen_frames") == std::string::npos;
    std::printf("%s thresholds given in the file are written back, derived ones are not\n", written ? "ok  " : "FAIL");
    if (!written) ++g_fail;
  }
  {  // 2-D: the thresholds follow the biases drawn for the flight (fdi_thresholds.hpp), so a printed
     // scenario flown with another seed derives them for that seed; given ones are written back
    const std::string head = "[time]\nduration_s = 60.0\n[accel]\nbias_sigma_mps2 = 1e-9\nnoise_sigma_mps2 = 1e-10\n";
    const auto base = p2(head + "seed = 1\n");
    truth::Scenario edited = base;
    edited.accel.seed = 2;
    const std::string printed = truth::scenario_to_toml(edited);
    const auto again = p2(printed);
    const truth::FdiThresholds th = truth::derive_fdi_thresholds(edited);  // the seed-2 biases
    const bool derived_again = again.firmware.fdi_parity_f_max_mps2 == th.parity_f_max_mps2 &&
                               again.firmware.fdi_asym_max_ps2 == th.asym_max_ps2 &&
                               again.firmware.fdi_parity_f_max_mps2 != base.firmware.fdi_parity_f_max_mps2 &&
                               printed.find("fdi_parity_f_max_mps2") == std::string::npos &&
                               printed.find("fdi_asym_max_ps2") == std::string::npos;
    std::printf("%s 2-D printed, seed edited, read again: fdi_parity_f_max %.4g (seed 2's %.4g, seed 1's %.4g)\n",
                derived_again ? "ok  " : "FAIL", again.firmware.fdi_parity_f_max_mps2, th.parity_f_max_mps2,
                base.firmware.fdi_parity_f_max_mps2);
    if (!derived_again) ++g_fail;
    const auto given = p2(head + "[firmware]\nfdi_parity_f_max_mps2 = 1e-7\nfdi_asym_max_ps2 = 2e-7\n");
    const std::string kept = truth::scenario_to_toml(given);
    const bool written = kept.find("fdi_parity_f_max_mps2 = 1e-07") != std::string::npos &&
                         kept.find("fdi_asym_max_ps2 = 2e-07") != std::string::npos &&
                         given.firmware.fdi_parity_f_max_mps2 == 1e-7 && given.firmware.fdi_asym_max_ps2 == 2e-7;
    std::printf("%s 2-D thresholds given in the file are kept and written back\n", written ? "ok  " : "FAIL");
    if (!written) ++g_fail;
  }
  defaults_accepted(truth::scenario_schema(), p2, "");
  defaults_accepted(truth3d::scenario3_schema(), p3, "");
  documented_fault_kinds_accepted(truth::scenario_schema(), p2, "1");
  documented_fault_kinds_accepted(truth3d::scenario3_schema(), p3, "0");
  if (g_fail) std::printf("%d check(s) failed\n", g_fail);
  return g_fail ? 1 : 0;
}
