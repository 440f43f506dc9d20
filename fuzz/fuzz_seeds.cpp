// Seed corpora for the fuzz harnesses (scripts/fuzz runs it):
//   <dir>/frame/   runs of consecutive encoded sensor_frame_t of the welker-perfect
//                  flight from seq 0 (what fuzz_frame's configuration expects), clean
//                  and with injected sensor faults
//   <dir>/config/  encoded nav2d_config_t of that flight (parity checks on and off)
// usage: fuzz_seeds DIR
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ggins/nav2d_config_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth/generator.hpp"

namespace fs = std::filesystem;
using namespace ggins::truth;

static void put(const fs::path& p, const std::vector<uint8_t>& b) {
  std::ofstream o(p, std::ios::binary);
  o.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
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
  std::printf("fuzz_seeds: %d frame seeds, 2 configuration seeds in %s\n", i, dir.c_str());
  return 0;
}
