// The map of the flight Liverpool -> Toulouse (Phillips et al. section III):
// Gamma_zz = dG_D/dD (s^-2, NED) at 3000 m along a corridor about the great
// circle, on a route-aligned grid (s along track, c cross track, metres on a
// sphere of radius R + 3000 m; only a parametrisation of the map: the map is a
// well-defined function of (lat, lon)).
//
//   Gamma_zz(lat, lon, h) = EGM96(s, c)                      (degree 360 + WGS-84 normal, bicubic on a 4 km grid)
//                         + land(lat) * Topo(s, c)           (synthetic terrain field, bilinear on a 250 m grid)
//                         + dGamma/dh (h - 3000)             (normal free-air gradient of Gamma_zz, -3 Gamma/r)
//
// Topo: the paper's SRTM2gravity (90 m) cannot be had here. Instead a synthetic
// topography with realistic statistics is forward-modelled: a Gaussian random
// surface with the self-affine spectrum of land relief, 2-D PSD ~ k^-3
// (Hurst 0.5, 1-D profiles ~ k^-2), rms `topo_rms` (150 m), high-passed at
// 40 km (longer wavelengths are in EGM96), density 2670 kg/m^3, and its vertical
// gradient at the flight height by the first term of Parker's series:
//   Gamma_zz(k) = 2 pi G rho |k| exp(-|k| d) H(k),  d = 3000 m - mean terrain height.
// land(lat) = 0 over the Channel: the route leaves England at 50.70 N and reaches
// Normandy at 49.40 N (both read off a map; a 2 km taper), EGM96 alone there.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ggins::coldatom {

struct RouteMapParams {
  double lat0_deg = 53.407579, lon0_deg = -2.967853;  // Liverpool
  double lat1_deg = 43.604652, lon1_deg = 1.444209;   // Toulouse
  double h = 3000.0;                                  // m
  double half_width = 30e3;                           // m, corridor half width
  double margin = 20e3;                               // m, beyond both ends
  double egm_step = 4000.0;                           // m
  double topo_step = 250.0;                           // m
  double topo_rms = 150.0;                            // m
  double topo_mean = 150.0;                           // m
  double topo_highpass = 40e3;                        // m
  double rho = 2670.0;                                // kg/m^3
  double sea_lat_n = 50.70, sea_lat_s = 49.40;        // deg
  std::uint64_t seed = 2024;
  bool with_egm96 = true;                             // false: normal field only (tests)
  bool with_topo = true;
};

class RouteMap {
 public:
  // Builds (EGM96 grid cached in cache_dir when given and with_egm96).
  RouteMap(const RouteMapParams& p, const std::string& egm96_path, const std::string& cache_dir);
  // Gamma_zz (s^-2). false when (lat, lon) is outside the corridor.
  bool gzz(double lat_rad, double lon_rad, double h, double* out) const;
  // Route geometry
  double length() const { return L_; }
  void route_point(double s, double c, double* lat_rad, double* lon_rad) const;
  void route_coords(double lat_rad, double lon_rad, double* s, double* c) const;
  double heading(double s) const;  // rad from north, along the route at c = 0
  bool land(double lat_rad) const;
  // statistics of the synthetic part (for the report)
  double topo_height_rms() const { return topo_h_rms_; }
  double topo_gzz_rms() const { return topo_g_rms_; }
  const RouteMapParams& params() const { return p_; }

 private:
  double egm(double s, double c) const;
  double topo(double s, double c) const;
  RouteMapParams p_;
  double R_ = 0, L_ = 0;
  double p0_[3], e2_[3], n_[3];
  int egm_ns_ = 0, egm_nc_ = 0;
  std::vector<double> egm_;  // [is * nc + ic], s from -margin, c from -half_width
  int topo_ns_ = 0, topo_nc_ = 0;
  std::vector<float> topo_;
  double topo_s0_ = 0, topo_c0_ = 0;
  double topo_h_rms_ = 0, topo_g_rms_ = 0;
};

}  // namespace ggins::coldatom
