/**
 * @file ggmath.h
 * @brief Elementary functions for the firmware without libm: sine, cosine
 *        and two-argument arctangent in gg_real_t (long double on the host,
 *        double on the Cortex-M, whose image links no libm).
 *
 * sin/cos: Cody-Waite reduction x = k pi/2 + r with pi/2 split into four
 * 32-bit parts (k * part is exact for |k| <= 2^20, hence |x| <= GG_MATH_ARG_MAX),
 * then the Taylor series of sin r and cos r on |r| <= pi/4 to the term in
 * r^29 (truncation < 1e-33). atan2: octant reduction to t = |y|/|x| in
 * [0, 1], two half-angle reductions atan t = 2 atan(t / (1 + sqrt(1 + t^2)))
 * to |t| <= tan(pi/16), then the series t - t^3/3 + ... to t^43 (truncation
 * < 1e-31). Errors are a few units in the last place of gg_real_t (tested
 * against the C library in tests/unit/test_ggmath.c). Loops have fixed trip
 * counts. Angles in radians.
 *
 * Two precisions, one place. The navigation path works in gg_real_t
 * (gg_sincos, gg_atan2 above); the aiding filters' per-sample work (the
 * particle filter's likelihoods and weights, the UKF's double state) in
 * double, cheaper on the Cortex-M and all their state holds:
 *  - gg_sqrt_d: sqrt through sqrtl (one rounding on the Cortex-M, where
 *    long double is double; inlined to the FPU instruction with
 *    -fno-math-errno, so no libm);
 *  - gg_exp_d: x = k ln2 + r, |r| <= ln2/2 (ln 2 split as in fdlibm), Taylor
 *    to r^14 (< 1e-17 relative), 2^k by exact binary factors; 0 below -745,
 *    GG_ERR_RANGE above 709;
 *  - gg_log_d: x = m 2^e with m in [1/sqrt 2, sqrt 2) by exact scalings,
 *    ln m = 2 atanh((m - 1)/(m + 1)) to z^25; subnormals scaled by 2^54 first;
 *  - gg_sincos_d: x = j pi/2 + r (pi/2 in two parts), Taylor to r^17 / r^16
 *    (abs. error ~ |x| eps from the reduction, |x| <= GG_MATH_ARG_MAX).
 */
#ifndef GGINS_GGMATH_H
#define GGINS_GGMATH_H

#include "ggins/limits.h"
#include "ggins/real.h"
#include "ggins/status.h"

/** pi to the precision of gg_real_t. */
#define GG_PI 3.141592653589793238462643383279502884L

/** *s = sin x, *c = cos x. GG_ERR_NONFINITE for NaN/Inf, GG_ERR_RANGE for
 *  |x| > GG_MATH_ARG_MAX (outputs untouched). */
gg_status_t gg_sincos(gg_real_t x, gg_real_t *s, gg_real_t *c);

/** *a = atan2(y, x) in (-pi, pi]; atan2(0, 0) = 0. GG_ERR_NONFINITE for
 *  NaN/Inf (output untouched). */
gg_status_t gg_atan2(gg_real_t y, gg_real_t x, gg_real_t *a);

/** sqrt x in double, x >= 0 (no check: callers pass sums of squares). */
static inline double gg_sqrt_d(double x)
{
    return (double)sqrtl((long double)x);
}

/** *y = e^x. GG_ERR_NONFINITE for NaN/Inf, GG_ERR_RANGE for x > 709
 *  (output untouched); 0 for x < -745. */
gg_status_t gg_exp_d(double x, double *y);

/** *y = ln x. GG_ERR_NONFINITE for NaN/Inf, GG_ERR_RANGE for x <= 0. */
gg_status_t gg_log_d(double x, double *y);

/** *s = sin x, *c = cos x in double. GG_ERR_NONFINITE for NaN/Inf,
 *  GG_ERR_RANGE for |x| > GG_MATH_ARG_MAX. */
gg_status_t gg_sincos_d(double x, double *s, double *c);

#endif /* GGINS_GGMATH_H */
