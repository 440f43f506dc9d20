// Spherical-harmonic engine without data files: a synthetic degree-360 model
// whose exact field is known in closed form (three point masses, two of them
// off-centre), the readers on small handwritten files, and derivatives.
#include "test_util.hpp"

#include "ggins/gravity/spherical_harmonic.hpp"

#include <cstdlib>
#include <fstream>
#include <vector>

using namespace ggins::gravity;

namespace {

const Real kA = 6378137.0L, kGm = 3.986004418e14L;
// Masses: central GM; m1 = 1e-3 GM on the equator at 0.85 a, longitude 0.7 rad;
// m2 = -5e-4 GM on the +z axis at 0.8 a.
const Real kS1 = 0.85L * kA, kLon1 = 0.7L, kGm1 = 1e-3L * kGm;
const Real kS2 = 0.80L * kA, kGm2 = -5e-4L * kGm;

// Pbar_nm(0) in closed form: P_nm(0) = (-1)^((n-m)/2) (n+m-1)!!/(n-m)!! for n+m
// even, 0 otherwise (no Condon-Shortley phase), times the full normalisation
// sqrt((2-delta_m0)(2n+1)(n-m)!/(n+m)!); evaluated with lgamma.
Real pbar_equator(int n, int m) {
  if ((n + m) % 2) return 0;
  const Real lg = 0.5L * std::log((m == 0 ? 1.0L : 2.0L) * (2 * n + 1)) + 0.5L * std::lgamma(n - m + 1.0L) +
                  0.5L * std::lgamma(n + m + 1.0L) - n * std::log(2.0L) - std::lgamma((n + m) / 2 + 1.0L) -
                  std::lgamma((n - m) / 2 + 1.0L);
  return (((n - m) / 2) % 2 ? -1.0L : 1.0L) * std::exp(lg);
}

// Addition theorem: 1/|r - s| = (1/a) sum (a/r)^(n+1) (s/a)^n / (2n+1) sum_m Pbar_nm(t) Pbar_nm(t') cos m(l - l').
ShCoefficients synthetic(int nmax) {
  ShCoefficients k;
  k.gm = kGm; k.a = kA; k.source = "synthetic";
  k.resize(nmax);
  k.c[0] = 1;
  for (int n = 0; n <= nmax; ++n) {
    const Real q1 = std::pow(kS1 / kA, static_cast<Real>(n)) / (2 * n + 1) * (kGm1 / kGm);
    for (int m = 0; m <= n; ++m) {
      const Real p = pbar_equator(n, m);
      k.c[ShCoefficients::idx(n, m)] += q1 * p * std::cos(m * kLon1);
      k.s[ShCoefficients::idx(n, m)] += q1 * p * std::sin(m * kLon1);
    }
    // Pbar_n0(1) = sqrt(2n+1)
    k.c[ShCoefficients::idx(n, 0)] += std::pow(kS2 / kA, static_cast<Real>(n)) / std::sqrt(2.0L * n + 1) * (kGm2 / kGm);
  }
  return k;
}

FieldSample truth(const Vec3& r) {
  const PointMassField c(kGm), f1(kGm1), f2(kGm2);
  const Vec3 s1(kS1 * std::cos(kLon1), kS1 * std::sin(kLon1), 0), s2(0, 0, kS2);
  FieldSample a = c.eval(r), b = f1.eval(r - s1), d = f2.eval(r - s2);
  a.potential += b.potential + d.potential;
  a.g += b.g + d.g;
  a.gamma += b.gamma + d.gamma;
  return a;
}

std::vector<Vec3> test_points() {
  return {Vec3(kA, 0, 0) * 1.0L,                                       // equator, lon 0
          Vec3(kA * std::cos(0.7L), kA * std::sin(0.7L), 0) * 1.02L,  // above mass 1 (slowest convergence)
          Vec3(0, 0, kA * 1.01L),                                     // exactly over the north pole (mass 2 below)
          Vec3(0, 0, -kA * 1.0L),                                     // south pole
          Vec3(1e-7L, -2e-7L, kA * 1.01L),                            // 0.2 um off the pole axis
          Vec3(-3.1e6L, 2.2e6L, -5.1e6L), Vec3(4.0e6L, -4.0e6L, 3.3e6L)};
}

}  // namespace

// Degree 360 against the closed-form field of the three masses.
static void test_synthetic_degree360(void**) {
  const SphericalHarmonicField f(synthetic(360));
  Real ev = 0, eg = 0, eG = 0;
  for (const Vec3& r : test_points()) {
    const FieldSample s = f.eval(r), t = truth(r);
    ev = std::max(ev, std::fabs(s.potential - t.potential));
    eg = std::max(eg, (s.g - t.g).cwiseAbs().maxCoeff());
    eG = std::max(eG, (s.gamma - t.gamma).cwiseAbs().maxCoeff());
  }
  std::printf("  synthetic n=360 vs closed form: V %.2Le m^2/s^2, G %.2Le m/s^2, Gamma %.2Le E\n", ev, eg, eG * 1e9L);
  assert_true(ev < 1e-10L);
  assert_true(eg < 1e-16L);
  assert_true(eG < 1e-22L);  // 1e-13 E
}

// Finite differences, symmetry, Laplace on the same model (the trace is zero
// by construction of the ladder sums, so this checks the assembly only).
static void test_fd(void**) {
  const SphericalHarmonicField f(synthetic(360));
  Real wg = 0, wG = 0, wtr = 0, was = 0;
  for (const Vec3& r : test_points()) {
    const gt::FdErrors e = gt::fd_check(f, r, 20.0L, 20.0L);
    wg = std::max(wg, e.g); wG = std::max(wG, e.gamma); wtr = std::max(wtr, e.trace); was = std::max(was, e.asym);
  }
  std::printf("  synthetic fd: g %.2Le m/s^2, Gamma %.2Le E, trace %.2Le E, asym %.2Le E\n", wg, wG * 1e9L, wtr * 1e9L, was * 1e9L);
  assert_true(wg < 2e-12L);
  assert_true(wG < 1e-18L);
  assert_true(wtr < 1e-21L);
  assert_true(was == 0);
}

// Third derivatives against finite differences of Gamma.
static void test_third_derivatives(void**) {
  const SphericalHarmonicField f(synthetic(120), -1, 3);
  Real worst = 0, scale = 0;
  for (const Vec3& r : test_points()) {
    const auto d = f.derivatives(r, 3);
    for (int k = 0; k < 3; ++k) {
      const Mat3 dG = gt::fd4([&](const Vec3& x) -> Mat3 { return f.eval(x).gamma; }, r, k, 50.0L);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          int ix[3] = {0, 0, 0};
          ++ix[i]; ++ix[j]; ++ix[k];
          const Real v = d[3].at(ix[0], ix[1], ix[2]);
          worst = std::max(worst, std::fabs(v - dG(i, j)));
          scale = std::max(scale, std::fabs(v));
        }
    }
  }
  std::printf("  third derivatives vs fd of Gamma: %.2Le s^-2/m (max |T| %.2Le)\n", worst, scale);
  assert_true(worst < 1e-9L * scale);
  // the Field::third member agrees with the closed-form third derivatives of the three masses
  const SphericalHarmonicField f360(synthetic(360), -1, 3);
  Real wt = 0, st = 0;
  for (const Vec3& r : test_points()) {
    Tensor3 a, b;
    for (Mat3& m : b) m.setZero();
    assert_true(f360.third(r, a));
    Tensor3 c0, c1, c2;
    const PointMassField c(kGm), f1(kGm1), f2(kGm2);
    const Vec3 s1(kS1 * std::cos(kLon1), kS1 * std::sin(kLon1), 0), s2(0, 0, kS2);
    c.third(r, c0); f1.third(r - s1, c1); f2.third(r - s2, c2);
    for (int k = 0; k < 3; ++k) {
      wt = std::max(wt, (a[k] - c0[k] - c1[k] - c2[k]).cwiseAbs().maxCoeff());
      st = std::max(st, a[k].cwiseAbs().maxCoeff());
    }
  }
  std::printf("  n=360 third derivatives vs closed form: %.2Le of %.2Le s^-2/m\n", wt, st);
  assert_true(wt < 1e-12L * st);
}

// C00 = 1 alone is exactly the point-mass field.
static void test_degree0_is_point_mass(void**) {
  ShCoefficients k;
  k.gm = kGm; k.a = kA; k.resize(4); k.c[0] = 1;
  const SphericalHarmonicField f(k);
  const PointMassField p(kGm);
  for (const Vec3& r : test_points()) {
    const FieldSample a = f.eval(r), b = p.eval(r);
    assert_true(std::fabs(a.potential - b.potential) < 1e-11L);
    assert_true((a.g - b.g).cwiseAbs().maxCoeff() < 1e-17L);
    assert_true((a.gamma - b.gamma).cwiseAbs().maxCoeff() < 1e-23L);
  }
}

static std::string tmpfile(const std::string& name, const std::string& text) {
  const char* d = std::getenv("TMPDIR");
  const std::string p = std::string(d ? d : "/tmp") + "/ggins_gravity_" + name;
  std::ofstream(p) << text;
  return p;
}

static void test_readers(void**) {
  const std::string nasa = tmpfile("nasa.txt",
                                   "   2   0 -0.484165371736E-03  0.000000000000E+00  0.35610635E-10  0.00000000E+00\n"
                                   "   2   1 -0.186987635955D-09  0.119528012031D-08  0.10000000E-29  0.10000000E-29\n"
                                   "\n"
                                   "   3   3  0.100000000000E-05 -0.200000000000E-05  0  0\n");
  const ShCoefficients a = read_nasa_ascii(nasa);
  assert_int_equal(a.nmax, 3);
  assert_true(a.C(0, 0) == 1 && a.C(1, 0) == 0);
  assert_true(a.C(2, 0) == -0.484165371736E-03L);
  assert_true(a.S(2, 1) == 0.119528012031E-08L && a.C(2, 1) == -0.186987635955E-09L);
  assert_true(a.sigma_c[ShCoefficients::idx(2, 0)] == 0.35610635E-10L);
  assert_true(a.C(3, 3) == 0.1E-05L && a.S(3, 3) == -0.2E-05L && a.C(3, 1) == 0);
  assert_true(a.gm == kEgm96Gm && a.a == kEgm96A);
  assert_int_equal(read_nasa_ascii(nasa, kGm, kA, 2).nmax, 2);

  const std::string gfc = tmpfile("model.gfc",
                                  "generating_institute  test\n"
                                  "product_type          gravity_field\n"
                                  "modelname             tiny\n"
                                  "earth_gravity_constant  0.3986004415E+15\n"
                                  "radius                0.63781363E+07\n"
                                  "max_degree            3\n"
                                  "errors                formal\n"
                                  "norm                  fully_normalized\n"
                                  "tide_system           tide_free\n"
                                  "\n"
                                  "key     L    M         C                  S                sigma C      sigma S\n"
                                  "end_of_head ==================================================================\n"
                                  "gfc     0    0  1.000000000000D+00  0.000000000000D+00  0.0000D+00  0.0000D+00\n"
                                  "gfc     2    0 -0.484165371736D-03  0.000000000000D+00  0.3561D-10  0.0000D+00\n"
                                  "gfc     3    2  0.904787894809D-06 -0.619005475177D-06  0.1D-29  0.2D-29\n");
  const ShCoefficients b = read_icgem_gfc(gfc);
  assert_int_equal(b.nmax, 3);
  assert_true(b.gm == 0.3986004415E+15L && b.a == 0.63781363E+07L);
  assert_true(b.C(0, 0) == 1 && b.C(2, 0) == -0.484165371736E-03L);
  assert_true(b.C(3, 2) == 0.904787894809E-06L && b.S(3, 2) == -0.619005475177E-06L);
  assert_true(b.sigma_s[ShCoefficients::idx(3, 2)] == 0.2E-29L);
  assert_int_equal(read_icgem_gfc(gfc, 2).nmax, 2);

  const std::string tv = tmpfile("tv.gfc",
                                 "earth_gravity_constant 3.986004415e14\nradius 6378136.3\nmax_degree 2\n"
                                 "norm fully_normalized\nerrors no\nend_of_head\n"
                                 "gfct 2 0 -0.48e-3 0 20000101\n");
  bool threw = false;
  try { (void)read_icgem_gfc(tv); } catch (const std::runtime_error&) { threw = true; }
  assert_true(threw);
  threw = false;
  try { (void)read_nasa_ascii(tmpfile("bad.txt", "2 3 1.0 0.0\n")); } catch (const std::runtime_error&) { threw = true; }
  assert_true(threw);
}

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_synthetic_degree360), cmocka_unit_test(test_fd), cmocka_unit_test(test_third_derivatives),
      cmocka_unit_test(test_degree0_is_point_mass), cmocka_unit_test(test_readers),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
