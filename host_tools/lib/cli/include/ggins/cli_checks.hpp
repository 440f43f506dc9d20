// Checks of command-line values shared by the host tools (CLI11 validators), and the
// one exit-code scheme of the ggins commands:
//   0  success
//   1  the run failed (an error while computing or writing; the message says what)
//   2  bad arguments: an option's value out of its range, not a number, a scenario
//      that does not parse or has an unknown key, an output path that cannot be made
// Every validator's message names the value and the allowed range; CLI11 prefixes the
// option's name ("--dt: value 0 is not in (0, 1]").
//
//   app.add_option("--dt", dt)->check(ggins::cli::FiniteRange(0, 1, ggins::cli::kOpenLow));
//   return ggins::cli::run("ggins-foo", app, argc, argv, [&] { ...; return 0; });
#pragma once

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace ggins::cli {

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitBadArgs = 2;

// A bad argument found after parsing (a combination of options, a scenario key):
// run() reports it with exit 2.
struct BadArgument : std::runtime_error {
  using std::runtime_error::runtime_error;
};

namespace detail {

inline std::string fmt(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

// The whole string as a double (strtod accepts "nan", "inf": those are reported by the
// callers as not finite); false for trailing characters or an empty string.
inline bool parse_double(const std::string& s, double& v) {
  if (s.empty()) return false;
  const char* b = s.c_str();
  char* e = nullptr;
  errno = 0;
  v = std::strtod(b, &e);
  if (e == b) return false;
  while (*e == ' ' || *e == '\t') ++e;
  return *e == '\0';
}

// The whole string as a decimal integer (optional sign); false otherwise or on overflow.
inline bool parse_int(const std::string& s, long long& v) {
  if (s.empty()) return false;
  const char* b = s.c_str();
  char* e = nullptr;
  errno = 0;
  v = std::strtoll(b, &e, 10);
  return e != b && *e == '\0' && errno != ERANGE;
}

}  // namespace detail

enum Bounds { kClosed = 0, kOpenLow = 1, kOpenHigh = 2, kOpen = 3 };

// A finite number in [lo, hi] (or (lo, hi], [lo, hi), (lo, hi) with bounds); NaN and
// +-inf are refused whatever the range.
inline CLI::Validator FiniteRange(double lo, double hi, int bounds = kClosed) {
  const bool ol = (bounds & kOpenLow) != 0, oh = (bounds & kOpenHigh) != 0;
  const std::string range = std::string(ol ? "(" : "[") + detail::fmt(lo) + ", " + detail::fmt(hi) + (oh ? ")" : "]");
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        double v = 0;
        if (!detail::parse_double(s, v)) return "value '" + s + "' is not a number (allowed: a finite number in " + range + ")";
        if (!std::isfinite(v)) return "value " + s + " is not finite (allowed: a finite number in " + range + ")";
        const bool low_ok = ol ? v > lo : v >= lo, high_ok = oh ? v < hi : v <= hi;
        if (!low_ok || !high_ok) return "value " + s + " is not in " + range;
        return std::string();
      },
      "FINITE in " + range, "FiniteRange");
}

constexpr double kInf = std::numeric_limits<double>::infinity();

inline CLI::Validator Finite() { return FiniteRange(-kInf, kInf, kOpen); }
inline CLI::Validator PositiveFinite() { return FiniteRange(0.0, kInf, kOpen); }
inline CLI::Validator NonNegativeFinite() { return FiniteRange(0.0, kInf, kOpenHigh); }

// An integer in [lo, hi].
inline CLI::Validator IntRange(long long lo, long long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        long long v = 0;
        if (!detail::parse_int(s, v)) return "value '" + s + "' is not an integer (allowed: an integer in " + range + ")";
        if (v < lo || v > hi) return "value " + s + " is not in " + range;
        return std::string();
      },
      "INT in " + range, "IntRange");
}

// A seed: a non-negative decimal integer up to max (no sign, so -1 never wraps to 2^64 - 1).
inline CLI::Validator Seed(std::uint64_t max = std::numeric_limits<std::uint64_t>::max()) {
  const std::string range = "[0, " + std::to_string(max) + "]";
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        bool digits = !s.empty() && s.size() <= 20;
        for (char c : s) digits = digits && c >= '0' && c <= '9';
        if (!digits) return "value '" + s + "' is not a non-negative integer (allowed: an integer in " + range + ")";
        errno = 0;
        const unsigned long long v = std::strtoull(s.c_str(), nullptr, 10);
        if (errno == ERANGE || v > max) return "value " + s + " is not in " + range;
        return std::string();
      },
      "SEED in " + range, "Seed");
}

// Why an output folder cannot be created or written ("" when it can): every existing
// component must be a folder, the deepest existing one writable.
inline std::string output_dir_problem(const std::string& s) {
  namespace fs = std::filesystem;
  if (s.empty()) return "an empty path";
  std::error_code ec;
  fs::path p = fs::absolute(fs::path(s), ec);
  if (ec) return "not a valid path";
  for (fs::path q = p; !q.empty(); q = q.parent_path()) {
    const auto st = fs::status(q, ec);
    if (fs::exists(st)) {
      if (!fs::is_directory(st)) return "'" + q.string() + "' exists and is not a folder";
      if (::access(q.c_str(), W_OK | X_OK) != 0) return "folder '" + q.string() + "' is not writable";
      return std::string();
    }
    if (q == q.parent_path()) break;
  }
  return "no existing parent folder";
}

// An output folder that exists and is writable, or can be created.
inline CLI::Validator OutputDir() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const std::string why = output_dir_problem(s);
        return why.empty() ? why
                           : "cannot write to folder '" + s + "': " + why +
                                 " (allowed: a writable folder, or one that can be created)";
      },
      "DIR (writable)", "OutputDir");
}

// Why an output file cannot be written ("" when it can): not a folder itself, its
// folder existing (or creatable) and writable.
inline std::string output_file_problem(const std::string& s) {
  namespace fs = std::filesystem;
  if (s.empty()) return "an empty path";
  std::error_code ec;
  const fs::path p = fs::absolute(fs::path(s), ec);
  if (ec) return "not a valid path";
  if (fs::is_directory(p, ec)) return "'" + p.string() + "' is a folder";
  if (fs::exists(p, ec) && ::access(p.c_str(), W_OK) != 0) return "'" + p.string() + "' is not writable";
  return output_dir_problem(p.parent_path().string());
}

// An output file that can be written (its folder exists or can be created).
inline CLI::Validator OutputFile() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const std::string why = output_file_problem(s);
        return why.empty() ? why
                           : "cannot write file '" + s + "': " + why + " (allowed: a writable file path)";
      },
      "FILE (writable)", "OutputFile");
}

// Write data to path; an output that cannot be written is an error (std::runtime_error).
inline void write_file(const std::string& path, const std::string& data, bool binary = false) {
  std::ofstream f(path, binary ? std::ios::binary | std::ios::out : std::ios::out);
  f.write(data.data(), static_cast<std::streamsize>(data.size()));
  f.close();
  if (!f) throw std::runtime_error("cannot write " + path);
}

// The python that draws the plots: the first of `requested`, $GGINS_PYTHON, /usr/bin/python3
// (Debian's python3-matplotlib, scripts/setup) and python3 that imports matplotlib; "" if none.
inline std::string find_python(const std::string& requested) {
  std::vector<std::string> cands;
  if (!requested.empty()) cands.push_back(requested);
  if (const char* e = std::getenv("GGINS_PYTHON")) cands.emplace_back(e);
  cands.emplace_back("/usr/bin/python3");
  cands.emplace_back("python3");
  for (const auto& c : cands)
    if (std::system(("'" + c + "' -c 'import matplotlib' >/dev/null 2>&1").c_str()) == 0) return c;
  return "";
}

// Parse the command line and run body with the exit-code scheme above: a parse or
// validation error prints CLI11's message (naming the option) and gives 2, --help 0;
// BadArgument from body gives 2, any other exception 1, each with the tool's name.
template <class Body>
int run(const char* tool, CLI::App& app, int argc, char** argv, Body&& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? kExitOk : kExitBadArgs;
  }
  try {
    return body();
  } catch (const BadArgument& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return kExitBadArgs;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return kExitBadArgs;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return kExitFailed;
  } catch (...) {
    std::fprintf(stderr, "%s: unknown error\n", tool);
    return kExitFailed;
  }
}

}  // namespace ggins::cli
