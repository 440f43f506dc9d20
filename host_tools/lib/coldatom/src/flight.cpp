#include "ggins/coldatom/flight.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "ggins/coldatom/ellipse_fit.hpp"
#include "ggins/coldatom/route_tiles.hpp"
#include "ggins/gravity/wgs84.hpp"

extern "C" {
#include "ggins/gmap.h"
#include "ggins/pf.h"
}

namespace ggins::coldatom {

namespace {
constexpr double kG0 = 9.80665;
using V3 = Eigen::Vector3d;
using M3 = Eigen::Matrix3d;

gg_status_t map_gzz(const void* ctx, double lat, double lon, double h, double* g) {
  return static_cast<const RouteMap*>(ctx)->gzz(lat, lon, h, g) ? GG_OK : GG_ERR_RANGE;
}
// Meridian and prime-vertical radii (WGS-84) at latitude lat, m.
void radii(double lat, double& rm, double& rn) {
  gravity::Real m, n;
  gravity::wgs84::radii(lat, m, n);
  rm = static_cast<double>(m);
  rn = static_cast<double>(n);
}
M3 skew_offdiag(std::mt19937_64& rng, double sd) {
  std::normal_distribution<double> n(0, sd);
  M3 m = M3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) m(i, j) = n(rng);
  return m;
}
}  // namespace

FlightResult fly(const RouteMap& map, const FlightConfig& cfg) {
  FlightResult res;
  std::mt19937_64 rng(cfg.seed * 7919u + 17u);
  std::normal_distribution<double> n01(0, 1);
  const InsErrorParams& e = cfg.ins;
  // --- per-flight sensor errors (Table I) ---
  V3 ba, bg;
  for (int i = 0; i < 3; ++i) { ba(i) = e.acc_bias_g * kG0 * n01(rng); bg(i) = e.gyro_bias * n01(rng); }
  M3 Ka = skew_offdiag(rng, e.acc_nonorth), Kg = skew_offdiag(rng, e.gyro_nonorth);
  for (int i = 0; i < 3; ++i) { Ka(i, i) = e.acc_scale * n01(rng); Kg(i, i) = e.gyro_scale * n01(rng); }
  if (!e.random) {
    ba = V3::Constant(e.acc_bias_g * kG0);
    bg = V3::Constant(e.gyro_bias);
    Ka = M3::Identity() * e.acc_scale;
    Kg = M3::Identity() * e.gyro_scale;
  }
  const double kOm = e.earth_rate;
  Gradiometer grad(cfg.grad, cfg.seed * 104729u + 3u);

  // --- particle filter ---
  static thread_local gg_pf_t pf;
  gg_pf_config_t pc{};
  pc.n = cfg.particles;
  pc.seed = cfg.seed * 1299709u + 5u;
  pc.k_eff = cfg.grad.k_eff();
  pc.T = cfg.grad.T;
  pc.dz = cfg.grad.dz;
  pc.contrast = cfg.grad.contrast;
  pc.c0 = 0.5 + cfg.grad.bias0;  // calibrated ellipse (known biases)
  pc.c1 = 0.5 + cfg.grad.bias1;
  pc.sigma = cfg.sigma_like > 0 ? cfg.sigma_like : std::max(1e-3, grad.expected_sigma());
  pc.sigma0_pos = cfg.sigma0_pos;
  pc.model = cfg.model == 2 ? GG_PF_MODEL_RBPF : (cfg.model == 1 ? GG_PF_MODEL_INS : GG_PF_MODEL_RW);
  if (pc.model == GG_PF_MODEL_RBPF) {
    // The truth's error model as linear states (pf.h), 1-sigma values of the INS specification
    // (Table I): tilt driven by the gyro noise, a constant gyro bias (jerk state) and a constant
    // horizontal accelerometer error (bias and non-orthogonality x g), velocity by the
    // accelerometer noise; perfect initial alignment.
    const double dtp = 1.0 / cfg.grad.rate_hz;
    const double b = kG0 * e.acc_bias_g, no = kG0 * e.acc_nonorth;
    pc.q_pos = cfg.q_pos >= 0 ? cfg.q_pos : 0.0;
    // (the RBPF needs q_vel > 0: a floor of 1e-6 m/s per shot for a noise-free INS)
    pc.q_vel = std::max(1e-6, cfg.q_vel >= 0 ? cfg.q_vel : kG0 * e.acc_noise_g * std::sqrt(dtp));
    pc.q_acc = cfg.q_acc >= 0 ? cfg.q_acc : kG0 * e.gyro_noise * std::sqrt(dtp);
    pc.sigma0_acc = cfg.sigma0_acc >= 0 ? cfg.sigma0_acc : 0.0;
    pc.sigma0_jerk = kG0 * e.gyro_bias;
    pc.q_jerk = cfg.q_jerk >= 0 ? cfg.q_jerk : 0.0;
    pc.sigma0_bias = std::sqrt(b * b + no * no);
    pc.q_bias = cfg.q_bias >= 0 ? cfg.q_bias : 0.0;
    pc.sigma0_vel = cfg.sigma0_vel >= 0 ? cfg.sigma0_vel : 0.0;
    // Silverman's bandwidth for the 2-D position kernel (chosen on seeds 1001-1010: 0.25 / 0.5 /
    // 1.0 / 1.5 x Silverman gave 610 / 606 / 575 / 602 m mean error)
    pc.reg_bw = cfg.reg_bw >= 0 ? cfg.reg_bw : 1.0;
  } else if (pc.model == GG_PF_MODEL_INS) {
    // Process noise from the INS specification (Table I, the 1-sigma values the designer knows),
    // not from the errors drawn for the flight. da = g psi + accelerometer error: psi is driven
    // by the gyro noise (random walk, g * 2 urad/s/sqrt(Hz)) and the gyro bias (a ramp g eps t,
    // represented by a random walk matching its spread over the longest gap without
    // information, tau = the 1500 s Channel); dv by the accelerometer noise; no white position
    // noise (the INS position error has none: it diffuses through dv and da).
    const double dtp = 1.0 / cfg.grad.rate_hz, tau = 1500.0;
    const double arw = kG0 * e.gyro_noise, ramp = kG0 * e.gyro_bias;
    const double b = kG0 * e.acc_bias_g, no = kG0 * e.acc_nonorth;
    pc.q_pos = cfg.q_pos >= 0 ? cfg.q_pos : 0.0;
    pc.q_vel = cfg.q_vel >= 0 ? cfg.q_vel : kG0 * e.acc_noise_g * std::sqrt(dtp);
    pc.q_acc = cfg.q_acc >= 0 ? cfg.q_acc : std::sqrt((arw * arw + ramp * ramp * tau) * dtp);
    pc.sigma0_acc = cfg.sigma0_acc >= 0 ? cfg.sigma0_acc : std::sqrt(b * b + no * no);
    pc.sigma0_vel = cfg.sigma0_vel >= 0 ? cfg.sigma0_vel : 0.0;  // perfect initial alignment
    pc.reg_bw = cfg.reg_bw >= 0 ? cfg.reg_bw : 0.5;
  } else {  // the first version's settings
    pc.q_pos = cfg.q_pos >= 0 ? cfg.q_pos : 2.0;
    pc.q_vel = cfg.q_vel >= 0 ? cfg.q_vel : 0.02;
    pc.sigma0_vel = cfg.sigma0_vel >= 0 ? cfg.sigma0_vel : 0.05;
    pc.reg_bw = cfg.reg_bw >= 0 ? cfg.reg_bw : 0.0;
  }
  pc.dt = 1.0 / cfg.grad.rate_hz;
  pc.gain = cfg.gain;
  pc.ess_frac = cfg.ess_frac;
  pc.map.gzz = map_gzz;
  pc.map.ctx = &map;
  static thread_local gg_gmap_t gm;
  static thread_local gg_gmap_tile_t tile;
  double tile_lat = 0, tile_lon = 0;
  bool have_tile = false;
  if (cfg.use_gmap) {
    double lat0, lon0;
    map.route_point(0, 0, &lat0, &lon0);
    if (!build_tile(map, lat0, lon0, map.params().h, cfg.tile_step, &tile) || gg_gmap_init(&gm, &tile) != GG_OK) {
      res.error = "the first gmap tile (50 x 50 nodes at " + std::to_string(cfg.tile_step) +
                  " m) leaves the route map's corridor at the start of the route";
      return res;
    }
    tile_lat = lat0; tile_lon = lon0; have_tile = true; ++res.tiles;
    if (gg_pf_map_from_gmap(&gm, &pc.map) != GG_OK) {
      res.error = "gg_pf_map_from_gmap refused the tile";
      return res;
    }
  }
  if (cfg.run_pf) {
    const gg_status_t si = gg_pf_init(&pf, &pc);
    if (si != GG_OK) {
      res.error = "gg_pf_init refused the filter configuration (status " + std::to_string(static_cast<int>(si)) + ")";
      return res;
    }
  }

  const double v = 100.0, h = map.params().h;
  const double T = cfg.duration > 0 ? std::min(cfg.duration, map.length() / v) : map.length() / v;
  const double dt = e.dt;
  const long nsteps = static_cast<long>(std::floor(T / dt + 1e-9));
  const long shot_every = static_cast<long>(std::lround(1.0 / (cfg.grad.rate_hz * dt)));
  const long rec_every = static_cast<long>(std::lround(cfg.record_every / dt));
  V3 dr = V3::Zero(), dv = V3::Zero(), psi = V3::Zero();
  double corr[2] = {0, 0};
  double last_ess = 0;
  std::vector<double> bx, by, bg_true, bg_pf;
  std::vector<double> step_ns;
  double sum_a = 0, sum_u = 0;
  long nrec = 0;
  for (long k = 1; k <= nsteps; ++k) {
    const double t = k * dt;
    // truth at t
    double lat, lon;
    map.route_point(v * t, 0, &lat, &lon);
    const double hd = map.heading(v * t);
    const double sl = std::sin(lat), cl = std::cos(lat);
    double RM, RN;
    radii(lat, RM, RN);
    const double vN = v * std::cos(hd), vE = v * std::sin(hd);
    const V3 Om(kOm * cl, 0, -kOm * sl);
    const V3 rho(vE / (RN + h), -vN / (RM + h), -vE * sl / cl / (RN + h));
    M3 Cbn;
    Cbn << std::cos(hd), -std::sin(hd), 0, std::sin(hd), std::cos(hd), 0, 0, 0, 1;
    const V3 fn(0, 0, -kG0);
    const V3 fb = Cbn.transpose() * fn, wb = Cbn.transpose() * (Om + rho);
    V3 na, ng;
    for (int i = 0; i < 3; ++i) {
      na(i) = e.acc_noise_g * kG0 / std::sqrt(dt) * n01(rng);
      ng(i) = e.gyro_noise / std::sqrt(dt) * n01(rng);
    }
    const V3 dfn = Cbn * (ba + Ka * fb + na);
    const V3 epn = Cbn * (bg + Kg * wb + ng);
    const double ws2 = kG0 / (std::sqrt(RM * RN) + h);
    V3 acc = -psi.cross(fn) - ws2 * dr - 2 * Om.cross(dv) + dfn;
    acc(2) = 0;
    dv += acc * dt;
    dr += dv * dt;
    psi += (-(Om + rho).cross(psi) + epn) * dt;

    if (k % shot_every == 0) {
      double gtrue = 0;
      map.gzz(lat, lon, h, &gtrue);
      const Shot s = grad.shot(gtrue);
      ++res.shots;
      const bool ok = s.status == ShotStatus::kOk;
      if (!ok) ++res.failed;
      // INS position (truth + error) and altimeter
      const double lat_i = lat + dr(0) / (RM + h), lon_i = lon + dr(1) / ((RN + h) * cl);
      const double h_alt = h + cfg.alt_noise * n01(rng);
      if (have_tile) {  // page the tile: re-centre on the corrected position (or the raw INS)
        const double ce = cfg.tile_on_estimate ? 1.0 : 0.0;
        const double lat_t = lat_i + ce * corr[0] / (RM + h), lon_t = lon_i + ce * corr[1] / ((RN + h) * cl);
        const double dn = (lat_t - tile_lat) * (RM + h), de = (lon_t - tile_lon) * (RN + h) * cl;
        if (std::hypot(dn, de) > cfg.tile_recentre && build_tile(map, lat_t, lon_t, h, cfg.tile_step, &tile) &&
            gg_gmap_init(&gm, &tile) == GG_OK) {
          tile_lat = lat_t; tile_lon = lon_t; ++res.tiles;
        }
      }
      if (cfg.run_pf) {
        // INS velocity = truth + its error (the RBPF's transport rate)
        gg_pf_input_t in{lat_i, lon_i, h_alt, ok ? 1 : 0, s.s0, s.s1, vN + dv(0), vE + dv(1)};
        gg_pf_output_t out{};
        const auto t0 = std::chrono::steady_clock::now();
        const gg_status_t st = gg_pf_step(&pf, &in, &out);
        const auto t1 = std::chrono::steady_clock::now();
        if (step_ns.size() < 4000 && ok)
          step_ns.push_back(static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count()));
        if (st == GG_OK) {
          corr[0] = out.corr[0]; corr[1] = out.corr[1];
          last_ess = out.ess;
          if (out.health & GG_PF_H_DEGENERATE) ++res.degenerate;
          if (out.health & GG_PF_H_MAP_MISS) ++res.map_miss;
          if (out.health & GG_PF_H_RESAMPLED) ++res.resampled;
        }
      }
      if (ok) {
        // ellipse-fitting baseline on batches; PF estimate = map at the corrected position
        bx.push_back(s.s0);
        by.push_back(s.s1);
        bg_true.push_back(gtrue);
        double gpf = 0;
        const double lat_c = lat_i + corr[0] / (RM + h), lon_c = lon_i + corr[1] / ((RN + h) * cl);
        if (!map.gzz(lat_c, lon_c, h, &gpf)) gpf = NAN;
        bg_pf.push_back(gpf);
        if (static_cast<int>(bx.size()) == cfg.batch) {
          const EllipseFit f = fit_ellipse(bx, by);
          double mt = 0, mp = 0;
          for (int i = 0; i < cfg.batch; ++i) { mt += bg_true[static_cast<std::size_t>(i)]; mp += bg_pf[static_cast<std::size_t>(i)]; }
          res.batch_t.push_back(t);
          res.g_true.push_back(mt / cfg.batch);
          res.g_fit.push_back(f.ok ? f.dphi / cfg.grad.scale() : NAN);
          res.g_pf.push_back(mp / cfg.batch);
          bx.clear(); by.clear(); bg_true.clear(); bg_pf.clear();
        }
      }
    }
    if (k % rec_every == 0) {
      const double eu = std::hypot(dr(0), dr(1));
      const double ea = std::hypot(dr(0) + corr[0], dr(1) + corr[1]);
      res.t.push_back(t);
      res.err_unaided.push_back(eu);
      res.err_aided.push_back(ea);
      if (cfg.run_pf) {  // diagnostics: the particle cloud against the truth (correction = -error)
        double m[4] = {0, 0, 0, 0}, v2[4] = {0, 0, 0, 0};
        for (int i = 0; i < pf.cfg.n; ++i)
          for (int q = 0; q < 4; ++q) m[q] += pf.w[i] * pf.x[i][q];
        for (int i = 0; i < pf.cfg.n; ++i)
          for (int q = 0; q < 4; ++q) v2[q] += pf.w[i] * (pf.x[i][q] - m[q]) * (pf.x[i][q] - m[q]);
        res.d_err_mean.push_back(std::hypot(dr(0) + m[0], dr(1) + m[1]));
        res.d_spread.push_back(std::sqrt(v2[0] + v2[1]));
        res.d_ess.push_back(last_ess);
        res.d_verr.push_back(std::hypot(dv(0) + m[2], dv(1) + m[3]));
        const double pvv = pf.cfg.model == GG_PF_MODEL_RBPF ? pf.P[0][0] + pf.P[1][1] : 0.0;  // + Kalman part
        res.d_vspread.push_back(std::sqrt(v2[2] + v2[3] + pvv));
        res.d_ins_dv.push_back(std::hypot(dv(0), dv(1)));
      }
      sum_a += ea; sum_u += eu; ++nrec;
    }
  }
  if (nrec) {
    res.mean_aided = sum_a / nrec; res.mean_unaided = sum_u / nrec;
    res.final_aided = res.err_aided.back(); res.final_unaided = res.err_unaided.back();
  }
  if (!step_ns.empty()) {
    std::nth_element(step_ns.begin(), step_ns.begin() + static_cast<long>(step_ns.size() / 2), step_ns.end());
    res.pf_step_ns_median = step_ns[step_ns.size() / 2];
  }
  if (res.t.empty() && res.error.empty()) res.error = "no record: the flight is shorter than the record interval";
  return res;
}

}  // namespace ggins::coldatom
