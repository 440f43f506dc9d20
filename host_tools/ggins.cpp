// ggins: one command for the host tools, git-style. `ggins <command> args`
// runs the program `ggins-<command>` that sits beside this one.
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

static const struct {
  const char* name;
  const char* what;
} kCommands[] = {
    {"run", "host-in-the-loop run of a scenario over LCM; writes summary.json, CSV, plots"},
    {"run3d", "3-D system (issue 7): fly a 3-D scenario over LCM (or --direct); summary.json, CSV, plots"},
    {"covariance", "covariance propagation of the linear error model (Table I of Welker et al.)"},
    {"montecarlo", "Monte Carlo host-in-the-loop runs against the covariance prediction"},
    {"covariance3d", "3-D error analysis on the rotating Earth: covariance, eigenvalues (issue 7)"},
    {"montecarlo3d", "3-D Monte Carlo of the firmware against the 3-D covariance (chi-square band)"},
    {"rw-eq8", "Rubenstein & Winter eq. 8: conventional INS in a random deflection field, Monte Carlo"},
    {"profile", "per-module firmware step timing for a scenario"},
    {"replay", "replay a recorded LCM log through the firmware, bit for bit"},
    {"gmap", "onboard gravity-gradient map tile from EGM96 (binary/JSON) for the map-matching filters"},
    {"mapnav", "gravity-gradient map matching UKF (Gao et al.) voyage vs pure inertial, Monte Carlo, NEES/NIS"},
    {"campaign", "Monte Carlo sets and parameter sweeps of these commands on Dask (local or a cluster), resumable"},
    {"coldatom", "cold-atom partial-gradient particle filter (Phillips et al.): Liverpool-Toulouse flights, sweeps"},
    {"field", "potential, gravitation and gradient of a model (normal, SH file, anomalies) at points or along a route"},
    {"spy", "lcm-spy with the ggins message types: decoded fields of a live run or a replayed log"},
    {"logtime", "LCM logs in Python (ggins_log): channels, event times rewritten to flight time, CSV"},
};

static void usage(FILE* out) {
  std::fprintf(out,
               "usage: ggins <command> [options]   (ggins <command> --help for its options)\n\n"
               "ggins - gravity-gradiometer integrated INS: host tools.\n\ncommands:\n");
  for (const auto& c : kCommands) std::fprintf(out, "  %-12s %s\n", c.name, c.what);
  std::fprintf(out, "\nWith no command, `ggins` prints this help. A command not built yet is reported.\n");
  std::fprintf(out,
               "\nexit status (mapnav, coldatom, covariance, covariance3d; host_tools/common/include/ggins/cli_checks.hpp):\n"
               "  0 success, 1 the run failed (the message says why), 2 bad arguments (the option or key, its value\n"
               "  and the allowed range are named). ggins run adds its own codes (ggins run --help).\n");
}

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    usage(stdout);
    return argc < 2 ? 0 : 0;
  }
  const std::string cmd = argv[1];
  std::error_code ec;
  fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) self = fs::absolute(argv[0]);
  const fs::path prog = self.parent_path() / ("ggins-" + cmd);
  if (!fs::exists(prog)) {
    std::fprintf(stderr, "ggins: unknown command '%s' (no %s)\n\n", cmd.c_str(), prog.c_str());
    usage(stderr);
    return 2;
  }
  std::vector<char*> args;
  std::string p = prog.string();
  args.push_back(p.data());
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execv(p.c_str(), args.data());
  std::perror("ggins: exec");
  return 127;
}
