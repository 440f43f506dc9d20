// The cold-atom vertical gradiometer of a 3-D flight (Phillips et al. section II) as a
// sensor of the frame, and the scenario tables of it and of its aid:
//
//   [coldatom]                  # the sensor (frame.h ca_*): one shot every 1 / rate_hz s
//   enabled = true
//   gzz_map = "phillips-route"  # the TRUE Gamma_zz: "phillips-route" (EGM96 + synthetic terrain
//                               # along Liverpool -> Toulouse, coldatom/route_map.hpp),
//                               # "phillips-route-normal" (its WGS-84 normal part alone) or
//                               # "field" (the scenario's [gravity] field: Gamma_DD of its
//                               # tensor along the geodetic down, any route)
//   egm96 = "..."               # EGM96 coefficients (default: the data directory's)
//   cache = "..."               # directory caching the map's EGM96 grid (default: none)
//                               # (relative names of both: from the scenario file's directory)
//   rate_hz = 1.0, dz_m = 1.0, T_s = 0.16, n_atoms = 1e5, contrast = 0.5,
//   phase_noise_mrad = 0.0, shot_noise = true, p_fail = 0.0, cloud_rw_m_rts = 0.0,
//   beam_radius_m = 6e-3, seed = 1,
//   topo_rms_m = 150.0          # rms height of the route map's synthetic terrain, m
//                               # (its Gamma_zz rms at 3000 m scales with it: 17.0 E at 150 m)
//
//   [aid_pf]                    # the particle filter of the 3-D task (aid_pf.h)
//   enabled = true
//   map_dir = "..."             # the Gamma_zz tiles (*.gmap) for the computer's map storage;
//                               # relative: from the scenario's directory
//   map_from_field = false      # or: the tiles written by the runner from the sensor's own
//                               # route map (coldatom/route_tiles.hpp) into <out>/maps/aid_pf/:
//   map_step_m = 250.0          #   node spacing, m (50 x 50 nodes a tile)
//   map_tile_spacing_m = 5000.0 #   distance along the route between tile centres, m
//                               # with gzz_map = "field": Gamma_zz tiles of the scenario's own
//                               # [gravity] field along the route in height layers, cut as the
//                               # map UKF's (run3d field_map.hpp):
//   map_spacing_deg = 0.05, map_margin_deg = 0.25, map_noise_E = 0.001, map_seed = 1
//   particles = 500, chunk = 50, end_chunk = 250, model = "rbpf" ("rw", "ins"), seed = 1,
//   feedback = "position-velocity" (or "position": what the closed loop feeds back),
//   sigma = 0 (likelihood sigma, signal units; 0: the sensor's expected scatter, at least 1e-3),
//   sigma0_pos_m = 50, sigma0_vel_mps = 0, sigma0_tilt_mps2 = 0, sigma0_gyro_mps3 = 4.9e-7,
//   sigma0_accel_mps2 = 3.1e-4, q_pos_m = 0, q_vel_mps = 1.47e-4, q_tilt_mps2 = 1.96e-5,
//   q_gyro_mps3 = 0, q_accel_mps2 = 0, reg_bw = 1.0, gain = 0.05, ess_frac = 0.5
//   (the flights' settings, docs/cold-atom-pf.md: from the INS specification of Table I).
//
// Shot n (at step k = n * steps per shot, n >= 1) is a pure function of (seed, n): its
// draws are counter-based (truth/generator.hpp) and go through coldatom::shot_from, the
// one copy of paper eqs. 1-2. Its Gamma_zz is the map's at the true position of the
// step; a position off the map's corridor gives a failed shot.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include <toml++/toml.h>

extern "C" {
#include "ggins/frame.h"
#include "ggins/nav3d.h"
}
#include "ggins/coldatom/gradiometer.hpp"
#include "ggins/coldatom/route_map.hpp"
#include "ggins/truth3d/integrity3d.hpp"

namespace ggins::truth3d {

struct ColdAtom3 {
  bool enabled = false;
  std::string gzz_map = "phillips-route";
  std::string egm96;
  std::string cache;
  coldatom::GradiometerParams grad;
  std::uint64_t seed = 1;
  double topo_rms_m = 150.0;  // m, the route map's synthetic terrain (coldatom/route_map.hpp)
};

struct AidPf3 : Integrity3 {
  bool enabled = false;
  std::string map_dir;  // as written in the scenario
  bool map_from_field = false;  // the runner writes the tiles from the sensor's route map
  double map_step_m = 250.0, map_tile_spacing_m = 5000.0;
  // map_from_field with [coldatom] gzz_map = "field": Gamma_zz tiles of the scenario's field
  // along the route (ggins run3d: field_map.hpp, the map UKF's cut and height layers)
  double map_spacing_deg = 0.05, map_margin_deg = 0.25, map_noise_E = 0.001;
  uint64_t map_seed = 1;
  int particles = 500, chunk = 50, end_chunk = 250;
  std::string model = "rbpf";
  std::string feedback = "position-velocity";  // or "position"
  std::uint64_t seed = 1;
  double sigma = 0.0;
  // < 0: derived from the scenario's IMU as the filter knows it (apply_aid_pf, PfImu)
  double sigma0_pos_m = 50.0, sigma0_vel_mps = 0.0, sigma0_tilt_mps2 = 0.0, sigma0_gyro_mps3 = -1.0,
         sigma0_accel_mps2 = -1.0;
  double q_pos_m = 0.0, q_vel_mps = -1.0, q_tilt_mps2 = -1.0, q_gyro_mps3 = 0.0, q_accel_mps2 = 0.0;
  double reg_bw = 1.0, gain = 0.05, ess_frac = 0.5;
  double info_min = 0.0;  // the information gate (aid_pf.h): feed only while info >= info_min
};

// [aid_pf] with the sensor's [coldatom] parameters onto c.aid_pf (the filter's ellipse
// model is the sensor's: k_eff, T, dz, contrast, centre 1/2 + bias; likelihood sigma 0 = the
// sensor's expected scatter, at least 1e-3); the firmware validates the values
// (gg_nav3d_init). Part of the scenario -> configuration mapping (config3d.hpp).
// The IMU as the particle filter's model knows it (the scenario's fixed values and the
// one-sigma of its draws, never a draw's outcome), from which the model's spreads not given
// in [aid_pf] are derived, per shot of dt_shot = 1 / [coldatom] rate_hz and g = 9.80665:
//   sigma0_gyro_mps3  = g sigma_bg                  (the tilt rate g x gyro bias)
//   sigma0_accel_mps2 = b_a                         (the horizontal accelerometer error)
//   q_vel_mps         = sigma_a dt sqrt(n)          (accelerometer white noise over a shot)
//   q_tilt_mps2       = g sigma_g dt sqrt(n)        (gyro white noise over a shot)
// with dt the navigation step, n = dt_shot / dt its steps per shot, sigma_a and sigma_g the
// white noise per sample; q_vel_mps at least kPfQVelFloor (the rbpf model needs it > 0).
struct PfImu {
  double gyro_bias_radps = 0, gyro_noise_radps = 0;  // one sigma: bias, white noise per sample
  double accel_bias_mps2 = 0, accel_noise_mps2 = 0;  // horizontal bias magnitude, white noise per sample
  double rate_hz = 100;                              // navigation steps per second
};
constexpr double kPfQVelFloor = 1e-9;  // m/s per shot
void apply_aid_pf(const AidPf3& a, const ColdAtom3& ca, const PfImu& imu, gg_nav3d_config_t& c);

// The directory of [aid_pf].map_dir (its *.gmap tiles: run3d/map_storage.hpp), a relative name
// from the scenario's directory.
std::string aid_pf_map_dir(const AidPf3& a, const std::string& scenario_source);

// The map of the true Gamma_zz the sensor samples.
std::shared_ptr<const coldatom::RouteMap> make_gzz_map3(const ColdAtom3& c);

class ColdAtomSensor3 {
 public:
  ColdAtomSensor3(const ColdAtom3& c, int64_t dt_us);
  // The frame's ca_* for step k with the true geodetic position (rad, rad, m): a shot at
  // the steps of the shots, ABSENT between them. With gzz_map "field" the shot samples
  // field_gzz, the truth field's Gamma_DD at the position (the caller's).
  void frame(int64_t k, double lat_rad, double lon_rad, double h_m, gg_frame_t& out,
             double field_gzz = 0.0) const;
  bool samples_field() const { return c_.gzz_map == "field"; }
  // Shot n at the true Gamma_zz gzz (the draws of (seed, n)).
  coldatom::Shot shot(int64_t n, double gzz) const;
  // The map, built at its first use (the EGM96 grid takes seconds even when cached).
  const coldatom::RouteMap& map() const;
  int64_t steps_per_shot() const { return every_; }
  const ColdAtom3& params() const { return c_; }

 private:
  ColdAtom3 c_;
  mutable std::once_flag once_;
  mutable std::shared_ptr<const coldatom::RouteMap> map_;
  int64_t every_ = 100;
};

}  // namespace ggins::truth3d
