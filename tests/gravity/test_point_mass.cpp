// PointMassField: against hand-derived values and finite differences.
#include "test_util.hpp"

#include "ggins/gravity/field.hpp"

using namespace ggins::gravity;

// On the x axis at r: V = GM/r, G = (-GM/r^2, 0, 0), Gamma = GM/r^3 diag(2, -1, -1)
// (docs/design.md: Gamma = w_s^2 (3 r^ r^T - I)). Numbers typed from the formula, not the code.
static void test_axis_values(void**) {
  const PointMassField f(3.986004418e14L);
  const Real r = 7.0e6L;
  const FieldSample s = f.eval(Vec3(r, 0, 0));
  const Real gm = 3.986004418e14L;
  assert_true(std::fabs(s.potential - gm / r) < 1e-9L);
  assert_true(std::fabs(s.g.x() + gm / (r * r)) < 1e-16L);
  assert_true(std::fabs(s.g.y()) == 0 && std::fabs(s.g.z()) == 0);
  const Real k = gm / (r * r * r);
  assert_true(std::fabs(s.gamma(0, 0) - 2 * k) < 1e-22L);
  assert_true(std::fabs(s.gamma(1, 1) + k) < 1e-22L);
  assert_true(std::fabs(s.gamma(2, 2) + k) < 1e-22L);
  // Known magnitude: at r = 7000 km, |G| = 8.1347...: GM/r^2 = 3.986004418e14/4.9e13
  assert_true(std::fabs(s.g.norm() - 8.13470289387755102L) < 1e-12L);
}

// Gamma against finite differences of G, G against finite differences of V,
// Laplace and symmetry, at points in all octants and over a pole.
static void test_fd_laplace(void**) {
  const PointMassField f;
  const Vec3 pts[] = {Vec3(6.4e6L, 1.0e5L, -2.0e5L), Vec3(-3.0e6L, 5.0e6L, 2.5e6L), Vec3(0, 0, 6.36e6L),
                      Vec3(1.0e3L, -2.0e3L, -6.4e6L), Vec3(4.2e7L, 0, 0)};
  for (const Vec3& r : pts) {
    const gt::FdErrors e = gt::fd_check(f, r, 20.0L, 20.0L);
    std::printf("  point-mass fd at |r|=%.0Lf: g %.2Le m/s^2, Gamma %.2Le E, trace %.2Le E, asym %.2Le E\n", r.norm(), e.g,
                e.gamma * 1e9L, e.trace * 1e9L, e.asym * 1e9L);
    assert_true(e.g < 2e-12L);       // rounding of V ~ 6e7 * 1e-19 / h
    assert_true(e.gamma < 1e-18L);   // 1e-9 E
    assert_true(e.trace < 1e-21L);
    assert_true(e.asym == 0);
  }
}

// Third derivatives (optional Field member) against FD of Gamma.
static void test_third(void**) {
  const PointMassField f;
  Real worst = 0, scale = 0;
  bool ok = false;
  for (const Vec3& r : {Vec3(6.4e6L, 1.0e5L, -2.0e5L), Vec3(-3.0e6L, 5.0e6L, 2.5e6L), Vec3(0, 0, 6.36e6L)})
    worst = std::max(worst, gt::third_fd_check(f, r, 50.0L, scale, ok));
  std::printf("  third derivatives vs fd: %.2Le of %.2Le s^-2/m\n", worst, scale);
  assert_true(ok);
  assert_true(worst < 1e-8L * scale);
}

static void test_rejects_centre(void**) {
  const PointMassField f;
  bool threw = false;
  try { (void)f.eval(Vec3::Zero()); } catch (const std::domain_error&) { threw = true; }
  assert_true(threw);
}

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_axis_values),
      cmocka_unit_test(test_fd_laplace),
      cmocka_unit_test(test_third),
      cmocka_unit_test(test_rejects_centre),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
