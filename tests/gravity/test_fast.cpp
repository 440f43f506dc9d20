// Fast path: lattice interpolation (exactness on polynomials, thread safety)
// and the Ewald-split point-mass anomaly field against the exact sum.
#include "test_util.hpp"

#include "ggins/gravity/composite.hpp"
#include "ggins/gravity/lattice.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <random>
#include <thread>

using namespace ggins::gravity;

namespace {
// A polynomial "field" of degree 7 in each variable's total degree <= 7 (not
// harmonic: the lattice does not care), with hand-written derivatives.
class PolyField final : public Field {
 public:
  FieldSample eval(const Vec3& r) const override {
    const Real x = r.x() * 1e-4L, y = r.y() * 1e-4L, z = r.z() * 1e-4L, s = 1e-4L;
    FieldSample f;
    f.potential = x * x * x * y - 2 * z * z * x + std::pow(y, 7) + 3 * x * y * z;
    f.g = s * Vec3(3 * x * x * y - 2 * z * z + 3 * y * z, x * x * x + 7 * std::pow(y, 6) + 3 * x * z, -4 * z * x + 3 * x * y);
    f.gamma << 6 * x * y, 3 * x * x + 3 * z, -4 * z + 3 * y,
               3 * x * x + 3 * z, 42 * std::pow(y, 5), 3 * x,
               -4 * z + 3 * y, 3 * x, -4 * x;
    f.gamma *= s * s;
    return f;
  }
  std::string name() const override { return "poly"; }
};
}  // namespace

// p = 8 Lagrange interpolation reproduces polynomials of degree 7 exactly.
static void test_polynomial_exact(void**) {
  LatticeOptions o;
  o.spacing = 700; o.points = 8; o.origin = Vec3(-1234.5L, 17, 3);
  const auto src = std::make_shared<PolyField>();
  const LatticeField lf(src, o);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3000, 3000);
  Real ev = 0, eg = 0, eG = 0;
  for (int i = 0; i < 50; ++i) {
    const Vec3 r(u(rng), u(rng), u(rng));
    const FieldSample a = lf.eval(r), b = src->eval(r);
    ev = std::max(ev, std::fabs(a.potential - b.potential));
    eg = std::max(eg, (a.g - b.g).cwiseAbs().maxCoeff());
    eG = std::max(eG, (a.gamma - b.gamma).cwiseAbs().maxCoeff());
  }
  std::printf("  degree-7 polynomial through p=8 lattice: V %.2Le, g %.2Le, Gamma %.2Le\n", ev, eg, eG);
  assert_true(ev < 1e-12L && eg < 1e-16L && eG < 1e-20L);
  // A degree-8 term is NOT reproduced (the test can fail).
  class Poly8 final : public Field {
   public:
    FieldSample eval(const Vec3& r) const override { FieldSample f; f.potential = std::pow(r.x() * 1e-3L, 8); return f; }
    std::string name() const override { return "x^8"; }
  };
  const LatticeField l8(std::make_shared<Poly8>(), o);
  assert_true(std::fabs(l8.eval(Vec3(350, 0, 0)).potential - std::pow(0.35L, 8)) > 1e-6L);
}

static std::shared_ptr<PointMassAnomalyField> rw_field() {
  RwAnomalyConfig cfg;
  cfg.half_size = 150e3L;
  return std::make_shared<PointMassAnomalyField>(make_rubenstein_winter_field(cfg));
}

// Normal (exact) + split point masses (short range exact, long range on a
// lattice, sigma 8 km, h 1 km, p 12) against normal + the exact sum, at random
// points in boxes at 0, 1 km and 10 km height (the shallowest masses are
// 3.06 km deep). Requirement: 1e-13 m/s^2 in G, 1e-4 E in Gamma.
static void test_split_point_masses(void**) {
  const auto exact = rw_field();
  const auto normal = std::make_shared<NormalField>();
  const RwAnomalyConfig cfg;
  LatticeOptions o;
  o.spacing = 1000; o.points = 12; o.origin = wgs84::geodetic_to_ecef(cfg.lat0, cfg.lon0, 0);
  const FastField fast(normal, std::make_shared<SplitPointMassField>(exact->masses(), 8000, o));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 2500);
  Real eg = 0, eG = 0;
  for (Real h : {0.0L, 1000.0L, 10000.0L}) {
    const Vec3 c = wgs84::geodetic_to_ecef(cfg.lat0 + 0.001L, cfg.lon0 - 0.002L, h);
    for (int i = 0; i < 10; ++i) {
      const Vec3 r = c + Vec3(u(rng), u(rng), u(rng));
      const FieldSample a = fast.eval(r), n = normal->eval(r), x = exact->eval(r);
      eg = std::max(eg, (a.g - n.g - x.g).cwiseAbs().maxCoeff());
      eG = std::max(eG, (a.gamma - n.gamma - x.gamma).cwiseAbs().maxCoeff());
    }
  }
  std::printf("  split point masses (%zu masses): max error G %.2Le m/s^2, Gamma %.2Le E\n", exact->masses().size(), eg, eG * 1e9L);
  assert_true(eg < 1e-13L);
  assert_true(eG < 1e-13L);  // 1e-4 E
}

// Concurrent evaluation from two threads equals serial evaluation.
static void test_threads(void**) {
  const auto exact = rw_field();
  LatticeOptions o;
  o.spacing = 1000; o.points = 12;
  const SplitPointMassField f(exact->masses(), 8000, o);
  const RwAnomalyConfig cfg;
  const Vec3 c = wgs84::geodetic_to_ecef(cfg.lat0, cfg.lon0, 2000);
  std::vector<Vec3> pts;
  for (int i = 0; i < 40; ++i) pts.push_back(c + Vec3(97.0L * i, -31.0L * i, 13.0L * i));
  std::vector<FieldSample> a(pts.size()), b(pts.size());
  std::thread t1([&] { for (std::size_t i = 0; i < pts.size(); i += 2) a[i] = f.eval(pts[i]); });
  std::thread t2([&] { for (std::size_t i = 1; i < pts.size(); i += 2) a[i] = f.eval(pts[i]); });
  t1.join(); t2.join();
  for (std::size_t i = 0; i < pts.size(); ++i) b[i] = f.eval(pts[i]);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    assert_true(a[i].g == b[i].g);
    assert_true(a[i].gamma == b[i].gamma);
  }
}

// gravitation() is eval().g with the Hessian work left out: the same bits for
// every model that overrides it (normal field, spherical harmonics in the three
// precisions, sums, lattices and the fast path), near the surface and near a pole.
static void test_gravitation_same_bits(void**) {
  const auto normal = std::make_shared<NormalField>();
  const ShCoefficients k = synthetic_kaula(60, 3);
  std::vector<std::shared_ptr<const Field>> fields = {normal};
  for (ShPrecision p : {ShPrecision::LongDouble, ShPrecision::Double, ShPrecision::Mixed})
    fields.push_back(std::make_shared<SphericalHarmonicField>(k, 60, 2, p));
  const auto dist = std::make_shared<SphericalHarmonicField>(subtract_normal(k), 60, 2, ShPrecision::Double);
  fields.push_back(std::make_shared<SumField>(std::vector<std::pair<Real, std::shared_ptr<const Field>>>{{1.0L, normal}, {1.0L, dist}}));
  LatticeOptions o;
  o.spacing = 2500; o.points = 8; o.origin = wgs84::geodetic_to_ecef(0.6L, 0.2L, 3000);
  fields.push_back(std::make_shared<FastField>(normal, dist, o));
  int n = 0;
  for (const auto& f : fields)
    for (Real lat : {0.6L, 0.6001L, 1.5707L})
      for (Real h : {0.0L, 3000.0L}) {
        if (lat > 1.5L && std::string(f->name()).rfind("fast", 0) == 0) continue;  // keep the lattice near its origin
        const Vec3 r = wgs84::geodetic_to_ecef(lat, 0.2L, h);
        assert_true(f->gravitation(r) == f->eval(r).g);
        ++n;
      }
  std::printf("  gravitation() == eval().g bit for bit at %d model-point pairs\n", n);
}

int main() {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_polynomial_exact), cmocka_unit_test(test_split_point_masses),
                                     cmocka_unit_test(test_threads), cmocka_unit_test(test_gravitation_same_bits)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
