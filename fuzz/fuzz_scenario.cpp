// libFuzzer harness: the scenario parser (TOML -> ggins::truth::Scenario, with
// [sensor_faults]). Any input must either parse or be refused with
// std::runtime_error (exit 2 of ggins run, naming the key): no crash, no other
// exception, no sanitizer report. A scenario that parses with the point-mass
// field must build a truth generator and generate its first and last frames.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "ggins/truth/generator.hpp"
#include "ggins/truth/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ggins::truth::Scenario s;
  try {
    s = ggins::truth::parse_scenario(text, "fuzz", "fuzz-input");
  } catch (const std::runtime_error&) {
    return 0;  // refused with a message: fine
  }
  if (s.name.empty()) {
    std::fprintf(stderr, "FUZZ INVARIANT BROKEN: parsed scenario without a name\n");
    std::abort();
  }
  if (s.gravity.model == "point-mass" && s.n_steps() > 0 && s.n_steps() < (int64_t(1) << 40)) {
    ggins::truth::Generator g(s);
    gg_frame_t f;
    g.frame(0, f);
    g.frame(g.n_steps() - 1, f);
    if (f.seq != g.n_steps() - 1) {
      std::fprintf(stderr, "FUZZ INVARIANT BROKEN: frame seq\n");
      std::abort();
    }
  }
  return 0;
}
