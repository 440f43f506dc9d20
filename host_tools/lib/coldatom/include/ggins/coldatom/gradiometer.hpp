// Cold-atom vertical gravity gradiometer model (Phillips et al., "position fixing
// with partial gravity gradient measurements from cold atom interferometers",
// section II, eqs. 1-3).
//
// Two interferometers a vertical distance dz apart share one Raman laser whose
// phase phi_L is unknown and random per shot. Each shot n (at f_meas = 1 Hz)
// gives the pair of normalised signals (paper eq. 1, divided by the mean atom
// number N as the paper does):
//
//   s_j(n) = (1 + dN_j(n)/N) * 1/2 * [1 - eta cos(phi_L(n) + phi_j + eps_j(n))] + b_j,  j = 0, 1
//
//   eta     fringe contrast (measurement efficiency)
//   dN_j    atom-number shot noise, Gaussian, standard deviation sqrt(N)
//   phi_L   laser phase, uniform on [0, 2 pi), common to both interferometers
//   eps_1   phase noise, Gaussian, sigma_phi (eps_0 = 0: the upper
//           interferometer's phase noise is subsumed in phi_L, as in the paper)
//   b_j     signal biases (the paper's s0, s1)
//   phi_0   = 0 (the common gravity phase k_eff g T^2 is subsumed in phi_L),
//   phi_1   = dphi = k_eff Gamma_zz dz T^2   (paper eq. 2)
//
// Gamma_zz is the TRUE vertical gradient dG_D/dD (NED, positive, ~3086 E at the
// surface) at the shot's position: the lower interferometer sees the larger g.
// Without noise the pairs lie on the ellipse (x = (1/2 + b_0 - s_0)/(eta/2),
// y likewise):  x^2 - 2 x y cos(dphi) + y^2 = sin^2(dphi)   (paper eq. 3 form).
//
// Failed shots: with probability p_fail, and whenever the atom cloud, which
// performs a horizontal random walk (platform vibration) during the 2T
// interferometer sequence, leaves the Raman beam (radius beam_radius).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace ggins::coldatom {

constexpr double kPi = 3.14159265358979323846;

// Values the paper's text lost are chosen here (docs/cold-atom-pf.md says why).
struct GradiometerParams {
  double wavelength = 852.347e-9;  // Cs D2 line, m; k_eff = 2 * 2 pi / lambda (counter-propagating Raman pair)
  double T = 0.16;                 // s, time between the pi/2 and the pi pulse (paper)
  double dz = 1.0;                 // m, vertical separation (lost in the text; chosen)
  double rate_hz = 1.0;            // shots per second (paper)
  double n_atoms = 1e5;            // mean atoms per shot (lost; chosen) -> shot noise 1/sqrt(N) relative
  double contrast = 0.5;           // eta (lost; chosen)
  double bias0 = 0.0, bias1 = 0.0; // b_0, b_1 (paper's s0, s1)
  double phase_noise = 0.0;        // sigma_phi, rad
  bool shot_noise = true;
  double p_fail = 0.0;             // probability of a failed shot (independent of the random walk)
  double cloud_rw = 0.0;           // m / sqrt(s): horizontal random walk of the cloud (per axis); 0 = off
  double beam_radius = 6e-3;       // m
  int rw_substeps = 32;            // random-walk steps over the 2T sequence
  double k_eff() const { return 4.0 * kPi / wavelength; }
  // dphi per unit gradient: k_eff dz T^2 (rad per s^-2)
  double scale() const { return k_eff() * dz * T * T; }
};

enum class ShotStatus { kOk = 0, kFailedRandom = 1, kFailedBeam = 2 };

struct Shot {
  ShotStatus status = ShotStatus::kOk;
  double s0 = 0, s1 = 0;       // normalised signals (valid when status == kOk)
  // truth, for diagnostics and tests only (the filter never sees these)
  double phi_laser = 0;        // rad
  double dphi_true = 0;        // k_eff Gamma_zz dz T^2, rad
  double cloud_excursion = 0;  // max horizontal distance of the cloud from the beam axis, m
};

// The random draws of one shot, in the order Gradiometer::shot takes them from its
// generator: the laser phase's uniform, the phase noise's normal, the two shot-noise
// normals, the failure uniform, then (cloud_rw > 0) rw_substeps pairs of normals of the
// cloud's walk. A generator of its own (e.g. counter-based, so that shot n is a pure
// function of (seed, n)) fills them and calls shot_from.
struct ShotDraws {
  double u_laser = 0, z_phase = 0, z_n0 = 0, z_n1 = 0, u_fail = 1;
  std::vector<double> z_walk;  // 2 * rw_substeps normals (x, y per sub-step), when cloud_rw > 0
};

// Paper eqs. 1-2 for one shot at the true vertical gradient gamma_zz (s^-2) with the given draws.
Shot shot_from(const GradiometerParams& p, double gamma_zz, const ShotDraws& d);

class Gradiometer {
 public:
  Gradiometer(const GradiometerParams& p, std::uint64_t seed);
  // One shot at the true vertical gradient gamma_zz (s^-2).
  Shot shot(double gamma_zz);
  const GradiometerParams& params() const { return p_; }
  // rms of the perpendicular scatter of a pair about its ellipse, signal units:
  // shot noise (eta-independent part ~ P/sqrt(N), P ~ 1/2) and eta/2 sigma_phi.
  double expected_sigma() const;

 private:
  GradiometerParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n01_{0.0, 1.0};
  std::uniform_real_distribution<double> u01_{0.0, 1.0};
};

}  // namespace ggins::coldatom
