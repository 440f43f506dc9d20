// Default 2-D fault-detection thresholds; see fdi_thresholds.hpp.
#include "ggins/truth/fdi_thresholds.hpp"

#include <algorithm>
#include <cmath>

extern "C" {
#include "ggins/fdi2d.h"
}
#include "ggins/truth/generator.hpp"

namespace ggins::truth {

namespace {

// p_x, p_z less the point-mass p_exp, and p_s, of four readings per axis
// (sensor i = 0..3, x = axis 0, z = axis 2), with the firmware's own p_exp.
void residuals(const Real f[4][3], const Vec3& r, const Vec3& g, Real a, Real b, Real out[3]) {
  const Real px = 0.5L * ((f[0][0] + f[2][0]) - (f[1][0] + f[3][0]));
  const Real pz = 0.5L * ((f[0][2] + f[2][2]) - (f[1][2] + f[3][2]));
  const Real ps = (f[3][0] - f[1][0]) / (2.0L * b) - (f[2][2] - f[0][2]) / (2.0L * a);
  gg_real_t rr[3] = {static_cast<gg_real_t>(r(0)), static_cast<gg_real_t>(r(1)), static_cast<gg_real_t>(r(2))};
  gg_real_t pe[2] = {0, 0};
  const Real mu = g.norm() * r.squaredNorm();
  if (gg_fdi2d_expected_parity(static_cast<gg_real_t>(a), static_cast<gg_real_t>(b), static_cast<gg_real_t>(mu),
                               rr, pe) != GG_OK)
    pe[0] = pe[1] = 0;
  out[0] = px - static_cast<Real>(pe[0]);
  out[1] = pz - static_cast<Real>(pe[1]);
  out[2] = ps;
}

}  // namespace

FdiThresholds derive_fdi_thresholds(const Scenario& s) {
  Scenario clean = s;
  clean.sensor_faults.faults.clear();
  const Generator gen(clean);
  const Real a = static_cast<Real>(s.a_m), b = static_cast<Real>(s.b_m);
  FdiThresholds th;
  const int64_t n = gen.n_steps();
  const int64_t per15s = std::max<int64_t>(1, std::llround(15e6 / static_cast<double>(gen.dt_us())));
  const int64_t stride = std::max<int64_t>(per15s, (n + 1439) / 1440);
  Real sys_f = 0, sys_s = 0, curv_f = 0, curv_s = 0;
  for (int64_t k = 0; k < n; k += stride) {
    const TruthState t = gen.truth(k);
    Real clean_f[4][3], real_f[4][3];
    for (int i = 0; i < 4; ++i) {
      const Vec3 fi = t.kin.a - gen.field().gravitation(t.kin.r + gen.offset(i));
      for (int j = 0; j < 3; ++j) {
        clean_f[i][j] = fi(j);
        real_f[i][j] = fi(j) * (1.0L + static_cast<Real>(gen.scale(i, j))) + static_cast<Real>(gen.bias(i, j));
      }
    }
    Real rc[3], rs[3];
    residuals(clean_f, t.kin.r, t.g, a, b, rc);
    residuals(real_f, t.kin.r, t.g, a, b, rs);
    curv_f = std::max({curv_f, std::fabs(rc[0]), std::fabs(rc[1])});
    curv_s = std::max(curv_s, std::fabs(rc[2]));
    sys_f = std::max({sys_f, std::fabs(rs[0]), std::fabs(rs[1])});
    sys_s = std::max(sys_s, std::fabs(rs[2]));
    ++th.samples;
  }
  const double sn = s.accel.noise_sigma_mps2;
  const double ad = static_cast<double>(a), bd = static_cast<double>(b);
  th.sys_f_mps2 = static_cast<double>(sys_f);
  th.sys_s_ps2 = static_cast<double>(sys_s);
  th.curv_f_mps2 = static_cast<double>(curv_f);
  th.curv_s_ps2 = static_cast<double>(curv_s);
  th.noise_f_mps2 = sn;
  const double hmin = std::min(ad, bd), hmax = std::max(ad, bd);
  // p_s is tested also while a reading is rebuilt from its group's parity
  // relation with p = p_exp: the rebuilt reading then carries twice the
  // group's residual e = p - p_exp, which moves p_s by e/b (x group) or e/a
  // (z group), and the noise of the three readings it was built from
  // (worst case: sigma_n sqrt(1.5/h_min^2 + 0.5/h_max^2))
  th.noise_s_ps2 = sn * std::sqrt(1.5 / (hmin * hmin) + 0.5 / (hmax * hmax));
  const double floor_f = 1e-14, floor_s = 1e-14 / hmin;
  th.parity_f_max_mps2 = 2.0 * th.sys_f_mps2 + 7.0 * th.noise_f_mps2 + floor_f;
  th.asym_max_ps2 = 2.0 * (th.sys_s_ps2 + th.sys_f_mps2 / hmin) + 7.0 * th.noise_s_ps2 + floor_s;
  return th;
}

void apply_default_fdi_thresholds(Scenario& s) {
  if (!s.firmware.acc_frozen_frames_set)
    s.firmware.acc_frozen_frames = default_frozen_frames(s.accel.noise_sigma_mps2, s.firmware.f_max_mps2);
  if (s.firmware.fdi_parity_f_max_set && s.firmware.fdi_asym_max_set) return;
  const FdiThresholds th = derive_fdi_thresholds(s);
  if (!s.firmware.fdi_parity_f_max_set) s.firmware.fdi_parity_f_max_mps2 = th.parity_f_max_mps2;
  if (!s.firmware.fdi_asym_max_set) s.firmware.fdi_asym_max_ps2 = th.asym_max_ps2;
}

int64_t default_frozen_frames(double noise_sigma_mps2, double f_max_mps2) {
  const double eps = std::nextafter(f_max_mps2, HUGE_VAL) - f_max_mps2;  // ulp(f_max)
  return (std::isfinite(noise_sigma_mps2) && noise_sigma_mps2 >= 10.0 * eps) ? kFrozenFrames : 0;
}

}  // namespace ggins::truth
