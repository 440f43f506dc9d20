// The covariance tool's model is the firmware's model.
// Linearizes the firmware's actual navigation step (gg_nav2d_step) by finite
// differences -- perturbing each of the six navigation states (through the
// initial state of the nav task) and each of the eight accelerometer readings
// -- at times along the welker-table1 flight, and compares the one-step
// Jacobian with the tool's one-step transition matrix
//   Phi(t+dt, t) = exp-like solution of d/dt [dx; d] = [F Gamma; 0 0] [dx; d]
// built from Welker2DModel's F(t) (eq. 9, sign-fixed) and Gamma(t) (eq. 10).
// A sign or factor error in either (e.g. the paper's printed -dG) fails here.
#include <cmath>
#include <memory>
#include <string>

#include "ggins/covariance/propagate.hpp"
#include "ggins/covariance/welker2d.hpp"
#include "ggins/gravity/field.hpp"

extern "C" {
#include "ggins/frame.h"
#include "ggins/nav2d.h"
}

// CMocka last (its fail() macro clashes with the C++ library).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
extern "C" {
#include <cmocka.h>
}

using namespace ggins::covariance;
using ggins::gravity::PointMassField;

namespace {

constexpr double kGM = 3.986004418e14, kRe = 6378137.0, kV = 300.0, kA = 0.5, kB = 0.5;
constexpr int64_t kDtUs = 10000;  // 100 Hz, as scenarios/welker-table1.toml
constexpr double kDt = 1e-6 * double(kDtUs);

// The model, time-shifted so that transition_matrix(.., dt, ..) spans [t0, t0 + dt].
class Shifted final : public LinearErrorModel {
 public:
  Shifted(const LinearErrorModel& m, double t0) : m_(m), t0_(t0) {}
  int n_states() const override { return m_.n_states(); }
  int n_dist() const override { return m_.n_dist(); }
  std::vector<std::string> state_keys() const override { return m_.state_keys(); }
  std::vector<std::string> dist_keys() const override { return m_.dist_keys(); }
  void matrices(double t, MatrixXd& F, MatrixXd& G) const override { m_.matrices(t0_ + t, F, G); }

 private:
  const LinearErrorModel& m_;
  double t0_;
};

struct Perturbation {
  double dstate[6] = {0, 0, 0, 0, 0, 0};  // x z vx vz Gx Gz
  double dread[8] = {0, 0, 0, 0, 0, 0, 0, 0};  // f1x f2x f3x f4x f1z f2z f3z f4z
};

// Exact sensor frame at step k of the north flight (point-mass field).
gg_frame_t frame_at(const PointMassField& field, const NorthGreatCircle2D& traj, int64_t k, const double dread[8]) {
  using LD = long double;
  using ggins::gravity::Vec3;
  gg_frame_t fr;
  memset(&fr, 0, sizeof fr);
  fr.utime = k * kDtUs;
  fr.seq = k;
  fr.n_acc = 4;
  const double t = double(k) * kDt;
  const TrajectoryPoint p = traj.at(t);
  const Vec3 r = p.r.cast<LD>();
  const Vec3 off[4] = {Vec3(kA, 0, 0), Vec3(0, 0, kB), Vec3(-kA, 0, 0), Vec3(0, 0, -kB)};
  for (int i = 0; i < 4; ++i) {
    const Vec3 g = field.eval(r + off[i]).g;
    for (int ax = 0; ax < 2; ++ax) {
      const int c = ax == 0 ? 0 : 2;
      const LD f = LD(p.a(c)) - g(c) + LD(dread[4 * ax + i]);  // f = a - G (+ bias)
      fr.f[i][c] = double(f);
      fr.f_lo[i][c] = double(f - LD(fr.f[i][c]));
    }
    fr.acc_status[i] = GG_SENSOR_OK;
  }
  fr.gyro_status = GG_SENSOR_ABSENT;
  fr.baro_status = GG_SENSOR_ABSENT;
  return fr;
}

// Initialise the nav task at step k (state = truth + perturbation), step once
// to k + 1, return (x z vx vz Gx Gz).
Eigen::Matrix<double, 6, 1> one_step(const PointMassField& field, const NorthGreatCircle2D& traj, int64_t k,
                                     const Perturbation& d) {
  using ggins::gravity::Vec3;
  const TrajectoryPoint p = traj.at(double(k) * kDt);
  const Vec3 g0 = field.eval(p.r.cast<long double>()).g;
  gg_nav2d_config_t cfg;
  memset(&cfg, 0, sizeof cfg);
  cfg.geometry.a_m = kA;
  cfg.geometry.b_m = kB;
  cfg.dt_us = kDtUs;
  cfg.dt_tol_us = 0;
  cfg.r0[0] = (long double)p.r(0) + d.dstate[0];
  cfg.r0[2] = (long double)p.r(2) + d.dstate[1];
  cfg.v0[0] = (long double)p.v(0) + d.dstate[2];
  cfg.v0[2] = (long double)p.v(2) + d.dstate[3];
  cfg.g0[0] = g0(0) + d.dstate[4];
  cfg.g0[2] = g0(2) + d.dstate[5];
  cfg.f_max = 50.0;
  cfg.asym_max = 1.0;
  cfg.gravity_mode = GG_GRAVITY_GRADIOMETER;
  cfg.baro_enable = 0;
  static gg_nav2d_t nav;  // large; not on the stack
  assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
  gg_nav_output_t out;
  const gg_frame_t f0 = frame_at(field, traj, k, d.dread), f1 = frame_at(field, traj, k + 1, d.dread);
  assert_int_equal(gg_nav2d_step(&nav, &f0, NULL, &out), GG_OK);
  assert_int_equal(gg_nav2d_step(&nav, &f1, NULL, &out), GG_OK);
  assert_int_equal(out.seq, k + 1);
  Eigen::Matrix<double, 6, 1> s;
  s << out.r_i[0], out.r_i[2], out.v_i[0], out.v_i[2], out.g_i[0], out.g_i[2];
  return s;
}

void test_firmware_step_jacobian_vs_model(void**) {
  auto field = std::make_shared<PointMassField>(kGM);
  auto traj = std::make_shared<NorthGreatCircle2D>(kV, 0.0, 0.0, kRe);
  Welker2DModel model(field, traj, kA, kB);
  // Perturbation sizes: the step is linear in the state and in the readings
  // (gradiometer mode: G' = Gamma_measured v), so they are chosen large enough
  // for the double-precision outputs to resolve the responses.
  const double ds[6] = {1e3, 1e3, 1.0, 1.0, 1.0, 1.0};
  const double df = 1e-1;
  double worst = 0;
  int n_bad = 0;
  for (int64_t k : {int64_t(0), int64_t(90000), int64_t(180000), int64_t(270000), int64_t(359999)}) {
    const double t = double(k) * kDt;
    const MatrixXd Phi = transition_matrix(Shifted(model, t), kDt, kDt / 8);  // 14 x 14
    // Central differences: the step is bilinear in (readings, state) -- the
    // measured gradient multiplies the velocity -- so a one-sided difference
    // would carry a term proportional to the perturbation; the central one
    // cancels it exactly.
    MatrixXd J(6, 14);
    for (int j = 0; j < 14; ++j) {
      Perturbation p, m;
      const double h = j < 6 ? ds[j] : df;
      if (j < 6) {
        p.dstate[j] = h;
        m.dstate[j] = -h;
      } else {
        p.dread[j - 6] = h;
        m.dread[j - 6] = -h;
      }
      J.col(j) = (one_step(*field, *traj, k, p) - one_step(*field, *traj, k, m)) / (2 * h);
    }
    // The firmware's step is a second-order scheme in dt, so its one-step
    // Jacobian must equal the Taylor expansion of the model's transition,
    //   J = I + A dt + A^2 dt^2/2 + O(dt^3),  A = Fa(t + dt/2) = [F Gamma; 0 0],
    // entry by entry: to 1e-3 of the increment, plus the size of the next
    // (third-order) term (|A|^3 dt^3/6, doubled), plus the resolution of the
    // double outputs divided by the perturbation. A sign or factor error in F
    // or Gamma changes the first-order term A dt and fails by far.
    const MatrixXd A = model.augmented(t + 0.5 * kDt);
    const MatrixXd I14 = MatrixXd::Identity(14, 14);
    const MatrixXd T2 = (I14 + A * kDt + 0.5 * A * A * kDt * kDt).topRows(6);
    const MatrixXd Aabs = A.cwiseAbs();
    const MatrixXd E3 = (Aabs * Aabs * Aabs).topRows(6) * (kDt * kDt * kDt / 6.0);
    const double ulp_row[6] = {std::ldexp(1.0, -52) * kRe, std::ldexp(1.0, -52) * kRe, std::ldexp(1.0, -52) * 512,
                               std::ldexp(1.0, -52) * 512, std::ldexp(1.0, -52) * 16, std::ldexp(1.0, -52) * 16};
    const MatrixXd Aj = J - MatrixXd::Identity(6, 14);
    const MatrixXd At = T2 - MatrixXd::Identity(6, 14);
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 14; ++j) {
        const double pert = j < 6 ? ds[j] : df;
        const double tol = 1e-3 * std::abs(At(i, j)) + 2.0 * E3(i, j) + ulp_row[i] / pert;
        const double err = std::abs(Aj(i, j) - At(i, j));
        worst = std::max(worst, err / tol);
        if (!(err <= tol)) {
          print_error("t = %.2f s: d(state %d)/d(input %d): firmware %.9e, model %.9e (tol %.2e)\n", t, i, j,
                      Aj(i, j), At(i, j), tol);
          ++n_bad;
        }
      }
    }
    // Leading order, for the record: F and Gamma recovered from the firmware.
    const MatrixXd Ffd = Aj.leftCols(6) / kDt, Gfd = Aj.rightCols(8) / kDt;
    if (k == 0 || k == 359999)
      print_message("t = %.2f s: dG/dV firmware [%.6e %.6e; %.6e %.6e], model [%.6e %.6e; %.6e %.6e]; "
                    "dV/dG firmware %.6f %.6f; dGx/df3x firmware %.6f model %.6f\n",
                    t, Ffd(4, 2), Ffd(4, 3), Ffd(5, 2), Ffd(5, 3), A(4, 2), A(4, 3), A(5, 2), A(5, 3), Ffd(2, 4),
                    Ffd(3, 5), Gfd(4, 2), A(4, 8));
    if (k == 0) {
      print_message("t = 0: model  (Phi - I)[Gx row]: %s\n", [&] {
        std::string s;
        char b[32];
        for (int j = 0; j < 14; ++j) {
          snprintf(b, sizeof b, " %.4e", At(4, j));
          s += b;
        }
        return s;
      }().c_str());
      print_message("t = 0: firmware (J - I)[Gx row]: %s\n", [&] {
        std::string s;
        char b[32];
        for (int j = 0; j < 14; ++j) {
          snprintf(b, sizeof b, " %.4e", Aj(4, j));
          s += b;
        }
        return s;
      }().c_str());
    }
  }
  print_message("worst |firmware - model| / tolerance over the flight: %.3g\n", worst);
  assert_int_equal(n_bad, 0);
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_firmware_step_jacobian_vs_model),
  };
  return cmocka_run_group_tests_name("covariance_fw_linearization", tests, NULL, NULL);
}
