// Seed corpora for the fuzz harnesses (scripts/fuzz runs it):
//   <dir>/frame/   runs of consecutive encoded sensor_frame_t of the welker-perfect
//                  flight from seq 0 (what fuzz_frame's configuration expects), clean
//                  and with injected sensor faults
//   <dir>/config/  encoded nav2d_config_t of that flight (parity checks on and off)
//   <dir>/config3d/ encoded nav3d_config_t of fuzz_nav3d's reference configuration (a
//                  platform at rest at the equator, point-mass field, non-rotating):
//                  stabilized and strapdown, gradiometer and model gravity, barometer,
//                  fault detection, the map UKF and the particle filter
// usage: fuzz_seeds DIR
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ggins/nav2d_config_t.hpp"
#include "ggins/nav3d_config_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth/generator.hpp"

namespace fs = std::filesystem;
using namespace ggins::truth;

static void put(const fs::path& p, const std::vector<uint8_t>& b) {
  std::ofstream o(p, std::ios::binary);
  o.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// fuzz_nav3d.c's ref_config and ref_aids as a message (sel: bit 0 strapdown, bit 1
// gravity model, bit 2 barometer, bit 3 fault detection; aid: bit 0 map UKF, bit 1
// particle filter, bit 2 its velocity feedback, bit 3 its INS model, bit 4 NIS gate, bit 5
// the frozen-reading monitor)
static std::vector<uint8_t> config3d(unsigned sel, unsigned aid) {
  const double gm = 3.986004418e14, r0 = 6378137.0;
  ggins::nav3d_config_t c{};
  c.run_id = 1;
  for (double& h : c.half_base_m) h = 0.5;
  c.platform = (sel & 1u) ? 1 : 0;
  c.dt_us = 10000;
  c.dt_tol_us = 100;
  c.r0_hi[0] = r0;
  c.g0_hi[0] = -gm / (r0 * r0);
  c.q0_hi[0] = 1.0;
  c.omega_ie_hi = -1.0;  // non-rotating
  c.f_max = 100.0;
  c.asym_max = 1e-6;
  c.fdi_parity_f_max = (sel & 8u) ? 2e-12 : 0.0;  // GG_FDI3D_FLOOR_MPS2
  c.gravity_mode = (sel & 2u) ? 1 : 0;
  if (sel & 2u) {
    c.model_gm_hi = gm;
    c.model_a_m = r0;
  }
  c.baro_enable = (sel & 4u) ? 1 : 0;
  c.baro_poles[0] = 0.01;
  c.baro_poles[1] = 0.012;
  c.baro_poles[2] = 0.014;
  c.baro_omega_s2 = 9.8 / 6.4e6;
  c.baro_period_us = 100000;
  c.baro_max_age_us = 100000;
  c.baro_coast_us = 1000000;
  c.baro_alt_min_m = -1000.0;
  c.baro_alt_max_m = 30000.0;
  c.baro_gate_m = 50.0;
  c.baro_max_rejects = 10;
  c.aid_mm_enable = (aid & 1u) ? 1 : 0;
  c.aid_mm_update_steps = 6;
  c.aid_mm_max_passes = 2;
  c.aid_mm_sigma_meas_s2 = 1e-11;
  c.aid_mm_sigma_db_s2 = 1e-12;
  c.aid_mm_offdiag_ratio = 0.70710678118654752;
  c.aid_mm_sig0_pos_m = 50.0;
  c.aid_mm_sig0_vel_mps = 0.05;
  c.aid_mm_sig0_att_rad = 1e-6;
  c.aid_mm_sig0_g_mps2 = 1e-7;
  c.aid_mm_q_vel_mps_rts = 1e-6;
  c.aid_mm_q_att_rad_rts = 1e-9;
  c.aid_mm_q_g_mps2_rts = 1e-9;
  c.aid_mm_gate_nis = (aid & 16u) ? 30.0 : 0.0;
  c.acc_frozen_frames = (aid & 32u) ? 4 : 0;
  c.aid_mm_average_steps = 4;
  c.aid_mm_sigma_gyro_rps = 1e-8;
  c.aid_pf_enable = (aid & 2u) ? 1 : 0;
  c.aid_pf_chunk = 8;
  c.aid_pf_end_chunk = 16;
  c.aid_pf_feedback = (aid & 4u) ? 1 : 0;
  c.aid_pf_n = 16;
  c.aid_pf_seed = 7;
  c.aid_pf_model = (aid & 8u) ? 1 : 0;
  c.aid_pf_k_eff = 4.0 * 3.14159265358979323846 / 852.347e-9;
  c.aid_pf_T = 0.16;
  c.aid_pf_dz = 1.0;
  c.aid_pf_contrast = 0.5;
  c.aid_pf_c0 = 0.5;
  c.aid_pf_c1 = 0.5;
  c.aid_pf_sigma = 0.005;
  c.aid_pf_sigma0_pos = 100.0;
  c.aid_pf_sigma0_vel = 0.1;
  c.aid_pf_sigma0_acc = 1e-4;
  c.aid_pf_q_pos = 1.0;
  c.aid_pf_q_vel = 0.01;
  c.aid_pf_q_acc = 1e-6;
  c.aid_pf_dt = 1.0;
  c.aid_pf_gain = 1.0;
  c.aid_pf_ess_frac = 0.5;
  std::vector<uint8_t> b(static_cast<size_t>(c.getEncodedSize()));
  c.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

static std::vector<uint8_t> frames(const Scenario& s, int n) {
  Generator g(s);
  std::vector<uint8_t> out;
  for (int k = 0; k < n; ++k) {
    gg_frame_t f;
    g.frame(k, f);
    ggins::sensor_frame_t m{};
    m.utime = f.utime;
    m.seq = f.seq;
    m.run_id = 1;
    m.n_acc = f.n_acc;
    std::memcpy(m.f, f.f, sizeof m.f);
    std::memcpy(m.f_lo, f.f_lo, sizeof m.f_lo);
    for (int i = 0; i < 6; ++i) m.acc_status[i] = f.acc_status[i];
    m.gyro_status = f.gyro_status;
    m.baro_alt_m = f.baro_alt_m;
    m.baro_utime = f.baro_utime;
    m.baro_status = f.baro_status;
    std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    out.insert(out.end(), b.begin(), b.end());
  }
  return out;
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds DIR\n");
    return 2;
  }
  const fs::path dir(argv[1]);
  fs::create_directories(dir / "frame");
  fs::create_directories(dir / "config");
  const std::string base = "name = \"seed\"\n[time]\nduration_s = 1.0\nrate_hz = 100\n";
  const char* faults[] = {
      "",
      "kind = \"nan\"\nsensor = 3\naxis = \"z\"\nstart_s = 0.03\n",
      "kind = \"inf\"\nsensor = 1\naxis = \"x\"\nstart_s = 0.03\n",
      "kind = \"range\"\nsensor = 2\naxis = \"z\"\nstart_s = 0.03\nsize = 1e3\n",
      "kind = \"step\"\nsensor = 2\naxis = \"x\"\nstart_s = 0.03\nsize = 1e-9\n",
      "kind = \"step\"\nsensor = 1\naxis = \"x\"\nstart_s = 0.03\nsize = 1e-9\n",
      "kind = \"stuck\"\nsensor = 4\naxis = \"z\"\nstart_s = 0.03\n",
      "kind = \"status_bad\"\nsensor = 3\nstart_s = 0.03\n",
      "kind = \"time_jump\"\nstart_s = 0.03\nduration_s = 0.01\nsize = 5000\n",
      "kind = \"time_repeat\"\nstart_s = 0.03\nduration_s = 0.01\n",
  };
  int i = 0;
  for (const char* f : faults) {
    std::string text = base;
    if (*f) text += std::string("[sensor_faults]\n[[sensor_faults.fault]]\n") + f;
    const Scenario s = parse_scenario(text, "seed", "seed");
    for (int n : {2, 8}) put(dir / "frame" / ("seed_" + std::to_string(i++)), frames(s, n));
  }
  // configuration messages
  const Scenario s = parse_scenario(base, "seed", "seed");
  Generator g(s);
  const TruthState t0 = g.truth(0);
  for (int fdi = 0; fdi < 2; ++fdi) {
    ggins::nav2d_config_t c{};
    c.run_id = 1;
    c.a_m = 0.5;
    c.b_m = 0.5;
    c.dt_us = 10000;
    for (int j = 0; j < 3; ++j) {
      c.r0_hi[j] = static_cast<double>(t0.kin.r(j));
      c.r0_lo[j] = static_cast<double>(t0.kin.r(j) - static_cast<Real>(c.r0_hi[j]));
      c.v0_hi[j] = static_cast<double>(t0.kin.v(j));
      c.g0_hi[j] = static_cast<double>(t0.g(j));
      c.g0_lo[j] = static_cast<double>(t0.g(j) - static_cast<Real>(c.g0_hi[j]));
    }
    c.f_max = 50;
    c.asym_max = 1e-6;
    c.fdi_parity_f_max = fdi ? 1e-11 : 0;
    c.fdi_asym_max = fdi ? 1e-11 : 0;
    std::vector<uint8_t> b(static_cast<size_t>(c.getEncodedSize()));
    c.encode(b.data(), 0, static_cast<int>(b.size()));
    put(dir / "config" / ("seed_" + std::to_string(fdi)), b);
  }
  // 3-D configuration messages
  fs::create_directories(dir / "config3d");
  int n3 = 0;
  for (unsigned sel : {0x0u, 0x1u, 0x2u, 0x4u, 0x8u, 0xfu})
    for (unsigned aid : {0x00u, 0x01u, 0x02u, 0x1fu, 0x20u}) {
      char name[32];
      std::snprintf(name, sizeof name, "ref-%02x-%02x", sel, aid);
      put(dir / "config3d" / name, config3d(sel, aid));
      ++n3;
    }
  std::printf("fuzz_seeds: %d frame seeds, 2 configuration seeds, %d 3-D configuration seeds in %s\n", i, n3,
              dir.c_str());
  return 0;
}
