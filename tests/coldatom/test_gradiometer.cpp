// Cold-atom gradiometer model against closed forms: the ellipse the noise-free
// pairs lie on, the uniform laser phase, the statistics of phase noise and of
// atom shot noise, the failure probability (binomial) and bounds on the
// random-walk failure probability (end-point Rayleigh law; reflection principle).
#include <cmath>
#include <cstdio>

#include "check.hpp"
#include "ggins/coldatom/gradiometer.hpp"

using namespace ggins::coldatom;

static const double kGzz = 3.086e-6;  // s^-2, normal vertical gradient near the surface

static void test_noise_free_ellipse() {
  GradiometerParams p;
  p.shot_noise = false;
  p.bias0 = 0.01; p.bias1 = -0.02;
  Gradiometer g(p, 1);
  // independent constants: Cs D2 852.347 nm, k_eff = 2 k
  const double k = 2.0 * 2.0 * M_PI / 852.347e-9;
  const double dphi = k * kGzz * 1.0 * 0.16 * 0.16;
  CHECK(std::fabs(dphi - 1.16472) < 1e-4, "dphi %g", dphi);
  double worst = 0;
  for (int i = 0; i < 1000; ++i) {
    const Shot s = g.shot(kGzz);
    CHECK(s.status == ShotStatus::kOk, "failed shot without failure model");
    CHECK(std::fabs(s.dphi_true - dphi) < 1e-12, "dphi_true");
    const double x = (0.5 + p.bias0 - s.s0) / (0.5 * p.contrast);
    const double y = (0.5 + p.bias1 - s.s1) / (0.5 * p.contrast);
    const double r = x * x - 2 * x * y * std::cos(dphi) + y * y - std::sin(dphi) * std::sin(dphi);
    worst = std::fmax(worst, std::fabs(r));
  }
  CHECK(worst < 1e-12, "noise-free pairs off the ellipse by %g", worst);
}

// Laser phase uniform: E[x'] = 0, E[x'^2] = 1/2; phase noise: E[x' y'] = cos(dphi) e^{-s^2/2} / 2
// and E[(y' - cos(phi_L + dphi))^2] = 1 - e^{-s^2/2} (exact for Gaussian eps).
static void test_phase_noise(double sigma, int n, double tol_rel) {
  GradiometerParams p;
  p.shot_noise = false;
  p.phase_noise = sigma;
  Gradiometer g(p, 7);
  double mx = 0, mxx = 0, mxy = 0, mres = 0;
  double dphi = 0;
  for (int i = 0; i < n; ++i) {
    const Shot s = g.shot(kGzz);
    dphi = s.dphi_true;
    const double x = (0.5 - s.s0) / (0.5 * p.contrast), y = (0.5 - s.s1) / (0.5 * p.contrast);
    mx += x; mxx += x * x; mxy += x * y;
    const double r = y - std::cos(s.phi_laser + s.dphi_true);
    mres += r * r;
  }
  mx /= n; mxx /= n; mxy /= n; mres /= n;
  const double e = std::exp(-0.5 * sigma * sigma);
  CHECK(std::fabs(mx) < 5.0 * std::sqrt(0.5 / n), "E[x'] = %g", mx);
  CHECK(std::fabs(mxx - 0.5) < 5.0 * std::sqrt(0.125 / n), "E[x'^2] = %g", mxx);
  const double exy = 0.5 * std::cos(dphi) * e;
  CHECK(std::fabs(mxy - exy) < 5.0 * 0.5 / std::sqrt(n), "E[x'y'] = %g, closed form %g", mxy, exy);
  const double eres = 1.0 - e;
  CHECK(std::fabs(mres / eres - 1.0) < tol_rel, "E[res^2] = %g, closed form %g (sigma %g)", mres, eres, sigma);
  std::printf("phase noise %g rad: E[x'y'] %.6f (closed %.6f), E[res^2] %.4e (closed %.4e)\n", sigma, mxy,
              exy, mres, eres);
}

// Shot noise: s_j - b_j - P_j = P_j dN/N, variance E[P^2]/N = (1 + eta^2/2) / (4 N).
static void test_shot_noise() {
  GradiometerParams p;
  p.n_atoms = 1e4;
  Gradiometer g(p, 11);
  const int n = 200000;
  double m0 = 0, v0 = 0, v1 = 0;
  for (int i = 0; i < n; ++i) {
    const Shot s = g.shot(kGzz);
    const double p0 = 0.5 * (1 - p.contrast * std::cos(s.phi_laser));
    const double p1 = 0.5 * (1 - p.contrast * std::cos(s.phi_laser + s.dphi_true));
    m0 += s.s0 - p0;
    v0 += (s.s0 - p0) * (s.s0 - p0);
    v1 += (s.s1 - p1) * (s.s1 - p1);
  }
  m0 /= n; v0 /= n; v1 /= n;
  const double ev = (1 + 0.5 * p.contrast * p.contrast) / (4 * p.n_atoms);
  CHECK(std::fabs(m0) < 5 * std::sqrt(ev / n), "shot noise mean %g", m0);
  // relative std of a variance estimate ~ sqrt(2/n) * kurtosis factor (< 2): 5 sigma
  CHECK(std::fabs(v0 / ev - 1) < 0.03 && std::fabs(v1 / ev - 1) < 0.03, "shot noise var %g %g, closed %g", v0, v1,
        ev);
}

static void test_failures() {
  {
    GradiometerParams p;
    p.p_fail = 0.25;
    Gradiometer g(p, 3);
    const int n = 100000;
    int f = 0;
    for (int i = 0; i < n; ++i) f += g.shot(kGzz).status == ShotStatus::kFailedRandom;
    const double sd = std::sqrt(0.25 * 0.75 / n);
    CHECK(std::fabs(f / double(n) - 0.25) < 5 * sd, "failure fraction %g", f / double(n));
  }
  {
    // Random walk: end-point spread sigma_e^2 = rw^2 * 2T per axis.
    // Lower bound P(r_end > R) = exp(-R^2 / (2 sigma_e^2)) (Rayleigh); upper bound
    // max|r| > R => max|x| or max|y| > R/sqrt2; reflection: P(max|x| > a) <= 4 Q(a / sigma_e).
    GradiometerParams p;
    p.cloud_rw = 5e-3;
    p.beam_radius = 6e-3;
    Gradiometer g(p, 5);
    const int n = 40000;
    int f = 0;
    for (int i = 0; i < n; ++i) f += g.shot(kGzz).status == ShotStatus::kFailedBeam;
    const double se = p.cloud_rw * std::sqrt(2 * p.T);
    const double lo = std::exp(-p.beam_radius * p.beam_radius / (2 * se * se));
    const double a = p.beam_radius / std::sqrt(2.0) / se;
    const double hi = 2 * 4 * 0.5 * std::erfc(a / std::sqrt(2.0));
    const double fr = f / double(n);
    std::printf("random-walk failures %.4f (bounds %.4f .. %.4f)\n", fr, lo, hi);
    CHECK(fr > lo && fr < hi, "random-walk failure fraction %g outside [%g, %g]", fr, lo, hi);
  }
}

int main() {
  test_noise_free_ellipse();
  test_phase_noise(0.3, 200000, 0.02);
  test_phase_noise(0.010, 200000, 0.02);
  test_shot_noise();
  test_failures();
  std::printf(g_fail ? "coldatom.gradiometer: %d FAILED\n" : "coldatom.gradiometer: all passed\n", g_fail);
  return g_fail ? 1 : 0;
}
