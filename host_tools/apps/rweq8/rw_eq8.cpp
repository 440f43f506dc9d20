// ggins rw-eq8: Rubenstein & Winter eq. (8) reproduced with the firmware's
// conventional (gravity-model) mode, Monte Carlo, firmware linked in-process.
//
// B. R. Rubenstein and H. Winter, "A Method for Correcting the Effect of Gravity Anomalies
// on Precision Inertial Navigation Mapping Systems" (docs/rubenstein-winter.md):
//   eq. (3)  W(t) = R w_s sin(w_s t)            (Schuler weighting function)
//   eq. (6)  R(tau) = delta^2 exp(-alpha |tau|), alpha = V / L (330 kn / 33 n.mi. = 10 rad/h)
//   eq. (7)  (dx)^2 = int_0^t int_0^t W(u) W(v) R(u - v) dv du
//   eq. (8)  its closed form for (3) and (6).
// Each run flies the north flight at constant height (V = 330 kn) over a
// spherical Earth (point mass GM; the firmware's onboard model is exactly
// that point mass, so the deflection is the only gravity error) with perfect
// accelerometers and a perfect barometer (vertical channel damped, as on
// R&W's platform). The frames, the truth and the firmware configuration come
// from the simulation library (truth/generator.hpp, truth/config2d.hpp) for a
// scenario built from the options, with the deflected field below as its
// gravitation. The true gravitation has an along-track component
// g * delta(s) the onboard model does not know; delta(s) is either
//   --field gm  (default): a first-order Gauss-Markov sequence in distance,
//              delta_{k+1} = phi delta_k + sqrt(1 - phi^2) sigma w_k,
//              phi = exp(-ds / L): EXACTLY eq. (5)/(6)'s statistics at the samples;
//   --field point-mass: the along-track (north) deflection of a realisation of
//              the Rubenstein & Winter point-mass anomaly field
//              (gravity/point_anomaly.hpp), sampled every --pm-sample-m along the
//              meridian at the flight height and interpolated linearly. That field
//              is harmonic: its along-track correlation is C_par, not the
//              exponential (docs/gravity.md), so it is compared with eq. (7)
//              evaluated with C_par of the design and with the measured
//              autocorrelation of the realisations.
// The along-track position error (r_nav - r_true) . t^ is collected every
// --check-every-s; its Monte Carlo mean square over N runs is compared with the
// prediction: N ms / sigma^2 ~ chi^2_N (the error is linear in a Gaussian
// input), band [chi2_N(p/2), chi2_N(1 - p/2)] / N (Wilson-Hilferty quantiles).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "ggins/cli_checks.hpp"
#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth/config2d.hpp"
#include "ggins/truth/generator.hpp"
#include "ggins/truth/stats.hpp"
extern "C" {
#include "ggins/nav2d.h"
}

namespace {

using json = nlohmann::json;
constexpr long double kGM = ggins::gravity::wgs84::kGm;  // m^3/s^2
constexpr long double kRe = ggins::gravity::wgs84::kA;   // m
constexpr double kArcsec = 4.84813681109535994e-6;
constexpr double kKnot = 1852.0 / 3600.0;

struct Opts {
  int runs = 200;
  double hours = 2.0;
  double rate_hz = 1.0;
  double speed_kn = 330.0;
  double height_m = 3000.0;
  double lat0_deg = 30.0;
  double rms_arcsec = 4.5;
  double corr_nmi = 33.0;
  uint64_t seed = 1;
  std::string field = "gm";
  double pm_sample_m = 1000.0;
  double check_every_s = 300.0;
  double band = 0.999;  // two-sided coverage of the chi-square band
  std::string out;      // JSON/CSV prefix ("" = none)
  bool check = false;   // exit 1 when a checkpoint falls outside the band
  double check_from_s = 600.0;
};

// R&W eq. (8), as printed.
double eq8_ms(double t, double delta, double R, double g, double alpha, double ws) {
  const double a2w2 = alpha * alpha + ws * ws;
  return delta * delta * R * g / a2w2 *
         (alpha * (t - std::sin(2 * ws * t) / (2 * ws)) - 0.5 * (1 - std::cos(2 * ws * t)) +
          2 * ws / a2w2 * (ws * (1 - std::exp(-alpha * t) * std::cos(ws * t)) - alpha * std::exp(-alpha * t) * std::sin(ws * t)));
}

// R&W eq. (7) by quadrature, for any input autocorrelation Rf(tau) (rad^2):
// (dx)^2 = 2 int_0^t Rf(tau) K(tau) dtau, K(tau) = int_0^{t-tau} W(u) W(u + tau) du
//        = (R ws)^2 / 2 [(t - tau) cos(ws tau) - (sin(ws (2t - tau)) - sin(ws tau)) / (2 ws)].
template <class F>
double eq7_ms(double t, double R, double ws, F Rf, int n = 4000) {
  if (t <= 0) return 0;
  const double h = t / n;
  double s = 0;
  for (int i = 0; i <= n; ++i) {
    const double tau = i * h;
    const double K = 0.5 * R * R * ws * ws *
                     ((t - tau) * std::cos(ws * tau) - (std::sin(ws * (2 * t - tau)) - std::sin(ws * tau)) / (2 * ws));
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    s += w * Rf(tau) * K;
  }
  return 2 * s * h / 3;
}

// The truth gravitation of a run: the point mass plus R&W's along-track
// deflection, G(r) = G_pm(r) + |G_pm(r)| delta(s) t^(r), with s the distance
// along the flight circle (radius rho, from latitude lat0) of the point's
// polar angle, t^ the along-track (north) unit vector there, and delta given
// as samples every ds metres from s = 0 (linear between them). Gamma is taken
// by central differences of G (1 m steps): the deflection's own gradient
// (~ g delta / L ~ 1e-9 s^-2) is kept, though the runs (model mode) do not
// use it.
class DeflectedField final : public ggins::gravity::Field {
  using Vec3 = ggins::gravity::Vec3;

 public:
  DeflectedField(long double gm, long double rho, long double lat0, const std::vector<double>& delta, double ds)
      : pm_(gm), rho_(rho), lat0_(lat0), delta_(delta), ds_(ds) {}
  std::string name() const override { return "point-mass + along-track deflection"; }
  Vec3 gravitation(const Vec3& r) const override {
    const Vec3 g = pm_.gravitation(r);
    const long double th = std::atan2(r(2), r(0)), c = std::cos(th), sn = std::sin(th);
    const double x = static_cast<double>(rho_ * (th - lat0_)) / ds_;  // delta at the along-track distance
    size_t i0 = x > 0 ? static_cast<size_t>(x) : 0;
    if (i0 + 1 >= delta_.size()) i0 = delta_.size() - 2;
    const double fr = x - static_cast<double>(i0);
    const long double dl = (1 - fr) * delta_[i0] + fr * delta_[i0 + 1];
    return g + g.norm() * dl * Vec3(-sn, 0, c);
  }
  ggins::gravity::FieldSample eval(const Vec3& r) const override {
    ggins::gravity::FieldSample f;
    f.potential = pm_.eval(r).potential;  // the point mass's (the deflection has none here)
    f.g = gravitation(r);
    for (int k = 0; k < 3; ++k) {
      Vec3 h = Vec3::Zero();
      h(k) = 1.0L;
      f.gamma.col(k) = (gravitation(r + h) - gravitation(r - h)) / 2.0L;
    }
    return f;
  }

 private:
  ggins::gravity::PointMassField pm_;
  long double rho_, lat0_;
  const std::vector<double>& delta_;
  double ds_;
};

// The scenario of a run: R&W's north flight over the point mass, perfect
// sensors, a barometer sample every step, the firmware in model mode with the
// point mass as its onboard model and the barometric loop damping the
// vertical channel.
ggins::truth::Scenario rw_scenario(const Opts& o, int64_t dt_us, long double rho) {
  ggins::truth::Scenario s;
  s.name = "rw-eq8";
  s.trajectory.type = "north-flight";
  s.trajectory.speed_mps = o.speed_kn * kKnot;
  s.trajectory.height_m = o.height_m;
  s.trajectory.lat0_deg = o.lat0_deg;
  s.trajectory.radius_m = static_cast<double>(kRe);
  s.gravity.model = "point-mass";
  s.gravity.gm_m3ps2 = static_cast<double>(kGM);
  s.a_m = 0.5;
  s.b_m = 0.5;
  s.rate_hz = 1e6 / static_cast<double>(dt_us);
  s.duration_s = o.hours * 3600.0;
  s.firmware.f_max_mps2 = 100.0;
  s.firmware.asym_max_ps2 = 1e-6;
  s.firmware.dt_tol_us = 0;
  s.navigation.gravity = "model";
  s.navigation.model.set = true;
  s.navigation.model.gm_m3ps2 = static_cast<double>(kGM);
  s.navigation.model.a_m = static_cast<double>(kRe);
  s.baro.enable = true;  // perfect: no bias, no noise
  s.baro.rate_hz = s.rate_hz;
  auto& l = s.navigation.baro;
  l.enable = 1;
  l.poles_radps = {0.01, 0.02, 0.03};
  l.omega_s2 = static_cast<double>(kGM / (rho * rho * rho));
  l.period_s = static_cast<double>(dt_us) * 1e-6;
  l.max_age_s = 0.5 * l.period_s;
  l.coast_s = 10 * l.period_s;
  l.gate_m = 1000.0;
  return s;
}

// One flight through the deflected field. Returns the along-track errors at
// the checkpoints (every `every` steps).
std::vector<double> fly(const ggins::truth::Scenario& sc, const std::vector<double>& delta, double ds, int64_t every,
                        int& bad_steps) {
  static gg_nav2d_t nav;  // large (the model's grid): static, one flight at a time
  const long double rho = static_cast<long double>(sc.trajectory.radius_m) + static_cast<long double>(sc.trajectory.height_m);
  const long double lat0 = static_cast<long double>(sc.trajectory.lat0_deg) * 3.14159265358979323846264338327950288L / 180.0L;
  const ggins::truth::Generator gen(sc, std::make_shared<DeflectedField>(kGM, rho, lat0, delta, ds));
  const gg_nav2d_config_t cfg = ggins::truth::config2d(gen);
  if (gg_nav2d_init(&nav, &cfg) != GG_OK) throw std::runtime_error("gg_nav2d_init refused the configuration");
  std::vector<double> err;
  for (int64_t k = 0; k < gen.n_steps(); ++k) {
    gg_frame_t f;
    ggins::truth::TruthState t;
    gen.frame(k, f, &t);
    gg_nav_output_t out;
    if (gg_nav2d_step(&nav, &f, nullptr, &out) != GG_OK || out.health != 0) ++bad_steps;
    if (k % every == 0) {
      const ggins::truth::Vec3& r = t.kin.r;
      const long double rn = std::sqrt(r(0) * r(0) + r(2) * r(2));
      const long double th[3] = {-r(2) / rn, 0, r(0) / rn};  // along-track unit vector
      long double e = 0;
      for (int j = 0; j < 3; ++j) e += (static_cast<long double>(out.r_i[j]) - r(j)) * th[j];
      err.push_back(static_cast<double>(e));
    }
  }
  return err;
}

}  // namespace

int main(int argc, char** argv) {
  Opts o;
  CLI::App app{"Rubenstein & Winter eq. (8): Monte Carlo of the conventional INS in a random deflection field"};
  app.add_option("--runs", o.runs, "Monte Carlo runs")->check(CLI::Range(2, 1000000));
  app.add_option("--hours", o.hours, "flight time, h")->check(ggins::cli::FiniteRange(0.01, 24.0));
  app.add_option("--rate-hz", o.rate_hz, "firmware step rate, Hz")->check(ggins::cli::FiniteRange(0.2, 100.0));
  app.add_option("--speed-kn", o.speed_kn, "ground speed, knots (R&W: 330)")->check(ggins::cli::FiniteRange(1.0, 2000.0));
  app.add_option("--height-m", o.height_m, "flight height above R_e, m")->check(ggins::cli::FiniteRange(-1000.0, 1e5));
  app.add_option("--lat0-deg", o.lat0_deg, "start latitude, deg")->check(ggins::cli::FiniteRange(-89.0, 89.0));
  app.add_option("--rms-arcsec", o.rms_arcsec, "rms deflection, arcsec (R&W eq. 5: 4.5)")
      ->check(ggins::cli::FiniteRange(0.0, 3600.0, ggins::cli::kOpenLow));
  app.add_option("--corr-nmi", o.corr_nmi, "correlation distance, n.mi. (R&W eq. 5: 33)")
      ->check(ggins::cli::FiniteRange(0.0, 1e4, ggins::cli::kOpenLow));
  app.add_option("--seed", o.seed, "seed of the deflection realisations")->check(ggins::cli::Seed(1ULL << 40));
  app.add_option("--field", o.field, "gm (exact exponential, Gauss-Markov) or point-mass (R&W point-mass field)")
      ->check(CLI::IsMember({"gm", "point-mass"}));
  app.add_option("--pm-sample-m", o.pm_sample_m, "point-mass field: sample spacing along track, m")
      ->check(ggins::cli::FiniteRange(1.0, 1e5));
  app.add_option("--check-every-s", o.check_every_s, "checkpoint spacing, s")
      ->check(ggins::cli::FiniteRange(0.0, 86400.0, ggins::cli::kOpenLow));
  app.add_option("--band", o.band, "two-sided coverage of the chi-square band")->check(ggins::cli::FiniteRange(0.5, 0.999999));
  app.add_option("--out", o.out, "write <out>.json and <out>.csv");
  app.add_flag("--check", o.check, "exit 1 if a checkpoint at t >= --check-from-s is outside the band");
  app.add_option("--check-from-s", o.check_from_s, "first checkpoint time that --check tests, s")
      ->check(ggins::cli::NonNegativeFinite());
  try {  // bad arguments: CLI11's message naming the option, exit 2 (ggins/cli_checks.hpp)
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? ggins::cli::kExitOk : ggins::cli::kExitBadArgs;
  }
  try {

  const auto t_start = std::chrono::steady_clock::now();
  const int64_t dt_us = std::llround(1e6 / o.rate_hz);
  const int64_t n_steps = std::llround(o.hours * 3600.0 * 1e6 / static_cast<double>(dt_us)) + 1;
  const int64_t every = std::max<int64_t>(1, std::llround(o.check_every_s * 1e6 / static_cast<double>(dt_us)));
  const long double rho = kRe + static_cast<long double>(o.height_m);
  const ggins::truth::Scenario sc = rw_scenario(o, dt_us, rho);
  const double R = static_cast<double>(rho), V = sc.trajectory.speed_mps;
  const double g = static_cast<double>(kGM / (rho * rho)), ws = std::sqrt(g / R);
  const double L = o.corr_nmi * 1852.0, alpha = V / L, delta = o.rms_arcsec * kArcsec;
  const double length = V * static_cast<double>(n_steps) * static_cast<double>(dt_us) * 1e-6 + 2 * o.pm_sample_m;

  // deflection samples per run
  const double ds = o.field == "gm" ? V * static_cast<double>(dt_us) * 1e-6 : o.pm_sample_m;
  const size_t n_samp = static_cast<size_t>(std::ceil(length / ds)) + 2;
  std::vector<double> sum_sq;     // per checkpoint
  std::vector<double> acf_sum;    // measured autocorrelation of delta, lag j * ds
  const size_t n_lag = std::min<size_t>(n_samp / 2, static_cast<size_t>(std::ceil(4 * L / ds)) + 1);
  acf_sum.assign(n_lag, 0.0);
  double acf_n = 0;
  int bad_steps = 0;
  ggins::gravity::RwDesign design;
  bool have_design = false;
  for (int run = 0; run < o.runs; ++run) {
    std::vector<double> d(n_samp);
    if (o.field == "gm") {
      std::mt19937_64 rng(o.seed * 1000003ULL + static_cast<uint64_t>(run));
      std::normal_distribution<double> nd;
      const double phi = std::exp(-ds / L), q = std::sqrt(1 - phi * phi);
      d[0] = delta * nd(rng);
      for (size_t i = 1; i < n_samp; ++i) d[i] = phi * d[i - 1] + delta * q * nd(rng);
    } else {
      namespace gr = ggins::gravity;
      gr::RwAnomalyConfig c;
      const double lat_mid = o.lat0_deg + 0.5 * length / R * 180.0 / M_PI;
      c.lat0 = static_cast<gr::Real>(lat_mid * M_PI / 180.0);
      c.lon0 = 0;
      c.half_size = static_cast<gr::Real>(0.5 * length + 150e3);
      c.ref_height = o.height_m;
      c.rms_deflection = static_cast<gr::Real>(delta);
      c.corr_length = L;
      c.seed = o.seed * 1000003ULL + static_cast<uint64_t>(run);
      gr::RwDesign des;
      const gr::PointMassAnomalyField f = gr::make_rubenstein_winter_field(c, &des);
      if (!have_design) { design = des; have_design = true; }
      const double lat0 = o.lat0_deg * M_PI / 180.0;
      for (size_t i = 0; i < n_samp; ++i) {
        const double lat = lat0 + static_cast<double>(i) * ds / R;
        const gr::Vec3 re = gr::wgs84::geodetic_to_ecef(lat, 0.0L, o.height_m);
        const gr::Vec3 north(-std::sin(lat), 0.0, std::cos(lat));  // local north at lon 0
        const gr::Vec3 ga = f.gravitation(re);
        d[i] = static_cast<double>(ga.dot(north)) / g;
      }
    }
    for (size_t j = 0; j < n_lag; ++j) {
      double s = 0;
      for (size_t i = 0; i + j < n_samp; ++i) s += d[i] * d[i + j];
      acf_sum[j] += s / static_cast<double>(n_samp - j);
    }
    acf_n += 1;
    const std::vector<double> e = fly(sc, d, ds, every, bad_steps);
    if (sum_sq.empty()) sum_sq.assign(e.size(), 0.0);
    for (size_t i = 0; i < e.size(); ++i) sum_sq[i] += e[i] * e[i];
  }
  std::vector<double> acf(n_lag);
  for (size_t j = 0; j < n_lag; ++j) acf[j] = acf_sum[j] / acf_n;
  auto acf_at = [&](double lag_m) {  // measured, linear in lag; 0 beyond the measured range
    const double x = lag_m / ds;
    const size_t i = static_cast<size_t>(x);
    if (i + 1 >= n_lag) return 0.0;
    return (1 - (x - static_cast<double>(i))) * acf[i] + (x - static_cast<double>(i)) * acf[i + 1];
  };
  // measured 1/e distance of the autocorrelation
  double e_dist = NAN;
  for (size_t j = 1; j < n_lag; ++j)
    if (acf[j] < acf[0] / M_E) {
      const double f0 = acf[j - 1] - acf[0] / M_E, f1 = acf[j] - acf[0] / M_E;
      e_dist = (static_cast<double>(j - 1) + f0 / (f0 - f1)) * ds;
      break;
    }

  const double N = o.runs;
  const ggins::truth::Chi2Band band = ggins::truth::chi2_band_coverage(N, o.band);  // truth/stats.hpp
  const double b_lo = band.ms_lo, b_hi = band.ms_hi;
  json res;
  res["command"] = [&] { std::string s; for (int i = 0; i < argc; ++i) s += (i ? " " : "") + std::string(argv[i]); return s; }();
  res["field"] = o.field;
  res["runs"] = o.runs;
  res["hours"] = o.hours;
  res["rate_hz"] = o.rate_hz;
  res["speed_mps"] = V;
  res["alpha_radph"] = alpha * 3600;
  res["schuler_period_min"] = 2 * M_PI / ws / 60;
  res["delta_arcsec"] = o.rms_arcsec;
  res["corr_length_m"] = L;
  res["measured_rms_arcsec"] = std::sqrt(acf[0]) / kArcsec;
  res["measured_1e_distance_m"] = e_dist;
  res["band"] = {{"coverage", o.band}, {"ratio_ms_lo", b_lo}, {"ratio_ms_hi", b_hi},
                 {"ratio_rms_lo", std::sqrt(b_lo)}, {"ratio_rms_hi", std::sqrt(b_hi)}};
  res["steps_not_ok"] = bad_steps;
  std::printf("R&W eq. 8 Monte Carlo: field %s, %d runs, %.2f h at %.1f Hz, V %.2f m/s, alpha %.3f rad/h, "
              "Schuler %.2f min\n", o.field.c_str(), o.runs, o.hours, o.rate_hz, V, alpha * 3600, 2 * M_PI / ws / 60);
  std::printf("deflection realisations: rms %.3f arcsec, along-track 1/e distance %.1f km (eq. 5: %.1f km); "
              "steps not OK: %d\n", std::sqrt(acf[0]) / kArcsec, e_dist / 1e3, L / 1e3, bad_steps);
  std::printf("band (%.4g two-sided, N = %d): rms ratio in [%.4f, %.4f]\n", o.band, o.runs, std::sqrt(b_lo), std::sqrt(b_hi));
  std::printf("%8s %12s %12s %12s %12s %8s %s\n", "t_s", "mc_rms_m", "eq8_m", "eq7_quad_m", o.field == "gm" ? "" : "eq7_Cpar_m",
              "ratio", "in band");
  json rows = json::array();
  bool all_in = true;
  bool closed_form_ok = true;
  std::ofstream csv;
  if (!o.out.empty()) {
    csv.open(o.out + ".csv");
    csv << "t_s,mc_rms_m,eq8_m,eq7_exp_m,eq7_measured_acf_m,eq7_cpar_m,band_lo_m,band_hi_m\n";
  }
  for (size_t i = 0; i < sum_sq.size(); ++i) {
    const double t = static_cast<double>(static_cast<int64_t>(i) * every * dt_us) * 1e-6;
    const double mc = std::sqrt(sum_sq[i] / N);
    const double p8 = std::sqrt(std::max(0.0, eq8_ms(t, delta, R, g, alpha, ws)));
    const double p7 = std::sqrt(std::max(0.0, eq7_ms(t, R, ws, [&](double tau) { return delta * delta * std::exp(-alpha * tau); })));
    const double p7m = std::sqrt(std::max(0.0, eq7_ms(t, R, ws, [&](double tau) { return acf_at(V * tau); })));
    double p7c = NAN;
    if (have_design)
      p7c = std::sqrt(std::max(0.0, eq7_ms(t, R, ws, [&](double tau) {
        return static_cast<double>(ggins::gravity::rw_model_cov_par(design, delta, V * tau)); })));
    // the prediction tested: eq. 8 for the exact-statistics field; eq. 7 with the
    // design's C_par for the point-mass field (its along-track correlation)
    const double pred = o.field == "gm" ? p8 : p7c;
    const double ratio = pred > 0 ? mc / pred : NAN;
    const bool in = !(pred > 0) || (ratio * ratio >= b_lo && ratio * ratio <= b_hi);
    if (t >= o.check_from_s && !in) all_in = false;
    // the printed closed form (8) against the quadrature of (7) with the same exponential
    if (p8 > 0 && std::fabs(p8 - p7) > 0.01 * p8) closed_form_ok = false;
    std::printf("%8.0f %12.3f %12.3f %12.3f %12.3f %8.4f %s\n", t, mc, p8, p7, o.field == "gm" ? p7m : p7c, ratio,
                pred > 0 ? (in ? "yes" : "NO") : "-");
    rows.push_back({{"t_s", t}, {"mc_rms_m", mc}, {"eq8_m", p8}, {"eq7_exp_m", p7}, {"eq7_measured_acf_m", p7m},
                    {"eq7_cpar_m", have_design ? json(p7c) : json(nullptr)}, {"ratio", ratio}, {"in_band", in}});
    if (csv) csv << t << ',' << mc << ',' << p8 << ',' << p7 << ',' << p7m << ',' << (have_design ? p7c : NAN) << ','
                 << pred * std::sqrt(b_lo) << ',' << pred * std::sqrt(b_hi) << '\n';
  }
  res["rows"] = rows;
  res["all_in_band_from_s"] = {{"from_s", o.check_from_s}, {"all_in", all_in}};
  res["eq8_matches_eq7_quadrature_1pct"] = closed_form_ok;
  res["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  std::printf("wall %.1f s; checkpoints from %.0f s all in band: %s\n", res["wall_s"].get<double>(), o.check_from_s,
              all_in ? "yes" : "NO");
  if (!o.out.empty()) std::ofstream(o.out + ".json") << res.dump(2) << '\n';
  std::printf("eq. (8) as printed = eq. (7) by quadrature within 1%%: %s\n", closed_form_ok ? "yes" : "NO");
  if (bad_steps > 0) std::printf("WARNING: %d firmware steps were not OK or had health bits\n", bad_steps);
  return (o.check && (!all_in || bad_steps > 0 || !closed_form_ok)) ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-rw-eq8: %s\n", e.what());
    return ggins::cli::kExitFailed;
  }
}
