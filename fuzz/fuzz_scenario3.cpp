// libFuzzer harness: the 3-D scenario parser (TOML -> ggins::truth3d::Scenario3,
// every table of the schema: trajectory with routes and maneuvers, gravity,
// sensors, [sensor_faults], aids). Any input must either parse or be refused with
// std::runtime_error (exit 2 of ggins run3d, naming the key): no crash, no other
// exception, no sanitizer report. A scenario that parses with an analytic field
// (no EGM96 coefficients, no cold-atom gradiometer: both read data files) must
// build its 3-D truth generator and generate its first and last frames.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ggins::truth3d::Scenario3 s;
  try {
    s = ggins::truth3d::parse_scenario3(text, "fuzz", "fuzz-input");
  } catch (const std::runtime_error&) {
    return 0;  // refused with a message: fine
  }
  if (s.name.empty() || s.name.size() > 63) {
    std::fprintf(stderr, "FUZZ INVARIANT BROKEN: parsed scenario with a name of %zu characters\n", s.name.size());
    std::abort();
  }
  if (s.gravity.model != "egm96" && !s.coldatom.enabled && s.n_steps() > 1 && s.n_steps() < (int64_t(1) << 40)) {
    const ggins::truth3d::Generator3 g(s);
    gg_frame_t f;
    g.frame(0, f);
    g.frame(g.n_steps() - 1, f);
    if (int64_t(f.seq) != g.n_steps() - 1) {
      std::fprintf(stderr, "FUZZ INVARIANT BROKEN: frame seq\n");
      std::abort();
    }
  }
  return 0;
}
