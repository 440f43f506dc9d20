// Firmware step benchmark (not a test): flies a scenario's frames, from the
// simulation library (truth/generator.hpp, truth3d/generator3d.hpp; frames
// precomputed), through gg_nav2d_step or gg_nav3d_step in process with the
// configuration of the same scenario (truth/config2d.hpp, truth3d/config3d.hpp),
// and reports the time per module from the HAL cycle counter (host:
// CLOCK_MONOTONIC in ns). With --no-timing the step runs with no cycle
// counter at all (deterministic instruction counts under valgrind
// --tool=callgrind; scripts/bench does that).
//   nav2d: welker-perfect with a 1 Hz barometer and its loop (300 m/s north flight, 100 Hz);
//   nav3d: 3d-strapdown-1h (maneuvering strapdown flight, 100 Hz, 1 Hz barometer loop).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

extern "C" {
#include "ggins/nav2d.h"
#include "ggins/nav3d.h"
}
#include "ggins/cli_checks.hpp"
#include "ggins/truth/config2d.hpp"
#include "ggins/truth/generator.hpp"
#include "ggins/truth3d/config3d.hpp"
#include "ggins/truth3d/generator3d.hpp"

namespace {

uint32_t mono_ns(void* ctx) {
  (void)ctx;
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) * 1000000000u + static_cast<uint64_t>(ts.tv_nsec));
}

const char* kNames[GG_MOD_COUNT] = {"diff", "gravdr/model", "mech", "vchan", "total", "aid_mm", "aid_pf"};

void print_table(std::vector<std::vector<uint32_t>>& cyc) {
  std::printf("  %-13s %9s %9s %9s\n", "module", "median", "p99", "max");
  for (int m = 0; m < GG_MOD_COUNT; ++m) {
    auto& c = cyc[static_cast<size_t>(m)];
    std::sort(c.begin() + 1, c.end());  // step 0 = start
    const size_t n = c.size() - 1;
    std::printf("  %-13s %9u %9u %9u\n", kNames[m], c[1 + n / 2], c[1 + (n * 99) / 100], c[n]);
  }
}

template <class Nav, class Cfg, class Out, class Init, class Step>
int fly(const std::vector<gg_frame_t>& frames, const Cfg& cfg, Init init, Step step, bool timing, bool quiet,
        const std::string& title) {
  static Nav nav;  // large: static
  if (init(&nav, &cfg) != GG_OK) {
    std::fprintf(stderr, "bench_step: the firmware refused the configuration\n");
    return 1;
  }
  const gg_hal_t hal = {nullptr, nullptr, nullptr, mono_ns, 1000000000u, nullptr, nullptr};
  std::vector<std::vector<uint32_t>> cyc(GG_MOD_COUNT, std::vector<uint32_t>(frames.size()));
  long rejected = 0;
  Out out;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (step(&nav, &frames[k], timing ? &hal : nullptr, &out) != GG_OK) ++rejected;
    for (int m = 0; m < GG_MOD_COUNT; ++m) cyc[static_cast<size_t>(m)][k] = out.cycles[m];
  }
  if (!quiet) {
    std::printf("%s, %zu steps (%ld rejected), ns per step:\n", title.c_str(), frames.size(), rejected);
    print_table(cyc);
  }
  return rejected ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Firmware step benchmark: time per module of gg_nav2d_step / gg_nav3d_step on a scenario's frames "
               "(simulation library), median / p99 / max ns",
               "bench_step"};
  long steps = 100000;
  std::string mode = "gradiometer", task = "nav2d", scenario;
  bool no_timing = false;
  app.add_option("--steps", steps, "steps flown (frames precomputed)")->capture_default_str()->check(CLI::Range(2L, 10000000L));
  app.add_option("--mode", mode, "2-D gravity source")->capture_default_str()->check(CLI::IsMember({"gradiometer", "model"}));
  app.add_option("--task", task, "the task timed")->capture_default_str()->check(CLI::IsMember({"nav2d", "nav3d"}));
  app.add_option("-s,--scenario", scenario, "scenario (default: welker-perfect with a 1 Hz barometer loop; 3d-strapdown-1h)");
  app.add_flag("--no-timing", no_timing, "no cycle counter (for callgrind instruction counts); prints nothing");
  try {  // bad arguments: CLI11's message naming the option, exit 2 (ggins/cli_checks.hpp)
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? ggins::cli::kExitOk : ggins::cli::kExitBadArgs;
  }
  const bool quiet = no_timing, timing = !no_timing;
  const std::vector<std::string> dirs = {"scenarios", GGINS_SCENARIO_DIR};
  try {
    std::vector<gg_frame_t> frames(static_cast<size_t>(steps));
    if (task == "nav3d") {
      const ggins::truth3d::Scenario3 s = ggins::truth3d::load_scenario3(scenario.empty() ? "3d-strapdown-1h" : scenario, dirs);
      const ggins::truth3d::Generator3 g(s);
      if (steps > g.n_steps()) throw std::invalid_argument("--steps beyond the scenario's " + std::to_string(g.n_steps()));
      for (long k = 0; k < steps; ++k) g.frame(k, frames[static_cast<size_t>(k)]);
      const gg_nav3d_config_t cfg = ggins::truth3d::config3d(s, g);
      return fly<gg_nav3d_t, gg_nav3d_config_t, gg_nav3d_output_t>(frames, cfg, gg_nav3d_init, gg_nav3d_step, timing,
                                                                     quiet, "gg_nav3d_step, " + s.name);
    }
    ggins::truth::Scenario s = ggins::truth::load_scenario(scenario.empty() ? "welker-perfect" : scenario, dirs);
    if (scenario.empty()) s.baro.enable = true;  // 1 Hz, perfect; the loop follows it
    if (mode == "model") s.navigation.gravity = "model";
    const ggins::truth::Generator g(s);
    if (steps > g.n_steps()) throw std::invalid_argument("--steps beyond the scenario's " + std::to_string(g.n_steps()));
    for (long k = 0; k < steps; ++k) g.frame(k, frames[static_cast<size_t>(k)]);
    const gg_nav2d_config_t cfg = ggins::truth::config2d(g);
    return fly<gg_nav2d_t, gg_nav2d_config_t, gg_nav_output_t>(
        frames, cfg, gg_nav2d_init, gg_nav2d_step, timing, quiet,
        "gg_nav2d_step, " + s.name + ", " + (mode == "model" ? "gravity-model" : "gradiometer") + " mode");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_step: %s\n", e.what());
    return 2;
  }
}
