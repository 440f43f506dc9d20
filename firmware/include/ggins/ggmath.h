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
 */
#ifndef GGINS_GGMATH_H
#define GGINS_GGMATH_H

#include "ggins/real.h"
#include "ggins/status.h"

/** Largest |x| gg_sincos accepts, rad. */
#define GG_MATH_ARG_MAX 1.0e6L

/** pi to the precision of gg_real_t. */
#define GG_PI 3.141592653589793238462643383279502884L

/** *s = sin x, *c = cos x. GG_ERR_NONFINITE for NaN/Inf, GG_ERR_RANGE for
 *  |x| > GG_MATH_ARG_MAX (outputs untouched). */
gg_status_t gg_sincos(gg_real_t x, gg_real_t *s, gg_real_t *c);

/** *a = atan2(y, x) in (-pi, pi]; atan2(0, 0) = 0. GG_ERR_NONFINITE for
 *  NaN/Inf (output untouched). */
gg_status_t gg_atan2(gg_real_t y, gg_real_t x, gg_real_t *a);

#endif /* GGINS_GGMATH_H */
