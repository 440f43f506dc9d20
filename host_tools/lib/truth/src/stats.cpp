#include "ggins/truth/stats.hpp"

#include <cmath>

namespace ggins::truth {

double normal_quantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double pl = 0.02425;
  if (p < pl) {
    const double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > 1 - pl) return -normal_quantile(1 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

double chi2_quantile_wh(double n, double z) {
  const double k = 2.0 / (9.0 * n);
  const double t = 1.0 - k + z * std::sqrt(k);
  return n * t * t * t;
}

Chi2Band chi2_band(double n, double z_lo, double z_hi) {
  Chi2Band b;
  b.ms_lo = chi2_quantile_wh(n, z_lo) / n;
  b.ms_hi = chi2_quantile_wh(n, z_hi) / n;
  b.rms_lo = std::sqrt(b.ms_lo);
  b.rms_hi = std::sqrt(b.ms_hi);
  return b;
}

Chi2Band chi2_band_coverage(double n, double coverage) {
  const double p_lo = 0.5 * (1 - coverage), p_hi = 1 - p_lo;
  return chi2_band(n, normal_quantile(p_lo), normal_quantile(p_hi));
}

}  // namespace ggins::truth
