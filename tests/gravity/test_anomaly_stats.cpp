// Point-mass anomaly fields with Rubenstein & Winter's statistics (eq. 5:
// rms deflection 4.5 arcsec, correlation exp(-|d|/33 n.mi.)): the design, and
// the statistics sampled from seeded realisations.
#include "test_util.hpp"

#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <vector>

using namespace ggins::gravity;
static const Real kArcsec = 1.0L / 206264.80624709636L;

// Distance at which a sampled correlation curve first drops below 1/e (linear interpolation).
static Real one_over_e(const std::vector<Real>& c, Real step) {
  for (std::size_t k = 1; k < c.size(); ++k)
    if (c[k] < std::exp(-1.0L)) return step * (k - 1 + (c[k - 1] - std::exp(-1.0L)) / (c[k - 1] - c[k]));
  return c.size() * step;
}

// The design: NNLS fit of the layer covariances to exp(-d/L), weights sum to one.
static void test_design(void**) {
  const RwAnomalyConfig cfg;
  const RwDesign d = design_rubenstein_winter(cfg);
  Real wsum = 0;
  for (const RwLayer& l : d.layers) {
    std::printf("  layer depth %7.0Lf m, spacing %7.0Lf m, sigma(GM) %.3Le m^3/s^2, weight %.3Lf\n", l.depth, l.spacing, l.sigma_gm, l.weight);
    wsum += l.weight;
    assert_true(l.depth >= cfg.min_depth && l.weight > 0);
  }
  std::vector<Real> c;
  const Real step = 100;
  for (Real x = 0; x < 3 * cfg.corr_length; x += step) c.push_back(rw_model_cov_perp(d, 1, x));
  const Real le = one_over_e(c, step);
  std::printf("  fit max error %.4Lf; model 1/e distance %.0Lf m = %.3Lf L\n", d.fit_max_error, le, le / cfg.corr_length);
  assert_true(std::fabs(wsum - 1) < 1e-12L);
  assert_true(d.fit_max_error < 0.04L);
  assert_true(std::fabs(le / cfg.corr_length - 1) < 0.05L);
  assert_true(std::fabs(rw_model_cov_perp(d, cfg.rms_deflection, 0) - cfg.rms_deflection * cfg.rms_deflection) < 1e-20L);
}

// Sampled statistics of three seeded realisations (600 km half-width region,
// samples in the central +-300 km so every point has >= 300 km of masses
// around it): deflection components (horizontal gravitation / g_ref) along
// 7 E-W and 7 N-S lines each, 3 km apart along the line, at the reference
// height. About 3 x 14 x 600 km / 61 km ~ 400 correlation lengths are
// sampled, so rms is known to ~ +-4% and the 1/e distance to ~ +-10% (one
// sigma, from the spread over seeds printed below); tolerances are 10% / 20%.
static void test_sampled_statistics(void**) {
  RwAnomalyConfig cfg;
  const Real L = cfg.corr_length, step = 3000, inner = 300e3L;
  const int npts = static_cast<int>(2 * inner / step) + 1, nlag = static_cast<int>(2.5L * L / step) + 2, nline = 7;
  std::vector<Real> cperp(nlag, 0), cpar(nlag, 0), cnt(nlag, 0);
  Real sum2 = 0, n2 = 0;
  std::vector<Real> rms_seed;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    cfg.seed = seed;
    const PointMassAnomalyField f = make_rubenstein_winter_field(cfg);
    Real s2 = 0, m2 = 0;
    for (int dir = 0; dir < 2; ++dir)
      for (int li = 0; li < nline; ++li) {
        const Real off = -inner + 2 * inner * li / (nline - 1);
        std::vector<Real> perp(npts), par(npts);
        for (int i = 0; i < npts; ++i) {
          const Real s = -inner + i * step, e = dir ? off : s, n = dir ? s : off;
          const Real lat = cfg.lat0 + n / wgs84::kA, lon = cfg.lon0 + e / (wgs84::kA * std::cos(cfg.lat0));
          const Vec3 g = wgs84::enu_to_ecef(lat, lon).transpose() * f.gravitation(wgs84::geodetic_to_ecef(lat, lon, cfg.ref_height));
          const Real de = g[0] / cfg.g_ref, dn = g[1] / cfg.g_ref;
          perp[i] = dir ? de : dn;  // E-W line (dir 0): perpendicular = north component
          par[i] = dir ? dn : de;
          s2 += de * de + dn * dn; m2 += 2;
        }
        for (int k = 0; k < nlag; ++k)
          for (int i = 0; i + k < npts; ++i) { cperp[k] += perp[i] * perp[i + k]; cpar[k] += par[i] * par[i + k]; cnt[k] += 1; }
      }
    rms_seed.push_back(std::sqrt(s2 / m2) / kArcsec);
    sum2 += s2; n2 += m2;
  }
  const Real rms = std::sqrt(sum2 / n2) / kArcsec;
  std::vector<Real> rp(nlag), ra(nlag);
  for (int k = 0; k < nlag; ++k) { rp[k] = cperp[k] / cnt[k] / (cperp[0] / cnt[0]); ra[k] = cpar[k] / cnt[k] / (cpar[0] / cnt[0]); }
  const Real le = one_over_e(rp, step), le_par = one_over_e(ra, step);
  const RwDesign des = design_rubenstein_winter(cfg);
  std::vector<Real> cm;
  for (Real x = 0; x < 2 * L; x += 100) cm.push_back(rw_model_cov_par(des, 1, x));
  std::printf("  rms deflection %.3Lf arcsec (seeds: %.3Lf %.3Lf %.3Lf; R&W 4.5)\n", rms, rms_seed[0], rms_seed[1], rms_seed[2]);
  std::printf("  perpendicular component 1/e distance %.1Lf km = %.3Lf L (R&W L = 61.1 km)\n", le / 1e3L, le / L);
  std::printf("  parallel component 1/e distance %.1Lf km (model %.1Lf km)\n", le_par / 1e3L, one_over_e(cm, 100) / 1e3L);
  for (int k = 0; k < nlag; k += 5)
    std::printf("    d/L %.2Lf  perp %.3Lf  exp %.3Lf  model %.3Lf | par %.3Lf model %.3Lf\n", k * step / L, rp[k], std::exp(-k * step / L),
                rw_model_cov_perp(des, 1, k * step), ra[k], rw_model_cov_par(des, 1, k * step));
  assert_true(std::fabs(rms / 4.5L - 1) < 0.10L);
  assert_true(std::fabs(le / L - 1) < 0.20L);
}

// The point-mass anomaly field itself: Gamma vs FD of G, G vs FD of V,
// Laplace, symmetry, G-only path, third derivatives, at 1 km height over a
// small realisation (the shallowest masses are 3 km deep).
static void test_fd(void**) {
  RwAnomalyConfig cfg;
  cfg.half_size = 40e3L;
  const PointMassAnomalyField f = make_rubenstein_winter_field(cfg);
  Real wg = 0, wG = 0, wtr = 0, was = 0, wgo = 0, w3 = 0, s3 = 0, smax = 0;
  bool ok3 = false;
  for (int i = 0; i < 5; ++i) {
    const Vec3 r = wgs84::geodetic_to_ecef(cfg.lat0 + 1e-4L * i, cfg.lon0 - 2e-4L * i, 1000 + 300.0L * i);
    const gt::FdErrors e = gt::fd_check(f, r, 5.0L, 5.0L);
    const FieldSample s = f.eval(r);
    wg = std::max(wg, e.g); wG = std::max(wG, e.gamma); wtr = std::max(wtr, e.trace); was = std::max(was, e.asym);
    wgo = std::max(wgo, (f.gravitation(r) - s.g).cwiseAbs().maxCoeff());
    smax = std::max(smax, s.gamma.cwiseAbs().maxCoeff());
    w3 = std::max(w3, gt::third_fd_check(f, r, 5.0L, s3, ok3));
  }
  std::printf("  %zu masses: fd g %.2Le m/s^2, Gamma %.2Le E (max |Gamma| %.1Lf E), trace %.2Le E, asym %.2Le E;"
              " G-only path %.2Le m/s^2; third %.2Le of %.2Le s^-2/m\n",
              f.masses().size(), wg, wG * 1e9L, smax * 1e9L, wtr * 1e9L, was * 1e9L, wgo, w3, s3);
  assert_true(wg < 1e-14L);
  assert_true(wG < 1e-17L);  // 1e-8 E (fd truncation and rounding ~3e-10 E)
  assert_true(wtr < 1e-22L);
  assert_true(was == 0);
  assert_true(wgo < 1e-16L);  // G-only path sums in double
  assert_true(ok3 && w3 < 1e-6L * s3);
}

int main() {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_design), cmocka_unit_test(test_sampled_statistics),
                                     cmocka_unit_test(test_fd)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
