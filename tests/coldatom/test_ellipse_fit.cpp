// Ellipse fit against known ellipses (exact points: conic and phase to round-off),
// and the bias of the batch estimator: static with noise vs on a moving platform
// where the gradient changes within the batch.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "check.hpp"
#include "ggins/coldatom/ellipse_fit.hpp"

using namespace ggins::coldatom;

static void test_exact() {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0, 2 * M_PI);
  const double dphis[] = {0.3, 1.1647, M_PI / 2, 2.5};
  for (double dphi : dphis) {
    const double x0 = 0.52, y0 = 0.47, a = 0.25, b = 0.21;
    std::vector<double> x, y;
    for (int i = 0; i < 20; ++i) {
      const double t = u(rng);
      x.push_back(x0 + a * std::cos(t));
      y.push_back(y0 + b * std::cos(t + dphi));
    }
    const EllipseFit f = fit_ellipse(x, y);
    CHECK(f.ok, "fit failed");
    CHECK(std::fabs(f.dphi - dphi) < 1e-9, "dphi %.12f vs %.12f", f.dphi, dphi);
    CHECK(std::fabs(f.x0 - x0) < 1e-9 && std::fabs(f.y0 - y0) < 1e-9, "centre %g %g", f.x0, f.y0);
    // analytic conic: (x-x0)^2/a^2 - 2 c (x-x0)(y-y0)/(ab) + (y-y0)^2/b^2 - s^2 = 0, scaled to 4AC-B^2 = 1
    const double c = std::cos(dphi), s = std::sin(dphi);
    double A = 1 / (a * a), B = -2 * c / (a * b), C = 1 / (b * b);
    double D = -2 * A * x0 - B * y0, E = -2 * C * y0 - B * x0;
    double F = A * x0 * x0 + B * x0 * y0 + C * y0 * y0 - s * s;
    const double k = 1 / std::sqrt(4 * A * C - B * B);
    const double sg = (f.conic.A > 0) ? 1.0 : -1.0;
    const double ref[6] = {A * k, B * k, C * k, D * k, E * k, F * k};
    const double got[6] = {sg * f.conic.A, sg * f.conic.B, sg * f.conic.C, sg * f.conic.D, sg * f.conic.E,
                           sg * f.conic.F};
    for (int i = 0; i < 6; ++i)
      CHECK(std::fabs(got[i] - ref[i]) < 1e-8 * (1 + std::fabs(ref[i])), "conic[%d] %g vs %g", i, got[i], ref[i]);
  }
  std::vector<double> few{1, 2, 3};
  CHECK(!fit_ellipse(few, few).ok, "fit of 3 points must fail");
}

// Mean fitted dphi minus the batch-mean true dphi, over many batches of n pairs.
static double batch_bias(double dphi0, double ramp, double sigma, int n, int batches, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 2 * M_PI);
  std::normal_distribution<double> g(0, 1);
  double sum = 0;
  int ok = 0;
  for (int b = 0; b < batches; ++b) {
    std::vector<double> x, y;
    for (int i = 0; i < n; ++i) {
      const double dphi = dphi0 + ramp * ((i + 0.5) / n - 0.5);  // linear change, mean dphi0
      const double t = u(rng);
      x.push_back(0.5 - 0.25 * std::cos(t) + sigma * g(rng));
      y.push_back(0.5 - 0.25 * std::cos(t + dphi) + sigma * g(rng));
    }
    const EllipseFit f = fit_ellipse(x, y);
    if (f.ok) { sum += f.dphi - dphi0; ++ok; }
  }
  return ok ? sum / ok : NAN;
}

static void test_moving_bias() {
  const double b_static0 = batch_bias(1.1647, 0.0, 0.0, 20, 50, 1);
  CHECK(std::fabs(b_static0) < 1e-9, "noise-free static bias %g", b_static0);
  // Moving platform, noise free: the pairs of one batch lie on different ellipses
  // (dphi ramps linearly by `ramp` over the batch). The fit of the thickened family
  // is pulled toward the rounder ellipse, dphi -> pi/2: an over-estimate below pi/2,
  // an under-estimate above (mirror symmetry x -> -x maps dphi to pi - dphi), and
  // of second order in the ramp (the bias is even in the ramp). Checked: the sign
  // follows cot(dphi), bias * tan(dphi) is the same at four dphi (within 15 %), and
  // doubling the ramp multiplies the bias by 4 (3.4 .. 4.6).
  const double d[] = {0.5, 1.1647, 2.0, 2.6};
  double k[4];
  for (int i = 0; i < 4; ++i) {
    const double b1 = batch_bias(d[i], 0.1, 0.0, 20, 20000, 3);
    const double b2 = batch_bias(d[i], 0.2, 0.0, 20, 20000, 3);
    k[i] = b1 * std::tan(d[i]);
    std::printf("dphi %.4f: moving-platform bias %.3e rad (ramp 0.1 rad), %.3e (ramp 0.2 rad), ratio %.2f\n", d[i], b1,
                b2, b2 / b1);
    CHECK(k[i] > 0, "bias %g at dphi %g not toward pi/2", b1, d[i]);
    CHECK(b2 / b1 > 3.4 && b2 / b1 < 4.6, "bias not quadratic in the ramp: %g", b2 / b1);
  }
  for (int i = 1; i < 4; ++i) CHECK(std::fabs(k[i] / k[0] - 1) < 0.15, "bias*tan(dphi) %g vs %g", k[i], k[0]);
}

int main() {
  test_exact();
  test_moving_bias();
  std::printf(g_fail ? "coldatom.ellipse_fit: %d FAILED\n" : "coldatom.ellipse_fit: all passed\n", g_fail);
  return g_fail ? 1 : 0;
}
