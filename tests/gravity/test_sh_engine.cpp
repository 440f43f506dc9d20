// The point-synthesis engine of SphericalHarmonicField::eval (column recursion
// of Holmes & Featherstone, Horner in w, Pines' derivatives) against
//  - an independent method: the Cunningham solid-harmonic recursion with
//    ladder operators (SphericalHarmonicField::derivatives), in long double;
//  - the closed-form field of buried point masses (the series of 1/|r - s|
//    by the addition theorem, truncation error (0.8)^361 ~ 1e-35);
//  - the same physical masses expanded in a ROTATED frame in which the test
//    point lies on the equator: at the pole and within 1e-9..1e-3 rad of it
//    the two evaluations must agree as well as they do at mid latitudes
//    (the degree-n parts of 1/|r - s| are rotation invariant, so the two
//    truncated series are the same function; they differ by rounding only).
#include "test_util.hpp"

#include "ggins/gravity/spherical_harmonic.hpp"

#include <cstdint>
#include <vector>

using namespace ggins::gravity;

namespace {

const Real kA = 6378137.0L, kGm = 3.986004418e14L;

struct Mass { Real gm; Vec3 s; };

// Pbar_nm(t), n, m <= N, fully normalised, no Condon-Shortley phase, by the
// standard forward column recursion with the u^m factor (long double range
// suffices to degree 360).
std::vector<Real> pbar(int N, Real t) {
  std::vector<Real> p(ShCoefficients::idx(N, N) + 1, 0);
  const Real u = std::sqrt(std::max(Real(0), 1 - t * t));
  p[0] = 1;
  for (int m = 0; m <= N; ++m) {
    if (m > 0) p[ShCoefficients::idx(m, m)] = p[ShCoefficients::idx(m - 1, m - 1)] * u * (m == 1 ? std::sqrt(3.0L) : std::sqrt((2.0L * m + 1) / (2.0L * m)));
    for (int n = m + 1; n <= N; ++n) {
      const Real nn = n, mm = m;
      const Real a = std::sqrt((2 * nn - 1) * (2 * nn + 1) / ((nn - mm) * (nn + mm)));
      const Real b = (n >= m + 2) ? std::sqrt((2 * nn + 1) * (nn + mm - 1) * (nn - mm - 1) / ((2 * nn - 3) * (nn + mm) * (nn - mm))) : 0;
      p[ShCoefficients::idx(n, m)] = a * t * p[ShCoefficients::idx(n - 1, m)] - (n >= m + 2 ? b * p[ShCoefficients::idx(n - 2, m)] : 0);
    }
  }
  return p;
}

// Central mass plus buried masses, expanded to degree N by the addition theorem.
ShCoefficients expand(const std::vector<Mass>& ms, int N) {
  ShCoefficients k;
  k.gm = kGm; k.a = kA; k.source = "masses";
  k.resize(N);
  k.c[0] = 1;
  for (const Mass& m : ms) {
    const Real s = m.s.norm(), t = m.s.z() / s, lon = std::atan2(m.s.y(), m.s.x());
    const auto p = pbar(N, t);
    Real qn = m.gm / kGm;
    for (int n = 0; n <= N; ++n, qn *= s / kA)
      for (int mm = 0; mm <= n; ++mm) {
        const Real f = qn / (2 * n + 1) * p[ShCoefficients::idx(n, mm)];
        k.c[ShCoefficients::idx(n, mm)] += f * std::cos(mm * lon);
        k.s[ShCoefficients::idx(n, mm)] += f * std::sin(mm * lon);
      }
  }
  return k;
}

FieldSample closed_form(const std::vector<Mass>& ms, const Vec3& r) {
  FieldSample a = PointMassField(kGm).eval(r);
  for (const Mass& m : ms) {
    const FieldSample b = PointMassField(m.gm).eval(r - m.s);
    a.potential += b.potential; a.g += b.g; a.gamma += b.gamma;
  }
  return a;
}

std::uint64_t g_state = 0x243F6A8885A308D3ull;
Real uniform() {  // splitmix64
  std::uint64_t z = (g_state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<Real>(z >> 11) * 0x1.0p-53L;
}

Vec3 random_dir() {
  const Real t = 2 * uniform() - 1, l = 2 * static_cast<Real>(M_PI) * uniform(), u = std::sqrt(1 - t * t);
  return Vec3(u * std::cos(l), u * std::sin(l), t);
}

// Six anomalous masses at 0.8 a: two near the north pole, one at the south pole.
std::vector<Mass> masses() {
  std::vector<Mass> ms;
  ms.push_back({2e-5L * kGm, 0.8L * kA * Vec3(0.05L, 0.02L, 1).normalized()});
  ms.push_back({-1e-5L * kGm, 0.8L * kA * Vec3(-0.01L, 0.03L, 1).normalized()});
  ms.push_back({1.5e-5L * kGm, 0.8L * kA * Vec3(0, 0, -1)});
  for (int i = 0; i < 3; ++i) ms.push_back({(uniform() - 0.5L) * 4e-5L * kGm, 0.8L * kA * random_dir()});
  return ms;
}

struct Err {
  Real v = 0, g = 0, G = 0;
  void add(const FieldSample& a, const FieldSample& b) {
    v = std::max(v, std::fabs(a.potential - b.potential));
    g = std::max(g, (a.g - b.g).cwiseAbs().maxCoeff());
    G = std::max(G, (a.gamma - b.gamma).cwiseAbs().maxCoeff());
  }
};

// Rotation taking unit vector p to the x axis (rows: p, e2, e3).
Mat3 to_equator(const Vec3& p) {
  const Vec3 e1 = p.normalized();
  const Vec3 h = std::fabs(e1.z()) < 0.9L ? Vec3(0, 0, 1) : Vec3(1, 0, 0);
  const Vec3 e2 = h.cross(e1).normalized(), e3 = e1.cross(e2);
  Mat3 R;
  R.row(0) = e1.transpose(); R.row(1) = e2.transpose(); R.row(2) = e3.transpose();
  return R;
}

}  // namespace

// All three precisions against Cunningham (long double) and the closed form
// at 40 random points, 0..400 km above r = a.
static void test_vs_cunningham_and_closed_form(void**) {
  const auto ms = masses();
  const ShCoefficients k = expand(ms, 360);
  const SphericalHarmonicField fl(k, -1, 2, ShPrecision::LongDouble), fd(k, -1, 2, ShPrecision::Double),
      fm(k, -1, 2, ShPrecision::Mixed);
  Err el, ed, em, ec;
  for (int i = 0; i < 40; ++i) {
    const Vec3 r = (kA + 400e3L * uniform()) * random_dir();
    const auto d = fl.derivatives(r, 2);  // Cunningham
    FieldSample c;
    c.potential = d[0].value[0];
    c.g = Vec3(d[1].at(1, 0, 0), d[1].at(0, 1, 0), d[1].at(0, 0, 1));
    c.gamma << d[2].at(2, 0, 0), d[2].at(1, 1, 0), d[2].at(1, 0, 1), d[2].at(1, 1, 0), d[2].at(0, 2, 0), d[2].at(0, 1, 1),
        d[2].at(1, 0, 1), d[2].at(0, 1, 1), d[2].at(0, 0, 2);
    el.add(fl.eval(r), c); ed.add(fd.eval(r), c); em.add(fm.eval(r), c);
    ec.add(fl.eval(r), closed_form(ms, r));
  }
  std::printf("  vs Cunningham: long double V %.1Le G %.1Le Gamma %.1Le E | double %.1Le %.1Le %.1Le E | mixed %.1Le %.1Le %.1Le E\n",
              el.v, el.g, el.G * 1e9L, ed.v, ed.g, ed.G * 1e9L, em.v, em.g, em.G * 1e9L);
  std::printf("  long double vs closed form: V %.1Le m^2/s^2, G %.1Le m/s^2, Gamma %.1Le E\n", ec.v, ec.g, ec.G * 1e9L);
  assert_true(el.v < 1e-10L && el.g < 1e-17L && el.G < 1e-23L);
  assert_true(em.v < 1e-10L && em.g < 2e-17L && em.G < 1e-22L);
  assert_true(ed.v < 1e-7L && ed.g < 1e-14L && ed.G < 1e-20L);
  assert_true(ec.v < 1e-10L && ec.g < 1e-17L && ec.G < 1e-23L);
}

// At the pole and near it against the rotated-frame evaluation; the error
// there must not exceed (4x) the error 3-6 degrees from the poles.
static void test_poles_rotated_frame(void**) {
  const auto ms = masses();
  const int N = 360;
  const ShCoefficients k = expand(ms, N);
  for (ShPrecision prec : {ShPrecision::LongDouble, ShPrecision::Double}) {
    const SphericalHarmonicField f(k, -1, 2, prec);
    auto rotated_err = [&](const Vec3& r) {
      const Mat3 R = to_equator(r);
      std::vector<Mass> mr = ms;
      for (Mass& m : mr) m.s = R * m.s;
      const SphericalHarmonicField fr(expand(mr, N), -1, 2, prec);
      const FieldSample b = fr.eval(R * r);
      FieldSample back;
      back.potential = b.potential;
      back.g = R.transpose() * b.g;
      back.gamma = R.transpose() * b.gamma * R;
      Err e;
      e.add(f.eval(r), back);
      return e;
    };
    Err pole, mid;
    const Real rr = kA + 2000;
    for (Real zsign : {1.0L, -1.0L})
      for (Real th : {0.0L, 1e-9L, 1e-7L, 1e-6L, 1e-5L, 1e-3L})
        for (Real lon : {0.0L, 2.1L}) {
          const Vec3 r = rr * Vec3(std::sin(th) * std::cos(lon), std::sin(th) * std::sin(lon), zsign * std::cos(th));
          const Err e = rotated_err(r);
          pole.v = std::max(pole.v, e.v); pole.g = std::max(pole.g, e.g); pole.G = std::max(pole.G, e.G);
          if (th == 0) break;
        }
    // reference: the same polar caps, 3-6 degrees from the pole
    for (int i = 0; i < 4; ++i) {
      const Real th = 0.05L + 0.05L * (i % 2), lon = 1.1L * i, zs = i < 2 ? 1 : -1;
      const Err e = rotated_err(rr * Vec3(std::sin(th) * std::cos(lon), std::sin(th) * std::sin(lon), zs * std::cos(th)));
      mid.v = std::max(mid.v, e.v); mid.g = std::max(mid.g, e.g); mid.G = std::max(mid.G, e.G);
    }
    std::printf("  %s: rotated frame, pole and 1e-9..1e-3 rad: V %.1Le G %.1Le Gamma %.1Le E; 3-6 deg from the poles: %.1Le %.1Le %.1Le E\n",
                prec == ShPrecision::Double ? "double" : "long double", pole.v, pole.g, pole.G * 1e9L, mid.v, mid.g, mid.G * 1e9L);
    const Real tol = prec == ShPrecision::Double ? 2048 : 1;  // double vs long double epsilon
    assert_true(pole.g < 1e-17L * tol && pole.G < 1e-23L * tol && pole.v < 1e-10L * tol);
    assert_true(pole.g <= 4 * std::max(mid.g, 1e-18L * tol) && pole.G <= 4 * std::max(mid.G, 1e-24L * tol));
  }
}

// Circles of latitude (column sums shared along the circle, dual numbers for
// the derivative of Gamma along a direction in the meridian plane) against
// the closed-form field and third derivatives of the masses, from pole to pole.
static void test_circles(void**) {
  const auto ms = masses();
  const ShCoefficients k = expand(ms, 360);
  const Real rr = kA + 3000;
  for (ShPrecision prec : {ShPrecision::LongDouble, ShPrecision::Double, ShPrecision::Mixed}) {
    const SphericalHarmonicField f(k, -1, 2, prec);
    Err e;
    Real ed = 0, dmax = 0;
    int n = 0;
    for (Real latd : {-89.999L, -60.0L, -20.0L, 0.0L, 35.0L, 70.0L, 89.99L, 90.0L}) {
      const Real lat = latd * static_cast<Real>(M_PI) / 180, nl = lat + 0.003L;  // e: 0.003 rad off radial
      const Real rho = rr * std::cos(lat), z = rr * std::sin(lat);
      const auto c = f.circle(rho, z, std::cos(nl), std::sin(nl));
      for (Real lon : {0.0L, 0.7L, 1.9L, 3.0L, -2.2L, -0.3L}) {
        const Vec3 r(rho * std::cos(lon), rho * std::sin(lon), z);
        const Vec3 u(std::cos(nl) * std::cos(lon), std::cos(nl) * std::sin(lon), std::sin(nl));
        Mat3 dg;
        e.add(c->eval(lon, &dg), closed_form(ms, r));
        Tensor3 t;
        assert_true(PointMassField(kGm).third(r, t));
        Mat3 want = t[0] * u.x() + t[1] * u.y() + t[2] * u.z();
        for (const Mass& m : ms) {
          assert_true(PointMassField(m.gm).third(r - m.s, t));
          want += t[0] * u.x() + t[1] * u.y() + t[2] * u.z();
        }
        ed = std::max(ed, (dg - want).cwiseAbs().maxCoeff());
        dmax = std::max(dmax, want.cwiseAbs().maxCoeff());
        ++n;
      }
    }
    const char* name = prec == ShPrecision::Double ? "double" : prec == ShPrecision::Mixed ? "mixed" : "long double";
    std::printf("  %s circles (%d points, 8 latitudes incl. the pole): V %.1Le G %.1Le Gamma %.1Le E; dGamma/de %.1Le of %.1Le s^-2/m\n",
                name, n, e.v, e.g, e.G * 1e9L, ed, dmax);
    const Real tol = prec == ShPrecision::Double ? 2048 : 1;
    if (prec == ShPrecision::Mixed) assert_true(e.v < 1e-10L && e.g < 2e-17L && e.G < 1e-22L);  // as against Cunningham
    else assert_true(e.v < 1e-10L * tol && e.g < 1e-17L * tol && e.G < 1e-23L * tol);
    assert_true(ed < 1e-26L);  // double arithmetic: 1e-16 x |third derivatives| ~1e-12 s^-2/m, amplified by the sums
  }
}

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_vs_cunningham_and_closed_form),
      cmocka_unit_test(test_poles_rotated_frame),
      cmocka_unit_test(test_circles),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
