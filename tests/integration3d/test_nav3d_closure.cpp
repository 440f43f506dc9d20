// Direct-call closure test of the 3-D system: the 3-D truth
// generator (host_tools/lib/truth3d) feeds the firmware's gg_nav3d_step in
// process, no LCM; errors against the truth (run3d/compare3d.hpp). The bounds
// are the acceptance figures, given on the command line by CTest:
//   --max-pos-m X      final AND max position error over the run < X (m)
//   --max-gamma-E Y    max |Gamma_e(nav) - Gamma_e(true)| element after the
//                      first step < Y (Eotvos, 1 E = 1e-9 s^-2)
//   --max-att-rad Z    max attitude error < Z (rad)
// and the run: <scenario> [--duration S]. Prints the figures either way.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <unistd.h>

#include "compare3d.hpp"
#include "ggins/truth3d/config3d.hpp"

using namespace ggins;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <scenario> [--duration S] [--max-pos-m X] [--max-gamma-E Y] [--max-att-rad Z]\n", argv[0]);
    return 2;
  }
  double duration = -1, max_pos = -1, max_gam = -1, max_att = -1;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string o = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (o == "--duration") duration = v;
    else if (o == "--max-pos-m") max_pos = v;
    else if (o == "--max-gamma-E") max_gam = v;
    else if (o == "--max-att-rad") max_att = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", o.c_str());
      return 2;
    }
  }
  truth3d::Scenario3 sc = truth3d::load_scenario3(argv[1], {GGINS_SCENARIO_DIR});
  if (duration > 0) sc.duration_s = duration;
  if (sc.gravity.model == "egm96" && sc.sh.path.empty() &&
      access((std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt").c_str(), R_OK) != 0) {
    std::printf("SKIP: %s/egm96_to360.ascii.txt missing (scripts/fetch-egm96)\n", GGINS_DATA_DIR);
    return 77;
  }
  const truth3d::Generator3 gen(sc);
  gg_nav3d_config_t cfg;
  cfg = truth3d::config3d(sc, gen);
  static gg_nav3d_t nav;
  if (gg_nav3d_init(&nav, &cfg) != GG_OK) {
    std::printf("FAIL: gg_nav3d_init refused the configuration\n");
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int64_t n = gen.n_steps();
  double max_dr = 0, max_dv = 0, max_psi = 0, max_dg = 0, max_dgam = 0, max_dgam_b = 0, max_dh = 0;
  run3d::Errors3 last;
  uint32_t health_or = 0;
  int64_t rejected = 0;
  for (int64_t k = 0; k < n; ++k) {
    gg_frame_t f;
    truth3d::Truth3 t;
    gen.frame(k, f, &t);
    gg_nav3d_output_t out;
    const gg_status_t st = gg_nav3d_step(&nav, &f, nullptr, &out);
    if (st != GG_OK) ++rejected;
    health_or |= out.health;
    const run3d::Errors3 e = run3d::compare(t, out);
    last = e;
    max_dr = std::max(max_dr, static_cast<double>(e.dr));
    max_dv = std::max(max_dv, static_cast<double>(e.dv));
    max_psi = std::max(max_psi, static_cast<double>(e.psi));
    max_dg = std::max(max_dg, static_cast<double>(e.dg));
    max_dh = std::max(max_dh, static_cast<double>(std::fabs(e.dh)));
    if (k > 0) {  // the first output may carry no gradient yet
      max_dgam = std::max(max_dgam, static_cast<double>(e.dgamma_e));
      max_dgam_b = std::max(max_dgam_b, static_cast<double>(e.dgamma_b));
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("scenario %s (%s, %.0f s, %lld steps, wall %.1f s)\n", sc.name.c_str(), sc.platform.c_str(), sc.duration_s,
              static_cast<long long>(n), wall);
  std::printf("  position error  final %.3e m (N %.2e E %.2e D %.2e)  max %.3e m\n", static_cast<double>(last.dr),
              static_cast<double>(last.dr_n(0)), static_cast<double>(last.dr_n(1)), static_cast<double>(last.dr_n(2)),
              max_dr);
  std::printf("  velocity error  final %.3e m/s  max %.3e m/s\n", static_cast<double>(last.dv), max_dv);
  std::printf("  height error    final %.3e m  max %.3e m\n", static_cast<double>(last.dh), max_dh);
  std::printf("  attitude error  final %.3e rad  max %.3e rad\n", static_cast<double>(last.psi), max_psi);
  std::printf("  gravity error   final %.3e m/s^2  max %.3e m/s^2\n", static_cast<double>(last.dg), max_dg);
  std::printf("  Gamma error     final %.3e E  max %.3e E (ECEF); body axes max %.3e E\n",
              static_cast<double>(last.dgamma_e) * 1e9, max_dgam * 1e9, max_dgam_b * 1e9);
  std::printf("  steps rejected %lld, health bits seen 0x%08x\n", static_cast<long long>(rejected), health_or);
  int fail = 0;
  if (rejected) {
    std::printf("FAIL: %lld steps rejected\n", static_cast<long long>(rejected));
    ++fail;
  }
  if (max_pos > 0 && !(max_dr < max_pos)) {
    std::printf("FAIL: position error %.3e m not below %.3e m\n", max_dr, max_pos);
    ++fail;
  }
  if (max_gam > 0 && !(max_dgam * 1e9 < max_gam)) {
    std::printf("FAIL: Gamma error %.3e E not below %.3e E\n", max_dgam * 1e9, max_gam);
    ++fail;
  }
  if (max_att > 0 && !(max_psi < max_att)) {
    std::printf("FAIL: attitude error %.3e rad not below %.3e rad\n", max_psi, max_att);
    ++fail;
  }
  std::printf(fail ? "FAILED\n" : "PASSED\n");
  return fail ? 1 : 0;
}
