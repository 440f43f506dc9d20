/**
 * @file real.h
 * @brief Working precision and compensated accumulation.
 *
 * gg_real_t is `long double`: 64-bit mantissa on x86-64, but only a 53-bit
 * `double` on Arm Cortex-M (and on x86-64 built with -mlong-double-64).
 * Quantities that are *accumulated* over hours at 100 Hz or more
 * (position, velocity, the dead-reckoned gravitation G ~ 9.8 m/s^2 built
 * from ~1e-5 m/s^2 steps) are held in gg_acc_t, a compensated sum
 * (value = hi + lo, updated with Knuth's error-free TwoSum), so that the
 * rounding error of the running sum stays near 2^-106 relative whatever the
 * width of long double (see docs/design.md, "Numerical precision").
 *
 * Build switch GGINS_NAIVE_ACCUM (for the precision audit only): the
 * accumulators become plain `double` sums, to measure what compensation buys.
 */
#ifndef GGINS_REAL_H
#define GGINS_REAL_H

#include <math.h>

typedef long double gg_real_t;

/** Compensated accumulator: value = hi + lo, |lo| <= ulp(hi)/2. */
typedef struct {
    gg_real_t hi;
    gg_real_t lo;
} gg_acc_t;

/** Set an accumulator to x exactly. */
static inline void gg_acc_set(gg_acc_t *acc, gg_real_t x)
{
#ifdef GGINS_NAIVE_ACCUM
    acc->hi = (gg_real_t)(double)x;
#else
    acc->hi = x;
#endif
    acc->lo = 0.0L;
}

/** Add x to the accumulator (TwoSum, Knuth TAOCP vol. 2, 4.2.2). */
static inline void gg_acc_add(gg_acc_t *acc, gg_real_t x)
{
#ifdef GGINS_NAIVE_ACCUM
    acc->hi = (gg_real_t)((double)acc->hi + (double)x);
#else
    const gg_real_t s = acc->hi + x;
    const gg_real_t bp = s - acc->hi;
    const gg_real_t ap = s - bp;
    const gg_real_t err = (acc->hi - ap) + (x - bp);
    /* fold the error into lo, then renormalise (Fast2Sum, |s| >= |lo|) */
    const gg_real_t lo = acc->lo + err;
    const gg_real_t hi = s + lo;
    acc->lo = lo - (hi - s);
    acc->hi = hi;
#endif
}

/** Value of the accumulator, rounded to working precision. */
static inline gg_real_t gg_acc_value(const gg_acc_t *acc)
{
    return acc->hi + acc->lo;
}

/** Non-zero when x is a finite number (neither NaN nor infinite).
 *  C99 isfinite() is a type-generic macro; gcc expands it inline (no libm). */
#define GG_ISFINITE(x) (isfinite(x))

/** 1 when all three components are finite, else 0. */
static inline int gg_finite3(const gg_real_t v[3])
{
    return (GG_ISFINITE(v[0]) && GG_ISFINITE(v[1]) && GG_ISFINITE(v[2])) ? 1 : 0;
}

#endif /* GGINS_REAL_H */
