/* Elementary functions without libm (see ggmath.h). */
#include "ggins/ggmath.h"

#include <stddef.h>

/* pi/2 in four parts of at most 32 significant bits each (exact doubles) */
#define PIO2_1 0x1.921fb544p+0L
#define PIO2_2 0x1.0b4611a6p-34L
#define PIO2_3 0x1.3198a2ep-69L
#define PIO2_4 0x1.b839a252p-104L
#define TWO_OVER_PI 0.636619772367581343075535053490057448L

#define SIN_TERMS 14U  /* r^3 .. r^29 */
#define ATAN_TERMS 21U /* t^3 .. t^43 */

gg_status_t gg_sincos(gg_real_t x, gg_real_t *s, gg_real_t *c)
{
    gg_real_t kr;
    gg_real_t r;
    gg_real_t r2;
    gg_real_t ts;
    gg_real_t tc;
    gg_real_t ss;
    gg_real_t cc;
    long k;
    unsigned q;
    unsigned n;
    if ((s == NULL) || (c == NULL)) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(x)) {
        return GG_ERR_NONFINITE;
    }
    if ((x > GG_MATH_ARG_MAX) || (x < -GG_MATH_ARG_MAX)) {
        return GG_ERR_RANGE;
    }
    /* nearest integer k of x / (pi/2), without libm rounding functions */
    kr = x * TWO_OVER_PI;
    k = (long)((kr >= 0.0L) ? (kr + 0.5L) : (kr - 0.5L));
    kr = (gg_real_t)k;
    r = (((x - (kr * PIO2_1)) - (kr * PIO2_2)) - (kr * PIO2_3)) - (kr * PIO2_4);
    r2 = r * r;
    /* sin r = r - r^3/3! + ...; cos r = 1 - r^2/2! + ... (term recursion) */
    ts = r;
    ss = r;
    tc = 1.0L;
    cc = 1.0L;
    for (n = 1U; n <= SIN_TERMS; ++n) {
        const gg_real_t m = (gg_real_t)(2U * n);
        tc = -tc * r2 / ((m - 1.0L) * m);
        ts = -ts * r2 / (m * (m + 1.0L));
        cc += tc;
        ss += ts;
    }
    q = (unsigned)(k & 3L);
    if (q == 0U) {
        *s = ss;
        *c = cc;
    } else if (q == 1U) {
        *s = cc;
        *c = -ss;
    } else if (q == 2U) {
        *s = -ss;
        *c = -cc;
    } else {
        *s = -cc;
        *c = ss;
    }
    return GG_OK;
}

/* atan t for 0 <= t <= 1 */
static gg_real_t atan_unit(gg_real_t t)
{
    gg_real_t u = t;
    gg_real_t u2;
    gg_real_t p;
    gg_real_t sum;
    unsigned n;
    unsigned h;
    for (h = 0U; h < 2U; ++h) {
        u = u / (1.0L + sqrtl(1.0L + (u * u)));
    }
    u2 = u * u;
    p = u;
    sum = u;
    for (n = 1U; n <= ATAN_TERMS; ++n) {
        p = -p * u2;
        sum += p / (gg_real_t)((2U * n) + 1U);
    }
    return 4.0L * sum;
}

gg_status_t gg_atan2(gg_real_t y, gg_real_t x, gg_real_t *a)
{
    const gg_real_t ax = (x < 0.0L) ? -x : x;
    const gg_real_t ay = (y < 0.0L) ? -y : y;
    gg_real_t t;
    if (a == NULL) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(x) || !GG_ISFINITE(y)) {
        return GG_ERR_NONFINITE;
    }
    if ((ax == 0.0L) && (ay == 0.0L)) {
        *a = 0.0L;
        return GG_OK;
    }
    /* angle of (ax, ay) in [0, pi/2] */
    if (ay <= ax) {
        t = atan_unit(ay / ax);
    } else {
        t = (0.5L * GG_PI) - atan_unit(ax / ay);
    }
    if (x < 0.0L) {
        t = GG_PI - t;
    }
    *a = (y < 0.0L) ? -t : t;
    return GG_OK;
}
