// Fast path for EGM96 to degree 360: WGS-84 normal field exactly plus the
// disturbing field (subtract_normal(EGM96), double-precision synthesis at the
// nodes) on a lattice (h 2.5 km, p 8), against the
// direct degree-360 evaluation at random points. Requirement: 1e-13 m/s^2 in
// G and 1e-4 E in Gamma. Skipped without data/egm96_to360.ascii.txt.
#include "test_util.hpp"

#include "ggins/gravity/lattice.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <random>

using namespace ggins::gravity;
static const Real kDeg = static_cast<Real>(M_PI) / 180;

static void test_fast_vs_direct(void**) {
  const auto sh = std::make_shared<SphericalHarmonicField>(read_nasa_ascii(gt::egm96_path()), 360);
  const auto normal = std::make_shared<NormalField>();
  const auto anomaly = std::make_shared<SphericalHarmonicField>(subtract_normal(sh->coefficients()), 360, 2, ShPrecision::Double);
  LatticeOptions o;
  o.spacing = 2500; o.points = 8;
  const FastField fast(normal, anomaly, o);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 4999);
  Real eg = 0, eG = 0, ev = 0;
  // Two boxes: mid-latitude at 3 km (rough terrain, Appalachians) and near the pole at 10 km.
  for (const Vec3& c : {wgs84::geodetic_to_ecef(35.5L * kDeg, -82.5L * kDeg, 3000), wgs84::geodetic_to_ecef(89.98L * kDeg, 0, 10000)})
    for (int i = 0; i < 6; ++i) {
      const Vec3 r = c + Vec3(u(rng), u(rng), u(rng));
      const FieldSample a = fast.eval(r), b = sh->eval(r);
      ev = std::max(ev, std::fabs(a.potential - b.potential));
      eg = std::max(eg, (a.g - b.g).cwiseAbs().maxCoeff());
      eG = std::max(eG, (a.gamma - b.gamma).cwiseAbs().maxCoeff());
    }
  std::printf("  EGM96 n=360 fast path (h 2.5 km, p 8): max error V %.2Le m^2/s^2, G %.2Le m/s^2, Gamma %.2Le E\n", ev, eg, eG * 1e9L);
  assert_true(eg < 1e-13L);
  assert_true(eG < 1e-13L);  // 1e-4 E
}

int main() {
  if (!gt::have_file(gt::egm96_path())) {
    std::printf("SKIP: %s absent; run scripts/fetch-egm96\n", gt::egm96_path().c_str());
    return gt::kSkip;
  }
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_fast_vs_direct)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
