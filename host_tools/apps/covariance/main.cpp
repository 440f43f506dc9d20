// ggins-covariance: covariance analysis of the gradiometer-integrated INS error
// model of Welker, Pachter & Huffman (section V-VI, eqs. 7-11) along a
// scenario's trajectory. Outputs one-sigma position, velocity and gravity
// errors against time (CSV + PNG), the final values (--json), the eigenvalues
// of the reduced error dynamics along the flight and the unstable mode's share
// of the error. See docs/error-analysis.md.
#include <unistd.h>

#include <CLI/CLI.hpp>

#include "ggins/cli_checks.hpp"
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ggins/covariance/modes.hpp"
#include "ggins/covariance/propagate.hpp"
#include "ggins/covariance/scenario.hpp"
#include "ggins/covariance/welker2d.hpp"
#include "ggins/covariance/welker2d_baro.hpp"
#include "ggins/gravity/field.hpp"

#ifndef GGINS_COV_PLOT_SCRIPT
#define GGINS_COV_PLOT_SCRIPT ""
#endif
#ifndef GGINS_SOURCE_DIR
#define GGINS_SOURCE_DIR ""
#endif

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace ggins::covariance;

namespace {

struct Run {
  std::vector<Sample> samples;
  int n = 0;
};

std::shared_ptr<Welker2DModel> make_model(const CovScenario& s, Welker2DModel::GradientSource src) {
  auto field = std::make_shared<ggins::gravity::PointMassField>(s.gm_m3ps2);
  auto traj = std::make_shared<NorthGreatCircle2D>(s.speed_mps, s.height_m, s.lat0_rad, s.radius_m);
  auto m = std::make_shared<Welker2DModel>(field, traj, s.a_m, s.b_m, src);
  VectorXd psd(8);
  for (int i = 0; i < 8; ++i) psd(i) = s.noise_sigma_mps2[size_t(i)] * s.noise_sigma_mps2[size_t(i)] / s.rate_hz;
  m->set_white_noise_psd(psd);
  return m;
}

// P(0), Welker et al. eq. (11) with the initial errors of eq. (8):
// dx0 = (0 0 0 0 dGx(0) dGz(0)), biases ~ N(0, sigma_a^2 I).
MatrixXd initial_covariance(const CovScenario& s) {
  MatrixXd P0 = MatrixXd::Zero(14, 14);
  P0(0, 0) = P0(1, 1) = s.pos0_sigma_m * s.pos0_sigma_m;
  P0(2, 2) = P0(3, 3) = s.vel0_sigma_mps * s.vel0_sigma_mps;
  P0(4, 4) = s.gravity0_sigma_x_mps2 * s.gravity0_sigma_x_mps2;
  P0(5, 5) = s.gravity0_sigma_z_mps2 * s.gravity0_sigma_z_mps2;
  for (int i = 0; i < 8; ++i) P0(6 + i, 6 + i) = s.bias_sigma_mps2[size_t(i)] * s.bias_sigma_mps2[size_t(i)];
  return P0;
}

double max_rel_diff(const VectorXd& a, const VectorXd& b) {
  double m = 0;
  for (int i = 0; i < a.size(); ++i) {
    const double d = std::abs(a(i) - b(i)), s = std::max(std::abs(a(i)), std::abs(b(i)));
    if (s > 0) m = std::max(m, d / s);
  }
  return m;
}

json cjson(const cd& z) { return json::array({z.real(), z.imag()}); }

}  // namespace

int main(int argc, char** argv) {
  namespace C = ggins::cli;
  CLI::App app{
      "ggins covariance: covariance propagation of the gradiometer-integrated INS error model\n"
      "(Welker, Pachter & Huffman, eqs. 7-11: 6 navigation error states + 8 constant accelerometer\n"
      "biases, P' = Fa P + P Fa^T) along a scenario trajectory, with F(t), Gamma(t) from the\n"
      "gravity field evaluated on the trajectory. Writes covariance.csv, covariance.json and\n"
      "covariance.png to --out; --json prints the JSON summary on stdout.",
      "ggins-covariance"};
  std::string scen_arg = "welker-table1";
  std::string out_dir;
  bool want_json = false, want_eigen = false, no_plot = false, builtin_only = false;
  double dt = 1.0, output_dt = 10.0;
  std::string method_s = "transition", gradient_s = "centre", python;
  std::optional<double> g_override, sigma_g0, duration;
  app.add_option("-s,--scenario", scen_arg,
                 "scenario: a TOML file, a name in scenarios/<name>.toml, or built in (" +
                     builtin_names().front() + ")")
      ->capture_default_str();
  app.add_flag("--builtin", builtin_only, "use the built-in definition even if scenarios/<name>.toml exists");
  app.add_option("-o,--out", out_dir, "output directory (default out/covariance/<scenario>)")->check(C::OutputDir());
  app.add_flag("--json", want_json, "print the JSON summary (values at the end of the run) on stdout");
  app.add_flag("--eigen", want_eigen, "print the eigenvalues of the reduced error dynamics along the flight");
  app.add_option("--dt", dt, "integration step, s (RK4)")->capture_default_str()->check(C::FiniteRange(0, 1e5, C::kOpenLow));
  app.add_option("--output-dt", output_dt, "CSV sample spacing, s")->capture_default_str()->check(C::FiniteRange(0, 1e9, C::kOpenLow));
  app.add_option("--method", method_s, "transition: RK4 on Phi, P = Phi P0 Phi^T; lyapunov: RK4 on P")
      ->capture_default_str()
      ->check(CLI::IsMember({"transition", "lyapunov"}));
  app.add_option("--gradient", gradient_s,
                 "gradient block of F: centre (field gradient at the platform centre, the paper) or "
                 "baseline (differenced field over the accelerometer baseline)")
      ->capture_default_str()
      ->check(CLI::IsMember({"centre", "baseline"}));
  app.add_option("--g", g_override,
                 "use omega_s^2 = g/R_e with this g (m/s^2) instead of g = GM/R_e^2 (sets GM = g R_e^2)")->check(C::FiniteRange(0, 1e3, C::kOpenLow));
  app.add_option("--sigma-g0", sigma_g0, "initial gravity uncertainty dG(0), one sigma, m/s^2 (eq. 8)")->check(C::FiniteRange(0, 1e3));
  app.add_option("--duration", duration, "override the scenario duration, s")->check(C::FiniteRange(0, 1e9, C::kOpenLow));
  app.add_flag("--no-plot", no_plot, "do not run the matplotlib plot script");
  app.add_option("--python", python, "python interpreter with matplotlib (default: $GGINS_PYTHON, /usr/bin/python3)");
  bool print_scenario = false, print_defaults = false;
  app.add_flag("--print-scenario", print_scenario,
               "print the scenario as it would fly (every key: defaults filled in, overrides applied) and exit");
  app.add_flag("--defaults", print_defaults,
               "with --print-scenario: a complete template instead (every key at its default, commented\n"
               "with unit, allowed range and meaning; docs/scenario-reference.md)");
  return C::run("ggins-covariance", app, argc, argv, [&]() -> int {
  if (duration && *duration / dt > 1e8)
    throw C::BadArgument("--duration " + std::to_string(*duration) + " s with --dt " + std::to_string(dt) +
                         " s is more than 1e8 steps (allowed: duration / dt <= 1e8)");

  if (print_defaults && !print_scenario) throw C::BadArgument("--defaults: allowed only with --print-scenario");
  if (print_scenario && print_defaults) {
    std::fputs(cov_scenario_to_toml(CovScenario{}, true).c_str(), stdout);
    return C::kExitOk;
  }
  CovScenario sc;
  try {
    if (builtin_only) {
      auto b = builtin_scenario(scen_arg);
      if (!b) throw std::runtime_error("no built-in scenario '" + scen_arg + "'");
      sc = *b;
    } else {
      sc = resolve_scenario(scen_arg, GGINS_SOURCE_DIR);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-covariance: %s\n", e.what());
    return 2;
  }
  if (g_override) sc.gm_m3ps2 = *g_override * sc.radius_m * sc.radius_m;
  if (sigma_g0) sc.gravity0_sigma_x_mps2 = sc.gravity0_sigma_z_mps2 = *sigma_g0;
  if (duration) sc.duration_s = *duration;
  if (print_scenario) {
    std::fputs(cov_scenario_to_toml(sc).c_str(), stdout);
    return C::kExitOk;
  }
  if (dt > sc.duration_s)
    throw C::BadArgument("--dt " + std::to_string(dt) + " s is longer than the duration " + std::to_string(sc.duration_s) +
                         " s (allowed: --dt <= duration)");
  if (sc.duration_s / dt > 1e8)
    throw C::BadArgument("duration " + std::to_string(sc.duration_s) + " s with --dt " + std::to_string(dt) +
                         " s is more than 1e8 steps (allowed: duration / dt <= 1e8)");
  const auto src = gradient_s == "baseline" ? Welker2DModel::GradientSource::kBaseline
                                            : Welker2DModel::GradientSource::kCentre;
  Method method = method_s == "lyapunov" ? Method::kLyapunov : Method::kTransition;
  if (out_dir.empty()) out_dir = "out/covariance/" + sc.name;

  const auto base = make_model(sc, src);
  std::shared_ptr<const LinearErrorModel> model = base;
  MatrixXd P0 = initial_covariance(sc);
  std::shared_ptr<const Welker2DBaroModel> baro;
  if (sc.baro_loop) {  // the barometric vertical loop (welker2d_baro.hpp)
    BaroLoopParams bp;
    for (int i = 0; i < 3; ++i) bp.poles_radps[size_t(i)] = sc.baro_poles_radps[size_t(i)];
    const double r0 = base->trajectory().at(0).r.norm();
    bp.omega_s2 = sc.baro_omega_s2 > 0 ? sc.baro_omega_s2 : sc.gm_m3ps2 / (r0 * r0 * r0);
    bp.gm_tau_s = sc.baro_gm_tau_s;
    bp.gm_sigma_m = sc.baro_gm_sigma_m;
    bp.noise_sigma_m = sc.baro_noise_sigma_m;
    bp.period_s = sc.baro_period_s;
    baro = std::make_shared<Welker2DBaroModel>(base, bp);
    model = baro;
    MatrixXd Pb = MatrixXd::Zero(17, 17);  // (6 states, a_c, 8 biases, baro bias, baro GM)
    Pb.topLeftCorner(6, 6) = P0.topLeftCorner(6, 6);
    Pb.block(7, 7, 8, 8) = P0.block(6, 6, 8, 8);
    Pb(7 + Welker2DBaroModel::kBaroBias, 7 + Welker2DBaroModel::kBaroBias) = sc.baro_bias_m * sc.baro_bias_m;
    Pb(7 + Welker2DBaroModel::kBaroGm, 7 + Welker2DBaroModel::kBaroGm) = sc.baro_gm_sigma_m * sc.baro_gm_sigma_m;
    P0 = Pb;
  }
  const int n = model->n_states();
  const auto keys = model->state_keys();
  if (model->has_process_noise() && method == Method::kTransition) {
    std::fprintf(stderr, "ggins-covariance: process noise in the model (white accelerometer or barometer noise): using --method lyapunov\n");
    method = Method::kLyapunov;
    method_s = "lyapunov";
  }
  std::vector<std::string> unmodelled = sc.unmodelled;
  if (sc.scale_sigma != 0) unmodelled.emplace_back("accel.scale_sigma (scale-factor errors are not in the linear model)");
  for (const auto& u : unmodelled) std::fprintf(stderr, "ggins-covariance: NOTE not modelled: %s\n", u.c_str());

  PropagationOptions opt;
  opt.t_end = sc.duration_s;
  opt.dt = dt;
  opt.output_dt = output_dt;
  opt.method = method;
  std::vector<Sample> run, run_half, run_other;
  try {
    run = propagate(*model, P0, opt);
    // Accuracy evidence: the same run with half the step, and with the other method.
    PropagationOptions half = opt;
    half.dt = dt / 2;
    run_half = propagate(*model, P0, half);
    if (!model->has_process_noise()) {
      PropagationOptions other = opt;
      other.method = method == Method::kTransition ? Method::kLyapunov : Method::kTransition;
      run_other = propagate(*model, P0, other);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-covariance: %s\n", e.what());
    return 1;
  }
  const Sample& fin = run.back();
  const VectorXd sig = sigmas(fin.P, n);
  const double rel_half = max_rel_diff(sig, sigmas(run_half.back().P, n));
  const double rel_other = run_other.empty() ? NAN : max_rel_diff(sig, sigmas(run_other.back().P, n));

  // Eigenstructure of the reduced F (no bias states) along the flight, against
  // Welker et al. section VI: +-sqrt(2) w_s, +-j w_s (and the double zero of
  // the position rows), w_s^2 = g/R = GM/r^3 at the trajectory point.
  MatrixXd F, Gam;
  double eig_max_dev = 0;  // max |lambda - closed form| / w_s over the flight
  json eig_samples = json::array();
  struct ModeRow {
    double lambda_u, ws;
    VectorXd sig_u;
  };
  std::vector<ModeRow> modes;
  modes.reserve(run.size());
  for (size_t k = 0; k < run.size(); ++k) {
    const double t = run[k].t;
    base->matrices(t, F, Gam);  // the open-loop F of Welker et al. (also with the baro loop)
    const double r = base->trajectory().at(t).r.norm();
    const double ws = std::sqrt(sc.gm_m3ps2 / (r * r * r));
    const std::vector<cd> ev = sorted_eigenvalues(F);
    const std::vector<cd> expect = {cd(std::sqrt(2.0) * ws, 0), cd(0, ws), cd(0, 0),
                                    cd(0, 0),  cd(0, -ws), cd(-std::sqrt(2.0) * ws, 0)};
    // sorted_eigenvalues orders by real part then imaginary part: +sqrt2 w, +jw, 0, 0, -jw, -sqrt2 w
    // (the imaginary pair and the zeros share real part 0 up to round-off, so match greedily).
    std::vector<bool> used(6, false);
    for (const cd& e : expect) {
      int best = -1;
      for (int i = 0; i < 6; ++i)
        if (!used[size_t(i)] && (best < 0 || std::abs(ev[size_t(i)] - e) < std::abs(ev[size_t(best)] - e))) best = i;
      used[size_t(best)] = true;
      eig_max_dev = std::max(eig_max_dev, std::abs(ev[size_t(best)] - e) / ws);
    }
    double lu = 0;
    const MatrixXd Pi = unstable_projector(F, &lu);
    const MatrixXd Pn = run[k].P.topLeftCorner(6, 6);
    const MatrixXd Pu = Pi * Pn * Pi.transpose();
    VectorXd su = VectorXd::Zero(n);
    su.head(6) = sigmas(Pu, 6);
    modes.push_back({lu, ws, su});
    // JSON/--eigen samples: start, every 600 s, end.
    const bool mark = k == 0 || k + 1 == run.size() || std::fmod(t + 1e-6, 600.0) < 2e-6;
    if (mark) {
      json e = json::array();
      for (const cd& z : ev) e.push_back(cjson(z));
      eig_samples.push_back({{"t_s", t}, {"omega_s_radps", ws}, {"eigenvalues", e}});
    }
  }
  const double ws0 = modes.front().ws;

  // Unstable mode's share of the error and its growth rate near the end.
  const ModeRow& mend = modes.back();
  size_t k_prev = 0;
  for (size_t k = 0; k < run.size(); ++k)
    if (run[k].t <= fin.t - 600.0 + 1e-9) k_prev = k;
  const double dtg = fin.t - run[k_prev].t;
  const double growth_x = dtg > 0 ? std::log(sig(0) / sigmas(run[k_prev].P, n)(0)) / dtg : 0;
  const double growth_xu = dtg > 0 ? std::log(mend.sig_u(0) / modes[k_prev].sig_u(0)) / dtg : 0;

  // Outputs.
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  const fs::path csv = fs::path(out_dir) / "covariance.csv";
  {
    std::ofstream f(csv);
    if (!f) {
      std::fprintf(stderr, "ggins-covariance: cannot write %s\n", csv.c_str());
      return 1;
    }
    f << "t_s";
    for (const auto& k : keys) f << ',' << k;
    for (const auto& k : keys) f << ",unstable_" << k;
    f << ",lambda_u_ps,omega_s_radps\n";
    f.precision(10);
    for (size_t k = 0; k < run.size(); ++k) {
      const VectorXd s = sigmas(run[k].P, n);
      f << run[k].t;
      for (int i = 0; i < n; ++i) f << ',' << s(i);
      for (int i = 0; i < n; ++i) f << ',' << modes[k].sig_u(i);
      f << ',' << modes[k].lambda_u << ',' << modes[k].ws << '\n';
    }
  }

  json j;
  j["scenario"] = sc.name;
  j["t_s"] = fin.t;
  for (int i = 0; i < n; ++i) j[keys[size_t(i)]] = sig(i);
  j["parameters"] = {{"source", sc.source},
                     {"duration_s", sc.duration_s},
                     {"radius_m", sc.radius_m},
                     {"gm_m3ps2", sc.gm_m3ps2},
                     {"g_mps2", sc.gm_m3ps2 / (sc.radius_m * sc.radius_m)},
                     {"speed_mps", sc.speed_mps},
                     {"height_m", sc.height_m},
                     {"lat0_rad", sc.lat0_rad},
                     {"half_baseline_a_m", sc.a_m},
                     {"half_baseline_b_m", sc.b_m},
                     {"bias_sigma_mps2", sc.bias_sigma_mps2},
                     {"gravity0_sigma_mps2", {sc.gravity0_sigma_x_mps2, sc.gravity0_sigma_z_mps2}},
                     {"position0_sigma_m", sc.pos0_sigma_m},
                     {"velocity0_sigma_mps", sc.vel0_sigma_mps},
                     {"noise_sigma_mps2", sc.noise_sigma_mps2},
                     {"rate_hz", sc.rate_hz},
                     {"gradient", gradient_s},
                     {"defaulted", sc.defaulted},
                     {"unmodelled", unmodelled}};
  j["integration"] = {{"method", method_s},
                      {"dt_s", dt},
                      {"max_rel_diff_half_step", rel_half},
                      {"max_rel_diff_other_method", run_other.empty() ? json(nullptr) : json(rel_other)}};
  j["eigen"] = {{"omega_s_radps", ws0},
                {"closed_form", {"+sqrt2*omega_s", "+j*omega_s", "0", "0", "-j*omega_s", "-sqrt2*omega_s"}},
                {"max_abs_dev_over_flight_per_omega_s", eig_max_dev},
                {"samples", eig_samples}};
  if (baro) {  // vertical (along the true up) and along-track sigma from P_rr
    auto proj = [&](const Sample& smp) {
      const Eigen::Vector2d u = baro->up(smp.t);
      const TrajectoryPoint tp = base->trajectory().at(smp.t);
      const Eigen::Vector2d al = Eigen::Vector2d(tp.v(0), tp.v(2)).normalized();
      const Eigen::Matrix2d Pr = smp.P.topLeftCorner(2, 2);
      return std::make_pair(std::sqrt(u.dot(Pr * u)), std::sqrt(al.dot(Pr * al)));
    };
    json hv = json::object(), ha = json::object();
    for (const auto& smp : run)
      if (smp.t > 0 && std::fmod(smp.t + 1e-6, 3600.0) < 2e-6) {
        hv[std::to_string(int(smp.t / 3600 + 0.5)) + "h"] = proj(smp).first;
        ha[std::to_string(int(smp.t / 3600 + 0.5)) + "h"] = proj(smp).second;
      }
    j["baro_loop"] = {{"poles_radps", sc.baro_poles_radps},
                      {"k1", baro->k1()}, {"k2", baro->k2()}, {"k3", baro->k3()},
                      {"bias_sigma_m", sc.baro_bias_m}, {"gm_sigma_m", sc.baro_gm_sigma_m},
                      {"gm_tau_s", sc.baro_gm_tau_s}, {"noise_sigma_m", sc.baro_noise_sigma_m},
                      {"period_s", sc.baro_period_s},
                      {"sigma_vertical_m", proj(fin).first}, {"sigma_along_track_m", proj(fin).second},
                      {"sigma_vertical_at_hours_m", hv}, {"sigma_along_track_at_hours_m", ha},
                      {"note", "eigen and unstable_mode describe the open-loop F of Welker et al. (6 states); the "
                               "covariance includes the loop"}};
  }
  j["unstable_mode"] = {
      {"lambda_ps", mend.lambda_u},
      {"sqrt2_omega_s_ps", std::sqrt(2.0) * mend.ws},
      {"sigma_unstable_part", [&] {
         json u;
         for (int i = 0; i < n; ++i) u[keys[size_t(i)]] = mend.sig_u(i);
         return u;
       }()},
      {"growth_rate_last_600s_x_ps", growth_x},
      {"growth_rate_last_600s_x_unstable_ps", growth_xu}};
  if (sc.name == "welker-table1") {
    // Welker et al., Table I (one sigma after one hour).
    const double ref[6] = {41.41, 5.08, 7.37e-2, 0.98e-2, 0.1291e-3, 0.0208e-3};
    json t;
    for (int i = 0; i < 6; ++i)
      t[keys[size_t(i)]] = {{"paper", ref[i]}, {"ggins", sig(i)}, {"dev_pct", 100.0 * (sig(i) / ref[i] - 1.0)}};
    j["table1"] = t;
  }
  const fs::path jpath = fs::path(out_dir) / "covariance.json";
  C::write_file(jpath, j.dump(2) + '\n');

  std::string plot_msg;
  if (!no_plot) {
    const std::string py = C::find_python(python);
    const fs::path png = fs::path(out_dir) / "covariance.png";
    if (py.empty()) {
      plot_msg = "no python with matplotlib found (try --python /usr/bin/python3); no plot";
    } else {
      std::ostringstream cmd;
      cmd << "'" << py << "' '" << GGINS_COV_PLOT_SCRIPT << "' '" << csv.string() << "' '" << png.string()
          << "' --title '" << sc.name << "' 1>&2";
      if (std::system(cmd.str().c_str()) != 0)
        plot_msg = "plot script failed: " + cmd.str();
      else
        plot_msg = "plot: " + png.string();
    }
  }

  if (want_json) {
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("scenario %s (%s), t = %.1f s, %s RK4, dt = %g s\n", sc.name.c_str(), sc.source.c_str(), fin.t,
                method_s.c_str(), dt);
    for (int i = 0; i < n; ++i) std::printf("  sigma %-8s %.6g\n", keys[size_t(i)].c_str(), sig(i));
    std::printf("step halving: max relative change %.3g; other method: %.3g\n", rel_half, rel_other);
    std::printf("omega_s = %.9g rad/s; eigenvalues of F vs closed form: max |dev|/omega_s = %.3g\n", ws0,
                eig_max_dev);
    std::printf("unstable mode: lambda = %.9g /s (sqrt2 w_s = %.9g); share of sigma_x at end: %.4f\n",
                mend.lambda_u, std::sqrt(2.0) * mend.ws, mend.sig_u(0) / sig(0));
    if (baro)
      std::printf("barometric loop: sigma vertical %.6g m, along-track %.6g m at the end\n",
                  j["baro_loop"]["sigma_vertical_m"].get<double>(), j["baro_loop"]["sigma_along_track_m"].get<double>());
    std::printf("wrote %s, %s\n", csv.c_str(), jpath.c_str());
  }
  if (want_eigen) {
    std::fprintf(want_json ? stderr : stdout, "eigenvalues of the reduced F (Welker et al. sec. VI):\n");
    for (const auto& e : eig_samples) {
      std::fprintf(want_json ? stderr : stdout, "  t = %7.1f s  w_s = %.9g:", e["t_s"].get<double>(),
                   e["omega_s_radps"].get<double>());
      for (const auto& z : e["eigenvalues"])
        std::fprintf(want_json ? stderr : stdout, " (%+.6e %+.6ej)", z[0].get<double>(), z[1].get<double>());
      std::fprintf(want_json ? stderr : stdout, "\n");
    }
  }
  if (!plot_msg.empty()) std::fprintf(stderr, "ggins-covariance: %s\n", plot_msg.c_str());
  return 0;
  });
}
