#include "ggins/truth/survey.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ggins::truth {

namespace {
constexpr uint64_t kStreamSurvey = 40;             // counter_normal stream of the survey noise
constexpr double kArcsec = 4.84813681109535994e-6;  // rad
constexpr double kMgal = 1e-5;                      // m/s^2
}  // namespace

SurveyGrid make_survey_grid(const Generator& gen) {
  const Scenario& sc = gen.scenario();
  const SurveyParams& p = sc.navigation.survey;
  if (sc.trajectory.type != "north-flight")
    throw std::invalid_argument("navigation.survey: only for trajectory.type = north-flight");
  SurveyGrid s;
  const double rho = sc.trajectory.radius_m + sc.trajectory.height_m;  // the flight's radius
  const double lat0 = sc.trajectory.lat0_deg * M_PI / 180.0;
  const double length = sc.trajectory.speed_mps * sc.duration_s;  // along-track, m
  s.c0 = std::cos(lat0);
  s.s0 = std::sin(lat0);
  s.dth_rad = p.spacing_m / rho;
  s.th0_rad = -p.margin_m / rho;
  const double n = std::ceil((length + 2.0 * p.margin_m) / p.spacing_m) + 1.0;
  s.n_rho = static_cast<int32_t>(p.n_rho);
  if (!(n >= 2) || n * static_cast<double>(s.n_rho) > GG_GMODEL_GRID_MAX)
    throw std::invalid_argument("navigation.survey: " + std::to_string(static_cast<long long>(n)) + " x " +
                                std::to_string(s.n_rho) + " nodes exceed GG_GMODEL_GRID_MAX = " +
                                std::to_string(GG_GMODEL_GRID_MAX) + " (raise spacing_m)");
  s.n_th = static_cast<int32_t>(n);
  s.drho_m = p.drho_m;
  s.rho0_m = rho - 0.5 * p.drho_m * static_cast<double>(s.n_rho - 1);
  const size_t nn = static_cast<size_t>(s.n_th) * static_cast<size_t>(s.n_rho);
  s.dg.resize(nn);
  s.dg_true.resize(nn);
  const double g0 = static_cast<double>(gen.truth(0).g.norm());
  double st = 0, sr = 0, tt = 0, tr = 0;
  for (int32_t k = 0; k < s.n_rho; ++k) {
    for (int32_t i = 0; i < s.n_th; ++i) {
      // node position: angle lat0 + th from the x axis (e0 = the start direction), radius rho_k
      const Real th = static_cast<Real>(lat0) + static_cast<Real>(s.th0_rad) + static_cast<Real>(i) * static_cast<Real>(s.dth_rad);
      const Real rk = static_cast<Real>(s.rho0_m) + static_cast<Real>(k) * static_cast<Real>(s.drho_m);
      const Vec3 r(rk * std::cos(th), 0.0L, rk * std::sin(th));
      const Vec3 d = gen.field().eval(r).g - gen.model_g(r);
      const Vec3 rhat(std::cos(th), 0.0L, std::sin(th)), that(-std::sin(th), 0.0L, std::cos(th));
      const double dt = static_cast<double>(d.dot(that)), dr = static_cast<double>(d.dot(rhat));
      const auto ui = static_cast<uint64_t>(i), uk = static_cast<uint64_t>(k);
      const double nt = p.noise_deflection_arcsec * kArcsec * g0 * counter_normal(p.seed, kStreamSurvey, ui, uk, 0);
      const double nr = p.noise_gravity_mgal * kMgal * counter_normal(p.seed, kStreamSurvey, ui, uk, 1);
      const size_t idx = static_cast<size_t>(k) * static_cast<size_t>(s.n_th) + static_cast<size_t>(i);
      s.dg_true[idx] = {dt, dr};
      s.dg[idx] = {dt + nt, dr + nr};
      st += nt * nt;
      sr += nr * nr;
      tt += dt * dt;
      tr += dr * dr;
    }
  }
  const double dn = static_cast<double>(nn);
  s.rms_noise_t = std::sqrt(st / dn);
  s.rms_noise_r = std::sqrt(sr / dn);
  s.rms_true_t = std::sqrt(tt / dn);
  s.rms_true_r = std::sqrt(tr / dn);
  return s;
}

void fill_gmodel_grid(const SurveyGrid& s, gg_gmodel_grid_t& out) {
  out.n_th = s.n_th;
  out.n_rho = s.n_rho;
  out.c0 = s.c0;
  out.s0 = s.s0;
  out.th0_rad = s.th0_rad;
  out.dth_rad = s.dth_rad;
  out.rho0_m = s.rho0_m;
  out.drho_m = s.drho_m;
  for (size_t i = 0; i < s.dg.size() && i < static_cast<size_t>(GG_GMODEL_GRID_MAX); ++i) {
    out.dg[i][0] = s.dg[i][0];
    out.dg[i][1] = s.dg[i][1];
  }
}

}  // namespace ggins::truth
