// Statistics of the Monte Carlo comparisons (montecarlo, montecarlo3d,
// rw-eq8): the acceptance band of a sample mean square against a predicted
// variance.
//
// With N zero-mean Gaussian errors of predicted variance sigma^2 the sample
// mean square ms = sum e^2 / N satisfies N ms / sigma^2 ~ chi^2_N. The band is
// the two-sided chi-square interval between the quantiles at the
// standard-normal points z_lo < 0 < z_hi, by the Wilson-Hilferty approximation
//   chi^2_N(z) ~ N (1 - 2/(9N) + z sqrt(2/(9N)))^3,
// for ms / sigma^2 and for the rms ratio s / sigma = sqrt(ms) / sigma.
#pragma once

namespace ggins::truth {

// Standard normal quantile (Acklam's rational approximation, |rel err| < 1.2e-9), 0 < p < 1.
double normal_quantile(double p);

// chi^2_N quantile at the standard-normal point z (Wilson-Hilferty).
double chi2_quantile_wh(double n, double z);

struct Chi2Band {
  double ms_lo = 0, ms_hi = 0;    // band of ms / sigma^2
  double rms_lo = 0, rms_hi = 0;  // band of s / sigma
};

// The band between the quantiles at z_lo and z_hi for N degrees of freedom.
Chi2Band chi2_band(double n, double z_lo, double z_hi);
// At +-z standard-normal quantiles (z = 3: 99.73 % two-sided).
inline Chi2Band chi2_band(double n, double z) { return chi2_band(n, -z, z); }
// With a two-sided coverage c (0.5 < c < 1): z = quantiles at (1 -+ c) / 2.
Chi2Band chi2_band_coverage(double n, double coverage);

}  // namespace ggins::truth
