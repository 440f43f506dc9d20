// ggins-covariance3d: covariance analysis of the 3-D gradiometer-integrated
// INS on a rotating Earth (model: nav3d_model.hpp), along an
// analytic great-circle flight, for the space-stabilized and the strapdown
// platform, with the eigenvalues of the 3-D error dynamics along the flight.
// See docs/error-analysis.md, section "3-D".
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

#include "ggins/covariance/cov3d.hpp"
#include "ggins/covariance/modes.hpp"
#include "ggins/covariance/propagate.hpp"
#ifdef GGINS_HAVE_TRUTH3D
#include "ggins/covariance/cov3d_truth3d.hpp"
#endif

#ifndef GGINS_COV3D_PLOT_SCRIPT
#define GGINS_COV3D_PLOT_SCRIPT ""
#endif

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace ggins::covariance;
using cdv = std::complex<double>;

namespace {

json cj(const cdv& z) { return json::array({z.real(), z.imag()}); }

// Predicted non-zero eigenvalues of the nav block (first order in omega_ie / omega_s):
// +-sqrt(Gamma_up), +-j(omega_s + omega_ie sin L), +-j(omega_s - omega_ie sin L).
std::vector<cdv> predicted(const Eigen3D& e) {
  const double v = std::sqrt(e.gamma_up), a = e.omega_s + e.foucault, b = e.omega_s - e.foucault;
  return {cdv(v, 0), cdv(-v, 0), cdv(0, a), cdv(0, -a), cdv(0, b), cdv(0, -b)};
}

// Max |computed - predicted| / omega_s over the six predicted values (greedy matching).
double match_dev(const std::vector<cdv>& ev, const std::vector<cdv>& pred, double ws) {
  std::vector<bool> used(ev.size(), false);
  double dev = 0;
  for (const cdv& p : pred) {
    int best = -1;
    for (size_t i = 0; i < ev.size(); ++i)
      if (!used[i] && (best < 0 || std::abs(ev[i] - p) < std::abs(ev[size_t(best)] - p))) best = int(i);
    if (best < 0) return INFINITY;
    used[size_t(best)] = true;
    dev = std::max(dev, std::abs(ev[size_t(best)] - p) / ws);
  }
  return dev;
}

}  // namespace

int main(int argc, char** argv) {
  namespace C = ggins::cli;
  CLI::App app{
      "ggins covariance3d: covariance propagation of the linear error model of the 3-D\n"
      "gradiometer-integrated INS on a rotating Earth (ECI mechanization, gravity dead reckoning\n"
      "in ECEF, 18 single-axis accelerometers, gyros on the strapdown platform, optional baro loop)\n"
      "along an analytic great-circle flight or a 3-D truth-generator scenario; eigenvalues of the 3-D\n"
      "error dynamics along the flight.\n"
      "Writes covariance3d.csv/.json/.png to --out; --json prints the JSON. docs/error-analysis.md.",
      "ggins-covariance3d"};
  std::string scen = "gc3d-stabilized", out_dir, method_s = "transition", python, platform_s, field_s;
  bool want_json = false, want_eigen = false, no_plot = false;
  double dt = 1.0, output_dt = 10.0;
  std::optional<double> omega_ie, lat0, lon0, heading, speed, height, duration, acc_bias, gyro_bias, acc_noise,
      gyro_noise, rate, g0, psi0;
  std::vector<double> half_base;
  std::optional<bool> baro;
  std::optional<double> baro_bias;
  app.add_option("-s,--scenario", scen,
                 "built-in great-circle scenario (gc3d-stabilized, gc3d-strapdown, gc3d-nonrotating, gc3d-baro), "
                 "a great-circle file (a [great_circle] table: ggins montecarlo3d --print-scenario), "
                 "or a 3-D truth-generator scenario (scenarios/3d-*.toml name or a TOML file path)")
      ->capture_default_str();
  app.add_option("--platform", platform_s, "stabilized | strapdown (overrides the scenario)")
      ->check(CLI::IsMember({"stabilized", "strapdown"}));
  app.add_option("--field", field_s, "normal (WGS-84 normal gravitation) | point-mass")
      ->check(CLI::IsMember({"normal", "point-mass"}));
  app.add_option("--omega-ie", omega_ie, "Earth rate, rad/s (0: non-rotating)")->check(C::FiniteRange(0, 1e-3));
  app.add_option("--lat0-deg", lat0, "start geocentric latitude, deg")->check(C::FiniteRange(-90, 90));
  app.add_option("--lon0-deg", lon0, "start longitude, deg")->check(C::FiniteRange(-360, 360));
  app.add_option("--heading-deg", heading, "initial heading from north, deg")->check(C::FiniteRange(-360, 360));
  app.add_option("--speed", speed, "ground speed, m/s (0: at rest)")->check(C::FiniteRange(0, 1e4));
  app.add_option("--height", height, "height above the 6378137 m sphere, m")->check(C::FiniteRange(-1e4, 1e6));
  app.add_option("--duration", duration, "s")->check(C::FiniteRange(0, 1e9, C::kOpenLow));
  app.add_option("--half-base", half_base, "a b c, m")->expected(3)->check(C::FiniteRange(0, 100, C::kOpenLow));
  app.add_option("--acc-bias-sigma", acc_bias, "constant bias of each of the 18 readings, 1 sigma, m/s^2")->check(C::FiniteRange(0, 1e3));
  app.add_option("--gyro-bias-sigma", gyro_bias, "constant gyro bias per axis, 1 sigma, rad/s (strapdown)")->check(C::FiniteRange(0, 10));
  app.add_option("--acc-noise-sigma", acc_noise, "white noise per reading per sample, m/s^2")->check(C::FiniteRange(0, 1e3));
  app.add_option("--gyro-noise-sigma", gyro_noise, "white gyro noise per axis per sample, rad/s")->check(C::FiniteRange(0, 10));
  app.add_option("--rate-hz", rate, "sample rate for the noise densities, Hz")->check(C::FiniteRange(0, 1e6, C::kOpenLow));
  app.add_option("--g0-sigma", g0, "initial gravity error per ECEF axis, 1 sigma, m/s^2")->check(C::FiniteRange(0, 1e3));
  app.add_option("--psi0-sigma", psi0, "initial attitude error per axis, 1 sigma, rad (strapdown)")->check(C::FiniteRange(0, 1));
  app.add_option("--baro", baro, "barometric vertical loop on/off (true/false)");
  app.add_option("--baro-bias-sigma", baro_bias, "constant barometer bias, 1 sigma, m")->check(C::FiniteRange(0, 1e5));
  app.add_option("--dt", dt, "RK4 step, s")->capture_default_str()->check(C::FiniteRange(0, 1e5, C::kOpenLow));
  app.add_option("--output-dt", output_dt, "CSV spacing, s")->capture_default_str()->check(C::FiniteRange(0, 1e9, C::kOpenLow));
  app.add_option("--method", method_s, "transition | lyapunov")->capture_default_str()
      ->check(CLI::IsMember({"transition", "lyapunov"}));
  app.add_option("-o,--out", out_dir, "output directory (default out/covariance3d/<scenario>)")->check(C::OutputDir());
  app.add_flag("--json", want_json, "print the JSON summary on stdout");
  app.add_flag("--eigen", want_eigen, "print the eigenvalues along the flight");
  app.add_flag("--no-plot", no_plot, "no matplotlib plot");
  app.add_option("--python", python, "python with matplotlib");
  return C::run("ggins-covariance3d", app, argc, argv, [&]() -> int {
  if (duration && *duration / dt > 1e8)
    throw C::BadArgument("--duration " + std::to_string(*duration) + " s with --dt " + std::to_string(dt) +
                         " s is more than 1e8 steps (allowed: duration / dt <= 1e8)");

  std::optional<Cov3DScenario> b;
  std::vector<std::string> unmodelled;
#ifdef GGINS_HAVE_TRUTH3D
  try {  // a gc3d-* built-in, a great-circle file, or a truth3d scenario
    auto in = resolve_scenario3d(scen, {"scenarios", std::string(GGINS_SOURCE_DIR) + "/scenarios"});
    b = in.cov;
    unmodelled = in.unmodelled;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-covariance3d: %s\n", e.what());
    return 2;
  }
#else
  b = builtin_scenario3d(scen);
#endif
  if (!b) {
    std::fprintf(stderr, "ggins-covariance3d: unknown scenario '%s'\n", scen.c_str());
    return 2;
  }
  Cov3DScenario s = *b;
  for (const auto& u : unmodelled) std::fprintf(stderr, "ggins-covariance3d: NOTE not modelled: %s\n", u.c_str());
  if (!platform_s.empty()) s.platform = platform_s == "strapdown" ? Platform::kStrapdown : Platform::kStabilized;
  if (!field_s.empty()) s.field = field_s;
  if (omega_ie) s.omega_ie = *omega_ie;
  if (lat0) s.lat0_deg = *lat0;
  if (lon0) s.lon0_deg = *lon0;
  if (heading) s.heading_deg = *heading;
  if (speed) s.speed_mps = *speed;
  if (height) s.height_m = *height;
  if (duration) s.duration_s = *duration;
  if (dt > s.duration_s)
    throw C::BadArgument("--dt " + std::to_string(dt) + " s is longer than the duration " + std::to_string(s.duration_s) +
                         " s (allowed: --dt <= duration)");
  if (s.duration_s / dt > 1e8)
    throw C::BadArgument("duration " + std::to_string(s.duration_s) + " s with --dt " + std::to_string(dt) +
                         " s is more than 1e8 steps (allowed: duration / dt <= 1e8)");
  if (!half_base.empty()) for (int i = 0; i < 3; ++i) s.model.half_base_m[size_t(i)] = half_base[size_t(i)];
  if (acc_bias) s.acc_bias_sigma_mps2 = *acc_bias;
  if (gyro_bias) s.gyro_bias_sigma_radps = *gyro_bias;
  if (acc_noise) s.model.acc_noise_sigma_mps2 = *acc_noise;
  if (gyro_noise) s.model.gyro_noise_sigma_radps = *gyro_noise;
  if (rate) s.model.rate_hz = *rate;
  if (g0) s.g0_sigma_mps2 = *g0;
  if (psi0) s.psi0_sigma_rad = *psi0;
  if (baro) s.model.baro.on = *baro;
  if (baro_bias) s.baro_bias_sigma_m = *baro_bias;
  if (out_dir.empty()) out_dir = "out/covariance3d/" + s.name;

  std::shared_ptr<const Nav3DModel> model;
  try {
    model = make_model3d(s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-covariance3d: %s\n", e.what());
    return 2;
  }
  Method method = method_s == "lyapunov" ? Method::kLyapunov : Method::kTransition;
  if (model->has_process_noise() && method == Method::kTransition) {
    method = Method::kLyapunov;
    method_s = "lyapunov";
    std::fprintf(stderr, "ggins-covariance3d: process noise in the model: using --method lyapunov\n");
  }
  const MatrixXd P0 = initial_covariance3d(s, *model);
  PropagationOptions opt;
  opt.t_end = s.duration_s;
  opt.dt = dt;
  opt.output_dt = output_dt;
  opt.method = method;
  std::vector<Sample> run, half, other;
  try {
    run = propagate(*model, P0, opt);
    PropagationOptions h = opt;
    h.dt = dt / 2;
    half = propagate(*model, P0, h);
    if (!model->has_process_noise()) {
      PropagationOptions o = opt;
      o.method = method == Method::kTransition ? Method::kLyapunov : Method::kTransition;
      other = propagate(*model, P0, o);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-covariance3d: %s\n", e.what());
    return 1;
  }
  const int n = model->n_states();
  auto maxrel = [n](const MatrixXd& A, const MatrixXd& B) {
    double m = 0;
    for (int i = 0; i < n; ++i) {
      const double a = std::sqrt(std::max(0.0, A(i, i))), c = std::sqrt(std::max(0.0, B(i, i)));
      if (std::max(a, c) > 0) m = std::max(m, std::abs(a - c) / std::max(a, c));
    }
    return m;
  };
  const double rel_half = maxrel(run.back().P, half.back().P);
  const double rel_other = other.empty() ? NAN : maxrel(run.back().P, other.back().P);

  const bool sd = model->strapdown();
  const char* blk[4] = {"r", "v", "g", "psi"};
  const char* unit[4] = {"m", "mps", "mps2", "rad"};
  const char* ned[3] = {"n", "e", "d"};
  const int nblk = sd ? 4 : 3;
  auto ned_all = [&](const Sample& smp) {
    const Eigen::Matrix3d Cne = model->ned_to_ecef(smp.t);
    std::vector<double> v;
    for (int bk = 0; bk < nblk; ++bk) {
      const Eigen::Vector3d sg = ned_sigma(smp.P, 3 * bk, Cne);
      for (int i = 0; i < 3; ++i) v.push_back(sg(i));
    }
    return v;
  };
  std::vector<std::string> cols;
  for (int bk = 0; bk < nblk; ++bk)
    for (int i = 0; i < 3; ++i) cols.push_back(std::string(blk[bk]) + ned[i] + "_" + unit[bk]);

  // Eigen analysis along the flight.
  double max_dev_pred = 0, max_charpoly = 0;
  json eig = json::array();
  std::vector<double> lam_u(run.size(), NAN);
  for (size_t k = 0; k < run.size(); ++k) {
    const Eigen3D e = eigen3d(*model, run[k].t);
    if (!model->baro()) {
      max_dev_pred = std::max(max_dev_pred, match_dev(e.nav_ev, predicted(e), e.omega_s));
      max_charpoly = std::max(max_charpoly, e.max_charpoly_residual);
    }
    MatrixXd F, Gm;
    model->matrices(run[k].t, F, Gm);
    try {
      double lu = 0;
      unstable_projector(F, &lu);
      lam_u[k] = lu;
    } catch (const std::exception&) {
    }
    const bool mark = k == 0 || k + 1 == run.size() || std::fmod(run[k].t + 1e-6, 600.0) < 2e-6;
    if (mark) {
      json ev = json::array(), nev = json::array(), pr = json::array();
      for (const auto& z : e.ev) ev.push_back(cj(z));
      for (const auto& z : e.nav_ev) nev.push_back(cj(z));
      for (const auto& z : predicted(e)) pr.push_back(cj(z));
      eig.push_back({{"t_s", run[k].t}, {"lat_gc_deg", e.lat_gc * 180 / M_PI}, {"omega_s_radps", e.omega_s},
                     {"gamma_up_ps2", e.gamma_up}, {"omega_ie_sinL_radps", e.foucault}, {"eigenvalues", ev},
                     {"nav_block_eigenvalues", nev}, {"predicted_first_order", pr},
                     {"charpoly_residual", model->baro() ? json(nullptr) : json(e.max_charpoly_residual)}});
    }
  }

  std::error_code ec;
  fs::create_directories(out_dir, ec);
  const fs::path csv = fs::path(out_dir) / "covariance3d.csv";
  {
    std::ofstream f(csv);
    if (!f) {
      std::fprintf(stderr, "ggins-covariance3d: cannot write %s\n", csv.c_str());
      return 1;
    }
    f << "t_s";
    for (const auto& c : cols) f << ',' << c;
    f << ",lambda_max_re_ps\n";
    f.precision(10);
    for (size_t k = 0; k < run.size(); ++k) {
      f << run[k].t;
      for (double v : ned_all(run[k])) f << ',' << v;
      f << ',' << lam_u[k] << '\n';
    }
  }
  const auto fin = ned_all(run.back());
  json j;
  j["scenario"] = s.name;
  j["t_s"] = run.back().t;
  j["frame"] = "one sigma in NED (north, east, down) at the reference point; psi = attitude error angles about N, E, D";
  for (size_t i = 0; i < cols.size(); ++i) j[cols[i]] = fin[i];
  {
    json ecef;
    const auto keys = model->state_keys();
    for (int i = 0; i < n; ++i) ecef[keys[size_t(i)]] = std::sqrt(std::max(0.0, run.back().P(i, i)));
    j["ecef"] = ecef;
  }
  j["parameters"] = {{"source", s.source}, {"unmodelled", unmodelled},
                     {"trajectory", s.traj_override ? "truth3d scenario" : "great circle (trajectory3d.hpp)"},
                     {"platform", sd ? "strapdown" : "stabilized"}, {"field", s.field}, {"omega_ie_radps", s.omega_ie},
                     {"radius_m", s.radius_m}, {"height_m", s.height_m}, {"lat0_deg", s.lat0_deg},
                     {"lon0_deg", s.lon0_deg}, {"heading_deg", s.heading_deg}, {"speed_mps", s.speed_mps},
                     {"duration_s", s.duration_s}, {"half_base_m", s.model.half_base_m},
                     {"acc_bias_sigma_mps2", s.acc_bias_sigma_mps2}, {"gyro_bias_sigma_radps", s.gyro_bias_sigma_radps},
                     {"acc_noise_sigma_mps2", s.model.acc_noise_sigma_mps2},
                     {"gyro_noise_sigma_radps", s.model.gyro_noise_sigma_radps}, {"rate_hz", s.model.rate_hz},
                     {"g0_sigma_mps2", s.g0_sigma_mps2}, {"psi0_sigma_rad", s.psi0_sigma_rad},
                     {"baro", s.model.baro.on}, {"n_states", n}, {"n_dist", model->n_dist()}};
  if (model->baro())
    j["baro_loop"] = {{"poles_radps", s.model.baro.poles_radps}, {"k1", model->k1()}, {"k2", model->k2()},
                      {"k3", model->k3()}, {"bias_sigma_m", s.baro_bias_sigma_m}, {"gm_sigma_m", s.model.baro.gm_sigma_m},
                      {"gm_tau_s", s.model.baro.gm_tau_s}, {"noise_sigma_m", s.model.baro.noise_sigma_m}};
  j["integration"] = {{"method", method_s}, {"dt_s", dt}, {"max_rel_diff_half_step", rel_half},
                      {"max_rel_diff_other_method", other.empty() ? json(nullptr) : json(rel_other)}};
  j["eigen"] = {{"note", "eigenvalues of the reduced F (error states resolved in ECEF); nav block = dr, dv, dG"},
                {"max_dev_nav_block_vs_first_order_per_omega_s", model->baro() ? json(nullptr) : json(max_dev_pred)},
                {"max_charpoly_residual", model->baro() ? json(nullptr) : json(max_charpoly)},
                {"samples", eig}};
  const fs::path jp = fs::path(out_dir) / "covariance3d.json";
  C::write_file(jp, j.dump(2) + '\n');

  std::string plot_msg;
  if (!no_plot) {
    const std::string py = C::find_python(python);
    const fs::path png = fs::path(out_dir) / "covariance3d.png";
    if (py.empty()) {
      plot_msg = "no python with matplotlib; no plot";
    } else {
      std::ostringstream cmd;
      cmd << "'" << py << "' '" << GGINS_COV3D_PLOT_SCRIPT << "' '" << csv.string() << "' '" << png.string()
          << "' --title '" << s.name << "' 1>&2";
      plot_msg = std::system(cmd.str().c_str()) == 0 ? "plot: " + png.string() : "plot failed: " + cmd.str();
    }
  }
  if (want_json) {
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("scenario %s (%s, %s field, omega_ie %g), t = %.1f s, %s RK4 dt = %g s\n", s.name.c_str(),
                sd ? "strapdown" : "stabilized", s.field.c_str(), s.omega_ie, run.back().t, method_s.c_str(), dt);
    for (size_t i = 0; i < cols.size(); ++i) std::printf("  sigma %-10s %.6g\n", cols[i].c_str(), fin[i]);
    std::printf("step halving: %.3g; other method: %.3g\n", rel_half, rel_other);
    if (!model->baro())
      std::printf("eigen: nav block vs first-order prediction max dev %.3g omega_s; charpoly residual %.3g\n",
                  max_dev_pred, max_charpoly);
    std::printf("wrote %s, %s\n", csv.c_str(), jp.c_str());
  }
  if (want_eigen) {
    FILE* o = want_json ? stderr : stdout;
    for (const auto& e : eig) {
      std::fprintf(o, "t = %7.1f s  lat %.3f deg  w_s %.6e  w_ie sinL %.6e\n", e["t_s"].get<double>(),
                   e["lat_gc_deg"].get<double>(), e["omega_s_radps"].get<double>(),
                   e["omega_ie_sinL_radps"].get<double>());
      for (const auto& z : e["eigenvalues"]) std::fprintf(o, "   %+.8e %+.8ej\n", z[0].get<double>(), z[1].get<double>());
    }
  }
  if (!plot_msg.empty()) std::fprintf(stderr, "ggins-covariance3d: %s\n", plot_msg.c_str());
  return 0;
  });
}
