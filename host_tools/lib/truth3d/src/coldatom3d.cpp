// The cold-atom gradiometer of a 3-D flight and its scenario tables (coldatom3d.hpp).
#include "ggins/truth3d/coldatom3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "ggins/truth/generator.hpp"

#ifndef GGINS_DATA_DIR
#define GGINS_DATA_DIR "data"
#endif

namespace ggins::truth3d {

namespace {
constexpr uint64_t kStreamCa = 61;  // the shots' draws (streams of generator3d.cpp: 20-43)
}


void apply_aid_pf(const AidPf3& a, const ColdAtom3& ca, const PfImu& imu, gg_nav3d_config_t& c) {
  gg_aid_pf_config_t& m = c.aid_pf;
  m = gg_aid_pf_config_t{};
  m.enable = a.enabled ? 1 : 0;
  if (!a.enabled) return;
  m.chunk = a.chunk;
  m.end_chunk = a.end_chunk;
  m.feedback = a.feedback == "position" ? GG_AID_PF_FB_POS : GG_AID_PF_FB_POS_VEL;
  m.integ = integrity_config(a);
  m.info_min = a.info_min;
  gg_pf_config_t& p = m.pf;
  const coldatom::GradiometerParams& g = ca.grad;
  p.n = a.particles;
  p.seed = a.seed;
  p.model = a.model == "rw" ? GG_PF_MODEL_RW : (a.model == "ins" ? GG_PF_MODEL_INS : GG_PF_MODEL_RBPF);
  p.k_eff = g.k_eff();
  p.T = g.T;
  p.dz = g.dz;
  p.contrast = g.contrast;
  p.c0 = 0.5 + g.bias0;
  p.c1 = 0.5 + g.bias1;
  p.sigma = a.sigma > 0 ? a.sigma : std::fmax(1e-3, coldatom::Gradiometer(g, 0).expected_sigma());
  p.sigma0_pos = a.sigma0_pos_m;
  p.sigma0_vel = a.sigma0_vel_mps;
  p.sigma0_acc = a.sigma0_tilt_mps2;
  const double g0 = 9.80665, dt = 1.0 / imu.rate_hz;
  const double per_shot = dt * std::sqrt(imu.rate_hz / g.rate_hz);  // dt sqrt(n)
  p.sigma0_jerk = a.sigma0_gyro_mps3 >= 0 ? a.sigma0_gyro_mps3 : g0 * imu.gyro_bias_radps;
  p.sigma0_bias = a.sigma0_accel_mps2 >= 0 ? a.sigma0_accel_mps2 : imu.accel_bias_mps2;
  p.q_pos = a.q_pos_m;
  p.q_vel = a.q_vel_mps >= 0 ? a.q_vel_mps : std::fmax(kPfQVelFloor, imu.accel_noise_mps2 * per_shot);
  p.q_acc = a.q_tilt_mps2 >= 0 ? a.q_tilt_mps2 : g0 * imu.gyro_noise_radps * per_shot;
  p.q_jerk = a.q_gyro_mps3;
  p.q_bias = a.q_accel_mps2;
  p.reg_bw = a.reg_bw;
  p.dt = 1.0 / g.rate_hz;
  p.gain = a.gain;
  p.ess_frac = a.ess_frac;
}

std::string aid_pf_map_dir(const AidPf3& a, const std::string& scenario_source) {
  return scenario_file(a.map_dir, scenario_source);
}

std::shared_ptr<const coldatom::RouteMap> make_gzz_map3(const ColdAtom3& c) {
  // one map per parameter set and process (the EGM96 grid takes seconds even when cached)
  static std::mutex mu;
  static std::shared_ptr<const coldatom::RouteMap> cached;
  static std::string cached_key;
  const std::string egm = c.egm96.empty() ? std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt" : c.egm96;
  const std::string key = c.gzz_map + "|" + egm + "|" + c.cache + "|" + std::to_string(c.topo_rms_m);
  std::lock_guard<std::mutex> lock(mu);
  if (cached && cached_key == key) return cached;
  coldatom::RouteMapParams p;
  p.topo_rms = c.topo_rms_m;
  if (c.gzz_map == "phillips-route-normal") {
    p.with_egm96 = false;
    p.with_topo = false;
  }
  cached = std::make_shared<const coldatom::RouteMap>(p, egm, c.cache);
  cached_key = key;
  return cached;
}

ColdAtomSensor3::ColdAtomSensor3(const ColdAtom3& c, int64_t dt_us) : c_(c) {
  every_ = std::max<int64_t>(1, std::llround(1e6 / (c.grad.rate_hz * static_cast<double>(dt_us))));
}

const coldatom::RouteMap& ColdAtomSensor3::map() const {
  std::call_once(once_, [this] { map_ = make_gzz_map3(c_); });
  return *map_;
}

coldatom::Shot ColdAtomSensor3::shot(int64_t n, double gzz) const {
  coldatom::ShotDraws d;
  const auto un = static_cast<uint64_t>(n);
  d.u_laser = truth::counter_uniform(c_.seed, kStreamCa, un, 0, 0);
  d.z_phase = truth::counter_normal(c_.seed, kStreamCa, un, 1, 0);
  d.z_n0 = truth::counter_normal(c_.seed, kStreamCa, un, 2, 0);
  d.z_n1 = truth::counter_normal(c_.seed, kStreamCa, un, 3, 0);
  d.u_fail = truth::counter_uniform(c_.seed, kStreamCa, un, 4, 0);
  if (c_.grad.cloud_rw > 0) {
    d.z_walk.resize(2 * static_cast<size_t>(c_.grad.rw_substeps));
    for (size_t j = 0; j < d.z_walk.size(); ++j) d.z_walk[j] = truth::counter_normal(c_.seed, kStreamCa, un, 5, j);
  }
  return coldatom::shot_from(c_.grad, gzz, d);
}

void ColdAtomSensor3::frame(int64_t k, double lat_rad, double lon_rad, double h_m, gg_frame_t& out,
                            double field_gzz) const {
  out.ca_status = GG_SENSOR_ABSENT;
  out.ca_s[0] = 0;
  out.ca_s[1] = 0;
  if (k < every_ || k % every_ != 0) return;
  out.ca_utime = out.utime;
  double g = field_gzz;
  if (!samples_field() && !map().gzz(lat_rad, lon_rad, h_m, &g)) {  // off the map's corridor: no gradient to measure
    out.ca_status = GG_SENSOR_BAD;
    return;
  }
  const coldatom::Shot s = shot(k / every_, g);
  if (s.status != coldatom::ShotStatus::kOk) {
    out.ca_status = GG_SENSOR_BAD;
    return;
  }
  out.ca_s[0] = s.s0;
  out.ca_s[1] = s.s1;
  out.ca_status = GG_SENSOR_OK;
}

}  // namespace ggins::truth3d
