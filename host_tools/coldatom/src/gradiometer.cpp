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
  Shot s;
  s.dphi_true = p_.scale() * gamma_zz;
  // Draw everything every shot, whatever the outcome, so that a change of
  // p_fail does not shift the random stream of the others.
  s.phi_laser = 2.0 * kPi * u01_(rng_);
  const double eps1 = p_.phase_noise * n01_(rng_);
  const double dn0 = n01_(rng_), dn1 = n01_(rng_);
  const double u_fail = u01_(rng_);
  double x = 0, y = 0, rmax = 0;
  if (p_.cloud_rw > 0) {
    const double dt = 2.0 * p_.T / p_.rw_substeps;
    const double sd = p_.cloud_rw * std::sqrt(dt);
    for (int k = 0; k < p_.rw_substeps; ++k) {
      x += sd * n01_(rng_);
      y += sd * n01_(rng_);
      rmax = std::fmax(rmax, std::hypot(x, y));
    }
  }
  s.cloud_excursion = rmax;
  const double rel = p_.shot_noise ? 1.0 / std::sqrt(p_.n_atoms) : 0.0;
  const double p0 = 0.5 * (1.0 - p_.contrast * std::cos(s.phi_laser));
  const double p1 = 0.5 * (1.0 - p_.contrast * std::cos(s.phi_laser + s.dphi_true + eps1));
  s.s0 = (1.0 + rel * dn0) * p0 + p_.bias0;
  s.s1 = (1.0 + rel * dn1) * p1 + p_.bias1;
  if (u_fail < p_.p_fail) {
    s.status = ShotStatus::kFailedRandom;
  } else if (p_.cloud_rw > 0 && rmax > p_.beam_radius) {
    s.status = ShotStatus::kFailedBeam;
  }
  return s;
}

}  // namespace ggins::coldatom
