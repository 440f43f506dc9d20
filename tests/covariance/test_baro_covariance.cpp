// ggins covariance model of the barometric vertical loop (welker2d_baro.hpp)
// against an independent prediction: the stationary variance of the
// vertical error of the loop, computed in the frequency domain from the loop's
// transfer function H_b(s) = (k1 s^2 + k2 s + k3) / (s^3 + k1 s^2 + (k2 - 2 w^2) s + k3)
// (docs/vertical.md), plus the constant bias b at DC gain 1:
//   sigma_h^2 = sigma_b^2 + (1/pi) int_0^{pi/T} |H_b|^2 (2 sigma_m^2/tau/(w^2 + 1/tau^2) + sigma_n^2 T) dw.
// The covariance propagation (time domain, Lyapunov RK4) must reach it. Also
// prints the predicted vertical and along-track sigmas of welker-baro-10h for
// comparison with the flight (docs/vertical.md).
#include <cmath>
#include <complex>
#include <cstdio>

#include "ggins/covariance/propagate.hpp"
#include "ggins/covariance/welker2d_baro.hpp"
#include "ggins/gravity/field.hpp"

using namespace ggins::covariance;

static int g_fail = 0;
static void check(bool c, const char* what, double a, double b) {
  std::printf("%s %s: %.6g vs %.6g\n", c ? "ok  " : "FAIL", what, a, b);
  if (!c) ++g_fail;
}

int main() {
  const double GM = 3.986004418e14, R = 6378137.0, w2 = GM / (R * R * R);
  const double sb = 3.0, sm = 3.0, tau = 600.0, sn = 0.5, T = 1.0, sa = 1e-12;
  BaroLoopParams p;
  p.omega_s2 = w2;
  p.gm_tau_s = tau;
  p.gm_sigma_m = sm;
  p.noise_sigma_m = sn;
  p.period_s = T;
  auto field = std::make_shared<ggins::gravity::PointMassField>(GM);
  auto traj = std::make_shared<NorthGreatCircle2D>(300.0, 0.0, 0.0, R);
  auto base = std::make_shared<Welker2DModel>(field, traj, 0.5, 0.5);
  Welker2DBaroModel m(base, p);

  // frequency-domain stationary sigma of dh (Simpson in ln w)
  const double k1 = m.k1(), k2 = m.k2(), k3 = m.k3(), k2p = k2 - 2 * w2;
  auto h2 = [&](double w) {
    const std::complex<double> s(0, w);
    return std::norm((k1 * s * s + k2 * s + k3) / (s * s * s + k1 * s * s + k2p * s + k3));
  };
  const int n = 200000;
  const double a = std::log(1e-8), b = std::log(M_PI / T), hs = (b - a) / n;
  double acc = 0;
  for (int i = 0; i <= n; ++i) {
    const double w = std::exp(a + i * hs), c = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    acc += c * w * h2(w) * (2 * sm * sm / tau / (w * w + 1 / (tau * tau)) + sn * sn * T);
  }
  const double var_f = acc * hs / 3 / M_PI;
  const double sig_pred = std::sqrt(sb * sb + var_f);
  std::printf("     frequency domain: sigma_f = %.4f m, with the bias sigma_h = %.4f m\n", std::sqrt(var_f), sig_pred);

  MatrixXd P0 = MatrixXd::Zero(17, 17);
  for (int i = 0; i < 8; ++i) P0(7 + i, 7 + i) = sa * sa;
  P0(7 + Welker2DBaroModel::kBaroBias, 7 + Welker2DBaroModel::kBaroBias) = sb * sb;
  P0(7 + Welker2DBaroModel::kBaroGm, 7 + Welker2DBaroModel::kBaroGm) = sm * sm;
  PropagationOptions o;
  o.t_end = 36000;
  o.dt = 0.5;
  o.output_dt = 3600;
  o.method = Method::kLyapunov;
  const auto run = propagate(m, P0, o);
  for (const auto& smp : run) {
    const Eigen::Vector2d u = m.up(smp.t);
    const TrajectoryPoint tp = traj->at(smp.t);
    const Eigen::Vector2d al = Eigen::Vector2d(tp.v(0), tp.v(2)).normalized();
    const Eigen::Matrix2d Pr = smp.P.topLeftCorner(2, 2);
    std::printf("     t = %5.0f s: sigma vertical %.4f m, along-track %.4f m, a_c %.3g m/s^2\n", smp.t,
                std::sqrt(u.dot(Pr * u)), std::sqrt(al.dot(Pr * al)), std::sqrt(smp.P(6, 6)));
  }
  for (const auto& smp : run) {
    if (smp.t < 3600) continue;
    const Eigen::Vector2d u = m.up(smp.t);
    const double sv = std::sqrt(u.dot(smp.P.topLeftCorner(2, 2) * u));
    // the continuous model of a loop whose discrete version has the same poles;
    // the frequency integral is cut at Nyquist: agreement to 1 %
    check(std::fabs(sv / sig_pred - 1) < 0.01, "vertical sigma (time domain) = frequency-domain prediction", sv,
          sig_pred);
  }
  // loop without barometer errors and with a common accelerometer bias (the
  // same value on every sensor: no gradient error): the integral state takes
  // the up bias and the vertical error vanishes (the transient, of order
  // b/k3, decays as exp(-p_min t): exp(-36) at 1 h). (Independent biases
  // make gradient errors, dG ramps, and a ramp leaves ramp/k3 - not tested here.)
  {
    BaroLoopParams q = p;
    q.gm_sigma_m = 0;
    q.noise_sigma_m = 0;
    // a platform at rest (V = 0): the up direction, and with it the up
    // component of the bias, stays constant (in flight it turns at V/R and the
    // integral state lags the changing up bias by ~ b V/R / k3 ~ 1e-8 m)
    auto still = std::make_shared<Welker2DModel>(field, std::make_shared<NorthGreatCircle2D>(0.0, 0.0, 0.0, R), 0.5, 0.5);
    Welker2DBaroModel mq(still, q);
    MatrixXd Q0 = MatrixXd::Zero(17, 17);
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        if (i / 4 == j / 4) Q0(7 + i, 7 + j) = 1e-9 * 1e-9;  // fully correlated within an axis
    o.t_end = 3600;
    const auto r2 = propagate(mq, Q0, o);
    const Eigen::Vector2d u = mq.up(3600);
    const double sv = std::sqrt(u.dot(r2.back().P.topLeftCorner(2, 2) * u));
    check(sv < 1e-9 / k3 * 1e-6, "common 1e-9 bias, perfect barometer: vertical sigma at 1 h (m) below 1e-6 b/k3", sv,
          1e-9 / k3 * 1e-6);
  }
  std::printf(g_fail ? "%d check(s) failed\n" : "baro covariance: all checks passed\n", g_fail);
  return g_fail ? 1 : 0;
}
