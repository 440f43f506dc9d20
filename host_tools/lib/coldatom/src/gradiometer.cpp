#include "ggins/coldatom/gradiometer.hpp"

#include <cmath>

namespace ggins::coldatom {

Gradiometer::Gradiometer(const GradiometerParams& p, std::uint64_t seed) : p_(p), rng_(seed) {}

double Gradiometer::expected_sigma() const {
  // Shot noise: s_j - b_j = P_j (1 + dN/N), std P_j / sqrt(N); E[P^2] = (1 + eta^2/2)/4.
  const double e2 = 0.25 * (1.0 + 0.5 * p_.contrast * p_.contrast);
  const double shot = p_.shot_noise ? std::sqrt(e2 / p_.n_atoms) : 0.0;
  // Phase noise moves s_1 along the fringe: ds_1 = eta/2 sin(.) eps -> rms eta/2 sigma / sqrt(2)
  // in s_1 alone; counted in full (upper bound) since only part is perpendicular.
  const double ph = 0.5 * p_.contrast * p_.phase_noise;
  return std::sqrt(shot * shot + ph * ph);
}

Shot Gradiometer::shot(double gamma_zz) {
  // Draw everything every shot, whatever the outcome, so that a change of
  // p_fail does not shift the random stream of the others.
  ShotDraws d;
  d.u_laser = u01_(rng_);
  d.z_phase = n01_(rng_);
  d.z_n0 = n01_(rng_);
  d.z_n1 = n01_(rng_);
  d.u_fail = u01_(rng_);
  if (p_.cloud_rw > 0) {
    d.z_walk.resize(2 * static_cast<size_t>(p_.rw_substeps));
    for (auto& z : d.z_walk) z = n01_(rng_);
  }
  return shot_from(p_, gamma_zz, d);
}

Shot shot_from(const GradiometerParams& p, double gamma_zz, const ShotDraws& d) {
  Shot s;
  s.dphi_true = p.scale() * gamma_zz;
  s.phi_laser = 2.0 * kPi * d.u_laser;
  const double eps1 = p.phase_noise * d.z_phase;
  double x = 0, y = 0, rmax = 0;
  if (p.cloud_rw > 0) {
    const double dt = 2.0 * p.T / p.rw_substeps;
    const double sd = p.cloud_rw * std::sqrt(dt);
    for (int k = 0; k < p.rw_substeps && 2 * static_cast<size_t>(k) + 1 < d.z_walk.size(); ++k) {
      x += sd * d.z_walk[2 * static_cast<size_t>(k)];
      y += sd * d.z_walk[2 * static_cast<size_t>(k) + 1];
      rmax = std::fmax(rmax, std::hypot(x, y));
    }
  }
  s.cloud_excursion = rmax;
  const double rel = p.shot_noise ? 1.0 / std::sqrt(p.n_atoms) : 0.0;
  const double p0 = 0.5 * (1.0 - p.contrast * std::cos(s.phi_laser));
  const double p1 = 0.5 * (1.0 - p.contrast * std::cos(s.phi_laser + s.dphi_true + eps1));
  s.s0 = (1.0 + rel * d.z_n0) * p0 + p.bias0;
  s.s1 = (1.0 + rel * d.z_n1) * p1 + p.bias1;
  if (d.u_fail < p.p_fail) {
    s.status = ShotStatus::kFailedRandom;
  } else if (p.cloud_rw > 0 && rmax > p.beam_radius) {
    s.status = ShotStatus::kFailedBeam;
  }
  return s;
}

}  // namespace ggins::coldatom
