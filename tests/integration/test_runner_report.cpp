// The runner's evaluation and report pieces (host_tools/lib/hil) against
// independent truth: order statistics against a sorted copy of the sample,
// the running final/max, the 2-D error definition on hand-made values, the
// health word against frame.h's documented bit values (written here as
// numbers), the step accounting and exit status of the report head, and the
// scenario written as flown read back with an independent TOML parse.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <toml++/toml.h>
#include <vector>

#include <unistd.h>

#include "evaluation.hpp"
#include "frame_names.hpp"
#include "report.hpp"

namespace {
int fails = 0;
void check(bool ok, const std::string& what) {
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  if (!ok) ++fails;
}

struct Out2 {  // the fields errors2d reads
  double r_i[3], v_i[3], g_i[3], gamma_i[3][3];
};
}  // namespace

int main() {
  using namespace ggins::hil;
  {  // order statistics: rank round(q (n - 1)) of the sorted sample, values above the bins included
    std::mt19937 rng(7);
    std::uniform_int_distribution<uint32_t> small(0, 5000), big(1u << 17, 1u << 30);
    for (int n : {1, 2, 99, 1000, 12345}) {
      CycleStats cs;
      std::vector<uint32_t> v;
      for (int i = 0; i < n; ++i) {
        const uint32_t x = (i % 97 == 3) ? big(rng) : small(rng);
        v.push_back(x);
        cs.add(x);
      }
      std::sort(v.begin(), v.end());
      auto at = [&](double q) { return static_cast<double>(v[static_cast<size_t>(q * (n - 1) + 0.5)]); };
      const Percentiles p = cs.percentiles();
      check(p.median == at(0.5) && p.p99 == at(0.99) && p.max == at(1.0),
            "CycleStats n=" + std::to_string(n) + ": median/p99/max equal the sorted sample's");
    }
  }
  {  // running final / max
    MaxFinal m;
    m.add(-3.0);
    m.add(2.0);
    check(m.final == 2.0 && m.max == 3.0, "MaxFinal: final = last, max = largest magnitude");
    m.add(10.0, false);
    check(m.final == 2.0 && m.max == 10.0, "MaxFinal: an earlier step's sample moves max, not final");
    m.add(std::numeric_limits<double>::quiet_NaN());
    m.add(1.0);
    check(std::isnan(m.max), "MaxFinal: a NaN sample makes max NaN (never hidden)");
  }
  {  // 2-D errors: nav - truth; gradient error only over the x/z block
    using V = Eigen::Matrix<long double, 3, 1>;
    using M = Eigen::Matrix<long double, 3, 3>;
    const V r(1, 2, 3), v(4, 5, 6), g(7, 8, 9);
    M gam = M::Zero();
    Out2 o{{1.5, 2, 1}, {4, 5, 6.25}, {7, 8, 9}, {{1e-6, 5, -2e-6}, {5, 5, 5}, {3e-6, 5, 0}}};
    const auto e = errors2d(r, v, g, gam, o);
    check(e.dr(0) == 0.5L && e.dr(2) == -2.0L && e.dv(2) == 0.25L && e.dg.norm() == 0.0L,
          "errors2d: dr, dv, dg are nav - truth per axis");
    check(std::fabs(static_cast<double>(e.dgamma) - 3e-6) < 1e-18,
          "errors2d: gradient error = largest |element| of the x/z block (the y row and column ignored)");
  }
  {  // health word: frame.h's values written as numbers (ACC_FAULT 0x8000, ACC_REBUILT 0x10000, DEADLINE 0x200)
    const nlohmann::json h = health_word(0x00018200u);
    check(h["raw"] == 0x18200u && h["hex"] == "0x00018200", "health_word: raw and hex beside the bits");
    check(h["bits"] == nlohmann::json::array({"DEADLINE", "ACC_FAULT", "ACC_REBUILT"}),
          "health_word: bits named lowest first " + h["bits"].dump());
    check(health_bit_name(0x00000003u) == "0x00000003", "a value that is no single bit of frame.h is given as hex");
    check(health_csv(0x00000101u) == "NOT_INIT|FRAME_REJECTED" && health_csv(0).empty(), "health_csv: |-separated");
  }
  {  // report head: accounting and status
    FlightCounts c;
    c.steps_expected = 1001;
    c.steps_flown = 400;
    c.final_seq = 399;
    c.dt_s = 0.01;
    FlightEnd e{"interrupted", 130, false, {}};
    nlohmann::json s = report_head("ggins run", "2-D", "x", "src", "d", "lockstep", 100, 10, c, e);
    check(s["status"] == "interrupted" && s["interrupted"] == true && s["completed"] == false &&
              s["steps_unflown"] == 601 && s["frames_lost"] == 0 && std::fabs(s["flown_s"].get<double>() - 3.99) < 1e-12,
          "interrupted: 601 unflown, none lost, flown_s 3.99 s");
    check(exit_status(s) == 130, "interrupted: exit 130");
    e = FlightEnd{"hal_sim gave up on step 400", 1, false, {}};
    s = report_head("ggins run", "2-D", "x", "src", "d", "lockstep", 100, 10, c, e);
    check(s["status"] == "failed" && s["frames_lost"] == 601 && exit_status(s) == 1, "transport failure: lost, exit 1");
    e = FlightEnd{"no multicast", 3, false, {}};
    s = report_head("ggins run", "2-D", "x", "src", "d", "lockstep", 100, 10, c, e);
    check(exit_status(s) == 3 && s["frames_lost"] == 0, "no multicast: exit 3");
    c.steps_flown = 1001;
    c.final_seq = 1000;
    s = report_head("ggins run3d", "3-D", "x", "src", "d", "direct", 100, 10, c,
                    FlightEnd{"", 0, true, {"12 outputs later than the real-time deadline"}});
    check(s["status"] == "degraded" && s["completed"] == true && exit_status(s) == 4 &&
              s["degraded_reasons"] == nlohmann::json::array({"12 outputs later than the real-time deadline"}),
          "degraded: exit 4, the reason in degraded_reasons");
    s = report_head("ggins run3d", "3-D", "x", "src", "d", "direct", 100, 10, c, FlightEnd{});
    check(s["status"] == "completed" && s["steps_unflown"] == 0 && exit_status(s) == 0 &&
              s["degraded_reasons"] == nlohmann::json::array(),
          "completed: exit 0, no degraded reason");
  }
  {  // the scenario as flown, read back
    const auto p = std::filesystem::temp_directory_path() / ("ggins_eff_" + std::to_string(::getpid()) + ".toml");
    write_effective_scenario(p, "s", "src.toml", "name = \"s\"\n[time]\nduration_s = 3600\n# c\n[accel]\nbias_sigma_mps2 = 2e-12\n",
                             {{"time.duration_s", 20.0}, {"time.rate_hz", 100.0}, {"transport.seed", 7}});
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    const toml::table t = toml::parse(ss.str());
    check(ss.str().rfind("# scenario s from src.toml", 0) == 0, "scenario.toml starts with where it came from");
    check(t["time"]["duration_s"].value<double>() == 20.0 && t["time"]["rate_hz"].value<double>() == 100.0,
          "override applied, default filled in");
    check(t["accel"]["bias_sigma_mps2"].value<double>() == 2e-12 && t["transport"]["seed"].value<int64_t>() == 7 &&
              t["name"].value<std::string>() == "s",
          "the file's other keys kept, a new table made");
    std::filesystem::remove(p);
  }
  std::printf("%d failure(s)\n", fails);
  return fails ? 1 : 0;
}
