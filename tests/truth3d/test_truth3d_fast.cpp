// The truth generator's fast path (one Field::eval_pairs at the body centre:
// the normal field's "-" sensors from the central difference
// G(r - d) = G(r + d) - 2 Gamma(r) d) against the reference: the field
// evaluated at each accelerometer's own position (Generator3::accel_reference).
// Independent checks:
//  - the dropped term against its closed form for the dominant point-mass part,
//    (fast - exact) . u = 8 GM |d|^3 P4(u . r^) / r^5 (the fourth directional
//    derivative of GM/r is 24 GM P4 / r^5; Legendre's expansion of 1/|r + s u|),
//    to the flattening's share (15 J2 = 1.6 %), with arms of 20-50 m where it
//    dominates the rounding, and the bound
//    NormalField::pair_truncation_bound;
//  - every built-in 3-D scenario and the point-mass and R&W anomaly fields at
//    sampled steps: the "+" sensors equal the reference to the bit, the "-"
//    sensors within the truncation bound (<= 4e-20 m/s^2 for 0.5 m arms) plus
//    the rounding of two long-double evaluations of G (budget 8 ulps of |G|
//    each: 1.7e-17 m/s^2 at 9.8 m/s^2), five orders below the 1e-12 m/s^2
//    accelerometer noise floor; frame() sends the fast-path values.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

using namespace ggins::truth3d;
namespace gr = ggins::gravity;

static int g_fail = 0;
#define CHECK(cond, ...)                               \
  do {                                                 \
    if (!(cond)) {                                     \
      ++g_fail;                                        \
      std::printf("FAIL %s:%d: ", __FILE__, __LINE__); \
      std::printf(__VA_ARGS__);                        \
      std::printf("\n");                               \
    }                                                  \
  } while (0)

// long-double ulp of x (64-bit significand)
static Real ulp(Real x) { return std::ldexp(1.0L, std::ilogb(x) - 63); }

// The dropped cubic term of the central difference, measured with long arms.
static void test_truncation_term() {
  const gr::NormalField f;
  Real worst_rel = 0;
  int n = 0;
  for (Real lat_deg : {0.0L, 37.0L, 80.0L})
    for (Real h : {0.0L, 10000.0L}) {
      const Real lat = lat_deg * kPi / 180;
      const Vec3 r = gr::wgs84::geodetic_to_ecef(lat, 0.6L, h);
      const Vec3 up = r.normalized();
      const Vec3 east = Vec3(0, 0, 1).cross(up).normalized();
      const Vec3 north = up.cross(east);
      for (const Vec3& u : {up, east, north, Vec3((up + east + north).normalized()), Vec3((2 * up - north).normalized())})
        for (Real arm : {20.0L, 50.0L}) {
          const Vec3 d = arm * u;
          Vec3 plus, minus;
          const gr::FieldSample s = f.eval_pairs(r, &d, 1, &plus, &minus);
          const Vec3 exact = f.gravitation(r - d);
          const Vec3 e = minus - exact;
          const Real rn = r.norm(), c = u.dot(r) / rn;
          const Real p4 = (35 * c * c * c * c - 30 * c * c + 3) / 8;
          const Real ex = 8 * f.params().gm * arm * arm * arm * p4 / std::pow(rn, 5);
          const Real bound = f.pair_truncation_bound(r, arm);
          CHECK(plus == f.gravitation(r + d), "eval_pairs: the + point is gravitation() itself");
          CHECK((s.g - f.eval(r).g).norm() == 0, "eval_pairs: the centre is eval()");
          CHECK(e.norm() <= bound, "lat %Lg h %Lg arm %Lg: |fast - exact| %Lg > bound %Lg", lat_deg, h, arm, e.norm(), bound);
          // component along u: the point-mass closed form to the flattening (15 J2 = 1.6 %) and rounding
          const Real tol = 2.5e-2L * 8 * f.params().gm * arm * arm * arm / std::pow(rn, 5) + 64 * ulp(exact.norm());
          CHECK(std::fabs(e.dot(u) - ex) < tol, "lat %Lg h %Lg arm %Lg: (fast - exact).u %Lg, closed form %Lg", lat_deg, h,
                arm, e.dot(u), ex);
          worst_rel = std::max(worst_rel, std::fabs(e.dot(u) - ex) / bound);
          ++n;
        }
    }
  std::printf("central difference, %d points, arms 20-50 m: dropped term = 8 GM |d|^3 P4 / r^5 to %.2Lg of the bound\n", n,
              worst_rel);
}

// Fast path against the reference at sampled steps of a generator.
// point_by_point: a field on the default eval_pairs (all six sensors then equal the reference).
static void check_generator(const Generator3& g, const std::string& what, int samples, bool point_by_point = false,
                            Real* worst_out = nullptr) {
  Real worst = 0, bound_used = 0;
  for (int i = 0; i < samples; ++i) {
    const int64_t k = (g.n_steps() - 1) * i / std::max(1, samples - 1);
    gg_frame_t fr;
    Truth3 t;
    g.frame(k, fr, &t);
    const auto fast = g.accel_true(t);
    const Real arm = std::max({g.offset(0).norm(), g.offset(1).norm(), g.offset(2).norm()});
    const Real bound = gr::NormalField().pair_truncation_bound(t.s.r_e, arm) + 16 * ulp(t.g_e.norm());
    bound_used = bound;
    for (int j = 0; j < 6; ++j) {
      const Vec3 ref = g.accel_reference(t, j);
      const Real e = (fast[static_cast<size_t>(j)] - ref).norm();
      worst = std::max(worst, e);
      if (j < 3 || point_by_point) CHECK(e == 0, "%s k=%ld sensor %d: + sensor differs from the reference by %Lg", what.c_str(), (long)k, j, e);
      CHECK(e <= bound, "%s k=%ld sensor %d: |fast - reference| %Lg > %Lg", what.c_str(), (long)k, j, e, bound);
      for (int ax = 0; ax < 3; ++ax) {  // frame() sends the fast path (errors off): f + f_lo
        const Real sent = static_cast<Real>(fr.f[j][ax]) + static_cast<Real>(fr.f_lo[j][ax]);
        CHECK(sent == fast[static_cast<size_t>(j)](ax), "%s k=%ld sensor %d axis %d: frame() %.21Lg vs accel_true %.21Lg",
              what.c_str(), (long)k, j, ax, sent, fast[static_cast<size_t>(j)](ax));
      }
    }
  }
  std::printf("%-18s %d steps: max |fast - reference| %.3Lg m/s^2 (bound %.3Lg)\n", what.c_str(), samples, worst, bound_used);
  if (worst_out) *worst_out = worst;
}

static void test_scenarios() {
  for (const std::string name : {"3d-strapdown-1h", "3d-stabilized-1h", "3d-tumble"}) {
    const Scenario3 s = load_scenario3(name, {GGINS_SCENARIO_DIR});
    check_generator(Generator3(s), name, 41);
  }
  const std::string egm = std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt";
  if (std::filesystem::exists(egm)) {
    const Scenario3 s = load_scenario3("3d-egm96-1h", {GGINS_SCENARIO_DIR});
    check_generator(Generator3(s), "3d-egm96-1h", 3);
  } else {
    std::printf("skip 3d-egm96-1h: %s missing (scripts/fetch-egm96)\n", egm.c_str());
  }
  // the other field models of the 3-D factory: point mass (point-by-point default) and R&W anomalies
  const char* tail = "[time]\nduration_s = 60\n[baro]\nenable = false\n";
  const Scenario3 pm = parse_scenario3(std::string("[trajectory]\ntype = \"tumble\"\n[gravity]\nmodel = \"point-mass\"\n") + tail,
                                       "pm", "test");
  check_generator(Generator3(pm), "point-mass tumble", 11, true);
  const Scenario3 rw = parse_scenario3(
      std::string("[trajectory]\ntype = \"circle\"\nlat_deg = 35\nlon_deg = -80\nheight_m = 1000\n"
                  "[platform]\nkind = \"strapdown\"\n[gravity]\nmodel = \"rw-anomaly\"\n") + tail,
      "rw", "test");
  check_generator(Generator3(rw), "rw-anomaly circle", 11);
  // long arms: the truncation is then the visible part of the difference, inside its bound
  Generator3Options o;
  o.half_base = {30.0L, 40.0L, 50.0L};
  o.n_steps = 6001;
  TumbleParams tp;
  tp.lat = 30 * kPi / 180;
  const Generator3 gl(std::make_shared<Tumble3>(tp), std::make_shared<gr::NormalField>(), o);
  Real worst = 0;
  check_generator(gl, "tumble, 30-50 m arms", 11, false, &worst);
  CHECK(worst > 0.1L * gr::NormalField().pair_truncation_bound(gl.truth(0).s.r_e, 30.0L),
        "long arms: the dropped term is visible (%Lg)", worst);
}

int main() {
  test_truncation_term();
  test_scenarios();
  if (g_fail) std::printf("%d check(s) failed\n", g_fail);
  else std::printf("all truth3d fast-path checks passed\n");
  return g_fail ? 1 : 0;
}
