// libFuzzer harness: the shared command-line checks (host_tools/lib/cli/ggins/cli_checks.hpp)
// and ggins covariance's scenario reader. The input's first byte picks the target:
//  - a command line (NUL-separated arguments) parsed by a CLI11 app whose options carry
//    every kind of validator: a parse either fails with CLI::ParseError (exit 2 of the tools)
//    or gives values inside the validators' ranges (finite, in range, seeds without a sign);
//  - a scenario TOML text for load_scenario_toml: it parses or throws std::runtime_error,
//    and a parsed scenario has finite positive duration, rate and half-baselines and finite,
//    non-negative sigmas.
// Any other exception, a value outside its range or a sanitizer report is a finding.
// Built in the fuzz build (scripts/fuzz: GGINS_FUZZ=ON) by tests/cli/CMakeLists.txt.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "ggins/cli_checks.hpp"
#include "ggins/covariance/scenario.hpp"

namespace {

[[noreturn]] void broken(const char* what) {
  std::fprintf(stderr, "FUZZ INVARIANT BROKEN: %s\n", what);
  std::abort();
}

void fuzz_cli(const std::string& text) {
  namespace C = ggins::cli;
  std::vector<std::string> args{"fuzz"};
  std::string cur;
  for (char c : text) {
    if (c == '\0') {
      args.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) args.push_back(cur);
  if (args.size() > 64) return;
  CLI::App app{"fuzz"};
  double fr = 1, pf = 1, nn = 0, fi = 0;
  int ir = 1;
  unsigned long long seed = 0;
  std::string out = "/tmp";
  app.add_option("--fr", fr)->check(C::FiniteRange(0, 1, C::kOpenLow));
  app.add_option("--pf", pf)->check(C::PositiveFinite());
  app.add_option("--nn", nn)->check(C::NonNegativeFinite());
  app.add_option("--fi", fi)->check(C::Finite());
  app.add_option("--ir", ir)->check(C::IntRange(1, 40));
  app.add_option("--seed", seed)->check(C::Seed());
  app.add_option("--out", out)->check(C::OutputDir());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError&) {
    return;  // refused with a message: exit 2 in the tools
  }
  if (!(fr > 0 && fr <= 1)) broken("--fr outside (0, 1]");
  if (!(std::isfinite(pf) && pf > 0)) broken("--pf not positive finite");
  if (!(std::isfinite(nn) && nn >= 0)) broken("--nn not non-negative finite");
  if (!std::isfinite(fi)) broken("--fi not finite");
  if (ir < 1 || ir > 40) broken("--ir outside [1, 40]");
  if (!C::output_dir_problem(out).empty()) broken("--out accepted but not writable");
}

void fuzz_scenario(const std::string& text) {
  char path[] = "/tmp/ggins-fuzz-cov-XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) return;
  const ssize_t n = write(fd, text.data(), text.size());
  close(fd);
  if (n != static_cast<ssize_t>(text.size())) {
    unlink(path);
    return;
  }
  try {
    const auto s = ggins::covariance::load_scenario_toml(path);
    unlink(path);
    auto pos = [](double v) { return std::isfinite(v) && v > 0; };
    auto sig = [](double v) { return std::isfinite(v) && v >= 0; };
    if (!pos(s.duration_s) || !pos(s.rate_hz) || !pos(s.a_m) || !pos(s.b_m) || !pos(s.radius_m) || !pos(s.gm_m3ps2))
      broken("scenario accepted with a non-positive or non-finite duration, rate, radius, GM or half-baseline");
    for (double v : s.bias_sigma_mps2)
      if (!sig(v)) broken("scenario accepted with a bad bias sigma");
    for (double v : s.noise_sigma_mps2)
      if (!sig(v)) broken("scenario accepted with a bad noise sigma");
    if (!sig(s.pos0_sigma_m) || !sig(s.vel0_sigma_mps) || !sig(s.gravity0_sigma_x_mps2) || !sig(s.gravity0_sigma_z_mps2))
      broken("scenario accepted with a bad initial sigma");
  } catch (const std::runtime_error&) {
    unlink(path);  // refused with a message: exit 2 of ggins covariance
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > 8192) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1) {
    fuzz_cli(text);
  } else {
    fuzz_scenario(text);
  }
  return 0;
}
