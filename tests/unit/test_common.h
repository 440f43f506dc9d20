/* Includes CMocka needs, plus small helpers shared by the unit tests. */
#ifndef GGINS_TESTS_COMMON_H
#define GGINS_TESTS_COMMON_H
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* assert |got - want| <= tol, printing the numbers on failure */
#define assert_near(got, want, tol)                                                        \
    do {                                                                                   \
        const long double g_ = (long double)(got), w_ = (long double)(want),              \
                          t_ = (long double)(tol);                                         \
        if (!(fabsl(g_ - w_) <= t_)) {                                                     \
            fail_msg("%s = %.21Lg, want %.21Lg, |diff| %.3Lg > tol %.3Lg", #got, g_, w_,   \
                     fabsl(g_ - w_), t_);                                                  \
        }                                                                                  \
    } while (0)

static inline long double norm3l(const long double a[3], const long double b[3])
{
    long double s = 0.0L;
    for (int j = 0; j < 3; ++j) s += (a[j] - b[j]) * (a[j] - b[j]);
    return sqrtl(s);
}
#endif
