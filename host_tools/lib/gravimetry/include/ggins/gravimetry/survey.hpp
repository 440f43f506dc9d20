// Post-mission airborne gravimetry from a flight's along-track record
// (gravimetry_raw.csv of ggins run3d: apps/run3d/gravimetry_record.hpp states every column).
//
// Quantities (SI inside, survey units on output):
//   disturbance  dg = g - gamma at the navigation's position, NED (m/s^2); the scalar
//                "gravity disturbance" is its down component (positive: gravity stronger
//                than normal), output in mGal (1 mGal = 1e-5 m/s^2);
//   deflections  xi = -dg_N / |g|, eta = -dg_E / |g| (north and east components of the
//                deflection of the vertical, positive when the plumb line's up direction
//                leans north / east of the ellipsoid normal), output in arcsec.
//
// Where the value belongs. The task dead-reckons G with the gradient MEASURED where the aircraft
// is, integrated along its own solution: G_nav(t) = G(r_0) + int Gamma(r_true) dr_nav. The
// normal field's share follows the navigation's position (Gamma_normal dr), and the anomaly's
// follows the true path (its gradient changes in a few km; the position error in hours), so
// to first order est = dG(r_true) + (the normal field's G(r_nav) - gamma(r_nav) = 0): the
// disturbance where the aircraft WAS, tagged with where the navigation says it was. The
// product is compared with the truth along the true path; a map georeferenced by the nav's
// positions reads Gamma_anom dr_nav off besides (stated apart, rms_true_pos_mgal).
//
// Error model of the gradiometer system's estimate (gradiometer mode), per NED component
// e(t) = est(t) - truth(r_true(t)): a Brownian motion in the accumulated variance tau(t)
// (white gradient noise integrated along the path) plus a constant gradient error dGamma_b in
// body axes, entries independent with sigma_Gb, whose share is sum_kl dGamma_b,kl B_j,kl(t), so
//   K_j(t, s) = min(tau_j,t, tau_j,s) + sigma_Gb^2 B_j(t) . B_j(s),   e(0) = 0
// (the task starts from the surveyed gravitation of its start point). Observations are
// linear in e: a closing measurement (back over the zero point: e = est - known - the
// measured gradient's disturbance times the nav's offset from the point; Rubenstein &
// Winter's return to the zero point) and line crossovers (two passes over the same nav
// point: e_A - e_B = est_A - est_B - dGamma (r_A - r_B), noisy by the two passes' position
// errors). The post-mission estimate is the
// Gaussian-process posterior given all of them (the flight is over: every observation
// informs every sample, before and after it):
//   e_hat(t) = k_t^T S^-1 y,   var(t) = K(t, t) - k_t^T S^-1 k_t,
//   S = A K A^T + R,  k_t = A K(., t)   (A the observations' coefficients on the samples).
// For a Brownian motion this is the piecewise-linear (in tau) bridge between observations.
//
// Rubenstein & Winter's gravimeter (model mode): the loop's output -a_c = H_g(s) dg is inverted
// after the flight within the product's band (make_product), so that its lag and attenuation
// do not count against it.
//
// Filter: zero-phase low-pass (a Butterworth of order n run forward and backward), cut-off
// at the spatial frequency 1/lambda converted to time with the line's mean ground speed;
// the amplitude response at the full wavelength lambda is 1/2 (|H|^2 of one pass).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ggins::gravimetry {

using V3 = std::array<double, 3>;

struct Sample {  // one row of gravimetry_raw.csv
  double t = 0;
  int64_t seq = 0;
  double lat_deg = 0, lon_deg = 0, h_m = 0;              // navigation
  double true_lat_deg = 0, true_lon_deg = 0, true_h_m = 0;
  double speed_mps = 0;
  V3 est{}, truth_nav{}, truth_true{};                   // disturbance, NED, m/s^2
  double a_c = 0;
  V3 var_rw{};                                           // random-walk variance per NED component, (m/s^2)^2
  std::array<std::array<double, 9>, 3> bias_coef{};     // B_j,kl: component j's coefficients of a body-axis
                                                         // constant gradient error (integral C_b_n,jk dr_b,l), m
  std::array<double, 6> gam_E{};                         // measured gradient's disturbance NN EE DD NE ND ED, E
  uint32_t health = 0;
  // filled by read_record: nav position in the local plane of the first sample (east,
  // north, up, m), and |g| (normal gravity) there
  V3 enu{}, true_enu{};
  double g_abs = 9.8;
};

struct Record {
  std::vector<Sample> s;
  std::string mode = "gradiometer";  // or "model": the R&W loop's estimate, no error model
  std::string field;
  double sigma_gamma_bias_ps2 = 0;
  std::vector<double> loop_poles;  // the barometer loop's poles (rad/s; empty: loop off, or not inverted)
  double rate_hz = 1;
};

// Reads <dir>/gravimetry_raw.csv and <dir>/summary.json's "gravimetry" block. Throws
// std::runtime_error naming the file and line on anything it cannot use.
Record read_record(const std::filesystem::path& run_dir);

struct Line {
  int number = 0;        // survey numbering: lines 10, 20, ...; ties 1000, 1010, ...
  bool tie = false;
  size_t begin = 0, end = 0;  // samples [begin, end)
  double heading_deg = 0;     // mean track heading
  double length_m = 0;
  double speed_mps = 0;       // mean ground speed
};

struct LineOptions {
  double max_turn_dps = 0.1;     // a line: |track heading rate| below this ...
  double max_climb_mps = 1.0;    // ... and |vertical speed| below this
  double min_length_m = 10000;   // ... for at least this far
  double smooth_s = 10;          // heading rate taken over this window
};
// Straight level stretches of the nav track; the commonest heading (mod 180, 10 deg bins,
// by length) are the lines, the others ties.
std::vector<Line> find_lines(const Record& r, const LineOptions& o);

struct Observation {  // y = sum coef_j e(sample_j) + noise (var), per component
  std::string kind;   // "closing" or "crossover"
  std::vector<std::pair<size_t, double>> coef;
  V3 y{};
  double var = 0;
  int line_a = 0, line_b = 0;  // crossover: the two lines' numbers
  double lat_deg = 0, lon_deg = 0;
};

struct ClosingOptions {
  bool enable = true;
  double radius_m = 500;  // the true track passes the zero point within this
};
// The closing measurement: the first time after leaving it (beyond 10 radius_m) that the
// aircraft comes back within radius_m of the start point (the pilot's mark over the zero
// point, or the landing on it: the moment and the offset are taken from the simulation's
// true track, as the mark gives them), known value the start's own disturbance.
bool closing(const Record& r, const ClosingOptions& o, Observation& out);
// Crossovers of every pair of lines whose nav tracks cross. The two passes over one nav point
// were at true points apart by the difference of their position errors: the observation's
// variance carries |Gamma_anom|^2 2 position_sigma_m^2 (Gamma_anom the measured gradient's
// disturbance there; the nav's horizontal one-sigma, no GNSS).
std::vector<Observation> crossovers(const Record& r, const std::vector<Line>& lines, double position_sigma_m);

struct Adjusted {
  std::vector<V3> value;      // corrected estimate, NED, m/s^2
  std::vector<V3> sigma;      // one-sigma of each component (NaN: no error model)
  std::vector<V3> residual;   // observation residuals after the adjustment (y - A e_hat)
};
Adjusted adjust(const Record& r, const std::vector<Observation>& obs);

// Zero-phase Butterworth low-pass of order `order` (even, 2..8), cut-off fc (Hz) at sample
// interval dt (s); edges padded by odd reflection. Amplitude response |H(f)|^2 of one pass.
std::vector<double> lowpass(const std::vector<double>& x, double dt, double fc, int order = 4);
double lowpass_gain(double f, double fc, int order = 4);  // analytic response, both passes

struct LineStats {
  int number = 0;
  bool tie = false;
  size_t n = 0;
  // against the truth along the TRUE path (the disturbance where the aircraft was)
  double rms_mgal = 0, max_mgal = 0;          // scalar dg (down)
  double rms_h_mgal = 0;                      // horizontal components (rms of N and E)
  double rms_xi_arcsec = 0, rms_eta_arcsec = 0;
  double rms_true_pos_mgal = 0;               // scalar against the truth at the NAV position (the map as
                                              // georeferenced by the navigation: + Gamma dr_nav)
  double rms_sigma_mgal = 0;                  // rms of the stated one-sigma
  double nmse = 0;                            // mean over samples and components of (err / sigma)^2
  double signal_rms_mgal = 0;                 // rms of the filtered truth (scalar)
  double pos_err_rms_m = 0;                   // horizontal nav position error
};

struct Product {
  double wavelength_m = 0;
  std::vector<Line> lines;
  std::vector<size_t> idx;            // the samples of the lines, in line order
  std::vector<int> line_of;           // per idx entry: the line's number
  std::vector<V3> est, truth, truth_true;  // filtered, NED, m/s^2
  std::vector<V3> sigma;
  std::vector<LineStats> stats;
  LineStats all;                      // pooled over the lines
};
Product make_product(const Record& r, const std::vector<Line>& lines, const Adjusted& a, double wavelength_m);

// A gridded map of the product: nodes every `spacing_m` over the lines' extent (in the local
// east-north plane of the first sample), each the Gaussian-weighted mean (sigma = radius / 2)
// of the samples within `radius_m` of it (NaN where there are none), for the estimate and
// for the truth along the true path alike. Columns: lat, lon, dg, truth, error (mGal), samples.
struct GridNode {
  double lat_deg = 0, lon_deg = 0, dg = 0, truth = 0;
  int n = 0;
};
struct Grid {
  size_t nx = 0, ny = 0;
  double spacing_m = 0, radius_m = 0;
  std::vector<GridNode> node;  // row-major, south to north, west to east
};
Grid make_grid(const Record& r, const Product& p, double spacing_m, double radius_m);
void write_grid_csv(const std::filesystem::path& p, const Grid& g);

// Survey line formats: CSV (a header row, one row per sample) and Geosoft-style XYZ ("/"
// comment header, "Line N" / "Tie N" blocks).
void write_csv(const std::filesystem::path& p, const Record& r, const Product& pr);
void write_xyz(const std::filesystem::path& p, const Record& r, const Product& pr, const std::string& title);

constexpr double kMgal = 1e-5;                          // m/s^2
constexpr double kArcsec = 4.84813681109536e-6;         // rad

}  // namespace ggins::gravimetry
