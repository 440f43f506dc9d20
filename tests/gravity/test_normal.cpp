// WGS-84 normal gravitation field: against published WGS-84 numbers
// (NIMA TR8350.2 ch. 3 derived constants and the Somigliana formula, eq. (4-1)), an
// independent zonal spherical-harmonic formulation, and finite differences.
#include "test_util.hpp"

#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <vector>

using namespace ggins::gravity;
static const Real kDeg = static_cast<Real>(M_PI) / 180;

// Normal GRAVITY (gravitation + centrifugal) on the ellipsoid has the
// magnitude of Somigliana's closed formula, TR8350.2 eq. (4-1):
//   gamma = gamma_e (1 + k sin^2 phi) / sqrt(1 - e^2 sin^2 phi),
// with the published gamma_e, k, e^2; it is normal to the ellipsoid; and the
// ellipsoid is the level surface U = U0 (published U0).
static void test_somigliana_u0_direction(void**) {
  const NormalField f;
  Real worst_g = 0, worst_u = 0, worst_dir = 0;
  for (int i = 0; i <= 18; ++i)
    for (Real lon : {0.0L, 1.1L, -2.9L}) {
      const Real lat = (-90 + 10 * i) * kDeg;
      const Vec3 r = wgs84::geodetic_to_ecef(lat, lon, 0);
      const FieldSample s = f.eval(r);
      const Vec3 gt = s.g + f.centrifugal_acceleration(r);
      const Real sl = std::sin(lat);
      const Real som = wgs84::kPubGammaE * (1 + wgs84::kPubK * sl * sl) / std::sqrt(1 - wgs84::kPubE2 * sl * sl);
      const Vec3 up(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), sl);
      worst_g = std::max(worst_g, std::fabs(gt.norm() - som));
      worst_u = std::max(worst_u, std::fabs(s.potential + f.centrifugal_potential(r) - wgs84::kPubU0));
      worst_dir = std::max(worst_dir, gt.normalized().cross(-up).norm());
    }
  std::printf("  |gamma| - Somigliana: %.2Le m/s^2; U - U0: %.2Le m^2/s^2; angle to ellipsoid normal %.2Le rad\n", worst_g,
              worst_u, worst_dir);
  assert_true(worst_g < 1e-10L);    // published gamma_e has 10 decimals
  assert_true(worst_u < 1e-4L);     // published U0 has 4 decimals
  assert_true(worst_dir < 1e-15L);  // exact property of the level ellipsoid
}

// Gravitation only: at the equator on the ellipsoid |G| = gamma_e + w^2 a.
static void test_no_centrifugal(void**) {
  const NormalField f;
  const FieldSample s = f.eval(Vec3(wgs84::kA, 0, 0));
  const Real expect = wgs84::kPubGammaE + wgs84::kOmega * wgs84::kOmega * wgs84::kA;
  assert_true(std::fabs(s.g.norm() - expect) < 1e-10L);
  assert_true(std::fabs(s.g.y()) < 1e-25L && std::fabs(s.g.z()) < 1e-25L);
}

// Independent formulation: V = GM/r [1 - sum_n J2n (a/r)^2n P2n(sin psi)] with
// J2n = (-1)^(n+1) 3 e^2n / ((2n+1)(2n+3)) (1 - n + 5n J2/e^2)
// (Heiskanen & Moritz 1967 eq. (2-92)), J2 = -sqrt(5) * published C20,
// P2n by Bonnet's recursion. Valid outside the sphere r > E.
static Real zonal_series_v(const Vec3& r) {
  const Real a = wgs84::kA, gm = wgs84::kGm, e2 = wgs84::kE2;
  const Real j2 = -std::sqrt(5.0L) * wgs84::kPubC20;
  const Real rr = r.norm(), t = r.z() / rr;
  std::vector<Real> p(42);
  p[0] = 1; p[1] = t;
  for (int n = 1; n < 41; ++n) p[n + 1] = ((2 * n + 1) * t * p[n] - n * p[n - 1]) / (n + 1);
  Real sum = 0, e2n = 1, ar2n = 1;
  for (int n = 1; n <= 20; ++n) {
    e2n *= e2;
    ar2n *= (a / rr) * (a / rr);
    const Real j2n = ((n % 2) ? 1 : -1) * 3 * e2n / ((2 * n + 1) * (2 * n + 3)) * (1 - n + 5 * n * j2 / e2);
    sum += j2n * ar2n * p[2 * n];
  }
  return gm / rr * (1 - sum);
}

static void test_against_zonal_series(void**) {
  const NormalField f;
  Real worst_v = 0, worst_g = 0;
  for (Real lat : {0.0L, 23.0L, 45.0L, 67.0L, 90.0L, -33.0L})
    for (Real h : {0.0L, 10e3L, 400e3L, 20000e3L}) {
      const Vec3 r = wgs84::geodetic_to_ecef(lat * kDeg, 0.4L, h);
      const FieldSample s = f.eval(r);
      worst_v = std::max(worst_v, std::fabs(s.potential - zonal_series_v(r)));
      for (int k = 0; k < 3; ++k)
        worst_g = std::max(worst_g, std::fabs(gt::fd4(zonal_series_v, r, k, 20.0L) - s.g[k]));
    }
  std::printf("  closed form vs zonal series: V %.2Le m^2/s^2, G %.2Le m/s^2\n", worst_v, worst_g);
  assert_true(worst_v < 1e-7L);   // published C20 to 12 digits: 5e-16 * GM/a
  assert_true(worst_g < 2e-11L);
}

// Normalised C20 of the field, extracted by quadrature (gt::normal_c20), equals
// the published WGS-84 value -0.484166774985e-3 (TR8350.2 ch. 3, table of derived physical constants).
static void test_c20_published(void**) {
  const Real c20 = gt::normal_c20();
  std::printf("  C20 of the normal field %.15Le, published %.15Le, diff %.2Le\n", c20, wgs84::kPubC20, c20 - wgs84::kPubC20);
  assert_true(std::fabs(c20 - wgs84::kPubC20) < 2e-15L);
}

// J2 of the level ellipsoid from its defining constants, H&M eq. (2-90), as
// used by subtract_normal(), equals the published one (-sqrt(5) C20).
static void test_j2_formula(void**) {
  const Real pub = -std::sqrt(5.0L) * wgs84::kPubC20;
  std::printf("  J2 from (2-90) %.15Le, published %.15Le\n", normal_j2n(1), pub);
  assert_true(std::fabs(normal_j2n(1) - pub) < 1e-17L);
}

static void test_fd_laplace(void**) {
  const NormalField f;
  Real wg = 0, wgam = 0, wtr = 0, was = 0;
  for (Real lat : {0.0L, 35.0L, -60.0L, 89.99L, 90.0L})
    for (Real h : {0.0L, 3000.0L, 400e3L, 35786e3L}) {
      const gt::FdErrors e = gt::fd_check(f, wgs84::geodetic_to_ecef(lat * kDeg, 2.0L, h), 20.0L, 20.0L);
      wg = std::max(wg, e.g); wgam = std::max(wgam, e.gamma); wtr = std::max(wtr, e.trace); was = std::max(was, e.asym);
    }
  std::printf("  normal fd: g %.2Le m/s^2, Gamma %.2Le E, trace %.2Le E, asym %.2Le E\n", wg, wgam * 1e9L, wtr * 1e9L, was * 1e9L);
  assert_true(wg < 2e-12L);
  assert_true(wgam < 1e-18L);  // 1e-9 E
  assert_true(wtr < 1e-20L);  // 1e-11 E
  assert_true(was < 1e-20L);
}

// Third derivatives (zonal series to degree 20) against FD of the closed-form Gamma.
static void test_third(void**) {
  const NormalField f;
  Real worst = 0, scale = 0;
  bool ok = false;
  for (Real lat : {0.0L, 40.0L, 90.0L})
    worst = std::max(worst, gt::third_fd_check(f, wgs84::geodetic_to_ecef(lat * kDeg, 1.0L, 5000), 50.0L, scale, ok));
  std::printf("  third derivatives vs fd of Gamma: %.2Le of %.2Le s^-2/m\n", worst, scale);
  assert_true(ok);
  assert_true(worst < 1e-8L * scale);
}

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_somigliana_u0_direction), cmocka_unit_test(test_no_centrifugal),
      cmocka_unit_test(test_against_zonal_series),    cmocka_unit_test(test_c20_published),
      cmocka_unit_test(test_j2_formula),              cmocka_unit_test(test_fd_laplace),
      cmocka_unit_test(test_third),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
