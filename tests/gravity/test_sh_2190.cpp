// Degree 2190 (the degree of EGM2008) on a synthetic Kaula-rule model, and
// the coefficient readers at full degree and on malformed files.
//  - the model written as an ICGEM .gfc file and read back: every coefficient,
//    GM, radius and tide system exact;
//  - double (Mixed) against long double synthesis: rounding only (long
//    double's exponent range needs no scaling; double relies on H&F's 1e-280);
//  - Gamma against 4th-order central differences of G, G against differences
//    of V (the independent check of the derivative assembly at this degree;
//    V and G are compared with pyshtools by gravity.pyshtools_2190).
//  - malformed files: the error names the file and line.
#include "test_util.hpp"

#include "ggins/gravity/spherical_harmonic.hpp"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <stdexcept>
#include <string>

using namespace ggins::gravity;

static std::string tmp(const std::string& name) {
  const char* d = std::getenv("TMPDIR");
  return std::string(d ? d : "/tmp") + "/ggins_gravity_" + name;
}

static double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static const int kN = 2190;
static ShCoefficients g_k;

static void test_gfc_roundtrip(void**) {
  const std::string p = tmp("kaula2190.gfc");
  FILE* f = std::fopen(p.c_str(), "w");
  assert_non_null(f);
  std::fprintf(f, "product_type gravity_field\nmodelname kaula\nearth_gravity_constant %.10Le\nradius %.4Lf\nmax_degree %d\n"
                  "norm fully_normalized\ntide_system zero_tide\nerrors no\n\nkey n m C S\nend_of_head =====\n",
               g_k.gm, g_k.a, kN);
  for (int n = 0; n <= kN; ++n)
    for (int m = 0; m <= n; ++m) std::fprintf(f, "gfc %d %d %.20Le %.20Le\n", n, m, g_k.C(n, m), g_k.S(n, m));
  std::fclose(f);
  const double t0 = cpu_s();
  const ShCoefficients b = read_icgem_gfc(p);
  std::printf("  read %d coefficient pairs in %.2f s CPU\n", static_cast<int>(b.c.size()), cpu_s() - t0);
  std::remove(p.c_str());
  assert_int_equal(b.nmax, kN);
  assert_true(b.gm == g_k.gm && b.a == g_k.a && b.tide_system == "zero_tide");
  std::size_t bad = 0;
  for (std::size_t i = 0; i < b.c.size(); ++i) bad += (b.c[i] != g_k.c[i]) + (b.s[i] != g_k.s[i]);
  assert_int_equal(bad, 0);
  // to_tide_system: EGM2008's published C20, tide free -0.484165143790815e-3 and
  // zero tide -0.484169317366974e-3 (Pavlis et al. 2012), differ by the IERS offset.
  ShCoefficients e = g_k.truncated(2);
  e.tide_system = "tide_free";
  e.c[ShCoefficients::idx(2, 0)] = -0.484165143790815e-3L;
  const ShCoefficients z = to_tide_system(e, "zero_tide");
  std::printf("  tide free -> zero tide C20 %.15Le (EGM2008 zero tide -0.484169317366974e-3)\n", z.C(2, 0));
  assert_true(std::fabs(z.C(2, 0) - (-0.484169317366974e-3L)) < 1e-13L);
  assert_true(std::fabs(to_tide_system(z, "tide_free").C(2, 0) - e.C(2, 0)) < 1e-20L);
}

static void test_degree2190(void**) {
  const SphericalHarmonicField fl(g_k, kN, 2, ShPrecision::LongDouble), fm(g_k, kN, 2, ShPrecision::Mixed);
  const Real a = g_k.a;
  const Vec3 pts[] = {Vec3(a + 1000, 0, 0), (a + 300) * Vec3(0.3L, -0.5L, 0.8124L).normalized(),
                      (a + 5000) * Vec3(0.01L, 0.02L, -1).normalized(), Vec3(0, 0, a + 2000)};
  Real ev = 0, eg = 0, eG = 0, fg = 0, fG = 0, tr = 0, gmax = 0, Gmax = 0;
  double tl = 0, tm = 0;
  for (const Vec3& r : pts) {
    double t0 = cpu_s();
    const FieldSample l = fl.eval(r);
    tl += cpu_s() - t0;
    t0 = cpu_s();
    const FieldSample m = fm.eval(r);
    tm += cpu_s() - t0;
    ev = std::max(ev, std::fabs(l.potential - m.potential));
    eg = std::max(eg, (l.g - m.g).cwiseAbs().maxCoeff());
    eG = std::max(eG, (l.gamma - m.gamma).cwiseAbs().maxCoeff());
    const Vec3 g0 = fl.eval(r).g + PointMassField(g_k.gm).eval(r).g * -1;  // disturbance
    gmax = std::max(gmax, g0.cwiseAbs().maxCoeff());
    Gmax = std::max(Gmax, (l.gamma - PointMassField(g_k.gm).eval(r).gamma).cwiseAbs().maxCoeff());
    // h = 2 m: 4th-order truncation (h^4/30) |d^5 V| ~ (2 pi/18 km)^4 |Gamma| ~ 1e-15 relative
    const gt::FdErrors e = gt::fd_check(fm, r, 2.0L, 2.0L);
    fg = std::max(fg, e.g); fG = std::max(fG, e.gamma); tr = std::max(tr, e.trace);
  }
  // a few metres from the pole axis (where t = z/r in double is off the unit
  // sphere by 1e-16 and Abar_nm(t) is steepest)
  for (Real zs : {1.0L, -1.0L})
    for (Real dx : {2.0L, 10.0L, 1000.0L}) {
      const Vec3 r(dx, -0.5L * dx, zs * (a + 2000));
      const FieldSample l = fl.eval(r), m = fm.eval(r);
      ev = std::max(ev, std::fabs(l.potential - m.potential));
      eg = std::max(eg, (l.g - m.g).cwiseAbs().maxCoeff());
      eG = std::max(eG, (l.gamma - m.gamma).cwiseAbs().maxCoeff());
    }
  std::printf("  n=2190: %.0f ms (long double), %.0f ms (mixed) per point\n", 1e3 * tl / 4, 1e3 * tm / 4);
  std::printf("  mixed vs long double: V %.1Le m^2/s^2, G %.1Le m/s^2, Gamma %.1Le E (disturbance up to %.1Le m/s^2, %.0Lf E)\n", ev, eg,
              eG * 1e9L, gmax, Gmax * 1e9L);
  std::printf("  mixed vs central differences: G %.1Le m/s^2, Gamma %.1Le E, trace %.1Le E\n", fg, fG * 1e9L, tr * 1e9L);
  assert_true(ev < 1e-10L && eg < 2e-15L && eG < 1e-18L);  // double: ~10 eps |G|, 1e-9 E
  assert_true(fg < 3e-11L);    // rounding of V (~1e-11 m^2/s^2) x 18 / (12 h)
  assert_true(fG < 1e-17L);    // 1e-8 E: rounding of G (1e-16) x 18 / (12 h)
  assert_true(tr < 1e-19L);    // 1e-10 E, the rounding of Gamma in double
}

static void expect_error(const std::string& name, const std::string& text, const std::string& want) {
  const std::string p = tmp(name);
  { std::FILE* f = std::fopen(p.c_str(), "w"); std::fputs(text.c_str(), f); std::fclose(f); }
  std::string msg;
  try {
    (void)read_model(p);
  } catch (const std::exception& e) {
    msg = e.what();
  }
  std::remove(p.c_str());
  std::printf("  %s -> %s\n", name.c_str(), msg.c_str());
  assert_true(msg.find(want) != std::string::npos);
}

static void test_malformed(void**) {
  const std::string head = "earth_gravity_constant 3.986004415e14\nradius 6378136.3\nmax_degree 2\nerrors no\nend_of_head\n";
  expect_error("bad_number.gfc", head + "gfc 0 0 1 0\ngfc 2 0 -0.48x-3 0\n", "bad_number.gfc:7: bad C '-0.48x-3'");
  expect_error("order.gfc", head + "gfc 2 3 1 0\n", "order.gfc:6: order 3 above degree 2");
  expect_error("short.gfc", head + "gfc 2 0 1\n", "short.gfc:6: expected 'gfc n m C S'");
  expect_error("deg.gfc", head + "gfc 3 0 1 0\n", "deg.gfc:6: degree 3 above max_degree 2");
  expect_error("nogm.gfc", "radius 6378136.3\nmax_degree 2\nend_of_head\n", "nogm.gfc:3: header lacks earth_gravity_constant");
  expect_error("tide.gfc", "earth_gravity_constant 3.9e14\ntide_system lunar\n", "tide.gfc:2: unknown tide_system 'lunar'");
  expect_error("nan.gfc", head + "gfc 2 0 nan 0\n", "nan.gfc:6: bad C 'nan'");
  expect_error("rec.gfc", head + "gfx 2 0 1 0\n", "rec.gfc:6: unknown record 'gfx'");
  expect_error("nasa.txt", "2 0 -0.48D-03 0\n2 1 1.0 2.0 3.0 4.0 5.0\n", "nasa.txt:2: expected 'n m C S [sigmaC sigmaS]'");
  expect_error("nasa2.txt", "2 0 -0.48D-03 0\n2 -1 1.0 2.0\n", "nasa2.txt:2: bad order '-1'");
}

int main() {
  g_k = synthetic_kaula(kN, 1);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_gfc_roundtrip),
      cmocka_unit_test(test_degree2190),
      cmocka_unit_test(test_malformed),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
