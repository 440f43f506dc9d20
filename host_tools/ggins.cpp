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
#include "ggins_commands.inc"
};

static void usage(FILE* out) {
  std::fprintf(out,
               "usage: ggins <command> [options]   (ggins <command> --help for its options)\n\n"
               "ggins - gravity-gradiometer integrated INS: host tools.\n\ncommands:\n");
  for (const auto& c : kCommands) std::fprintf(out, "  %-12s %s\n", c.name, c.what);
  std::fprintf(out,
               "\nexit status (every command):\n"
               "  0    done: every step flown and used, every output written\n"
               "  1    failed (the message says why)\n"
               "  2    bad arguments or bad input file (the option or key, its value and the allowed range are named)\n"
               "  3    the machine lacks what the command needs (e.g. no multicast route on loopback for LCM)\n"
               "  4    completed but degraded (frames rejected, outputs missing, an outage at the end) or a corrupt log\n"
               "  5    incomplete record (a log that lacks steps or outputs)\n"
               "  130  interrupted (Ctrl-C / SIGTERM); a partial report is marked interrupted\n"
               "\nWith no command, `ggins` prints this help. A command not built yet is reported.\n");
}

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    usage(stdout);
    return 0;
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
