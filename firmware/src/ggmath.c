/* Elementary functions without libm (see ggmath.h). */
#include "ggins/ggmath.h"

#include <stddef.h>
#include <stdint.h>

/* pi/2 in four parts of at most 32 significant bits each (exact doubles) */
#define PIO2_1 0x1.921fb544p+0L
#define PIO2_2 0x1.0b4611a6p-34L
#define PIO2_3 0x1.3198a2ep-69L
#define PIO2_4 0x1.b839a252p-104L
#define TWO_OVER_PI 0.636619772367581343075535053490057448L

#define SIN_TERMS 14U  /* r^3 .. r^29 */
#define ATAN_TERMS 21U /* t^3 .. t^43 */

/* sum c[n] x^n, n = 0..deg (Horner) */
static gg_real_t horner(const gg_real_t c[], unsigned deg, gg_real_t x)
{
    gg_real_t p = c[deg];
    unsigned n;
    for (n = deg; n > 0U; --n) {
        p = (p * x) + c[n - 1U];
    }
    return p;
}

gg_status_t gg_sincos(gg_real_t x, gg_real_t *s, gg_real_t *c)
{
    /* (-1)^n/(2n+1)!, n = 0..14: sin r = r sum SIN_C[n] r^2n */
    static const gg_real_t SIN_C[15] = {
        1.0L,
        -1.66666666666666666666666666666666667e-1L,
        8.33333333333333333333333333333333333e-3L,
        -1.98412698412698412698412698412698413e-4L,
        2.75573192239858906525573192239858907e-6L,
        -2.50521083854417187750521083854417188e-8L,
        1.60590438368216145993923771701549479e-10L,
        -7.64716373181981647590113198578807044e-13L,
        2.81145725434552076319894558301032002e-15L,
        -8.22063524662432971695598123687228075e-18L,
        1.95729410633912612308475743735054304e-20L,
        -3.86817017063068403771691193152281232e-23L,
        6.44695028438447339619485321920468721e-26L,
        -9.1836898637955461484257168364739134e-29L,
        1.1309962886447716931558764576938317e-31L
    };
    /* (-1)^n/(2n)!, n = 0..14: cos r = sum COS_C[n] r^2n */
    static const gg_real_t COS_C[15] = {
        1.0L,
        -5.0e-1L,
        4.16666666666666666666666666666666667e-2L,
        -1.38888888888888888888888888888888889e-3L,
        2.48015873015873015873015873015873016e-5L,
        -2.75573192239858906525573192239858907e-7L,
        2.08767569878680989792100903212014323e-9L,
        -1.14707455977297247138516979786821057e-11L,
        4.77947733238738529743820749111754403e-14L,
        -1.56192069685862264622163643500573334e-16L,
        4.11031762331216485847799061843614037e-19L,
        -8.89679139245057328674889744250246834e-22L,
        1.6117375710961183490487133048011718e-24L,
        -2.47959626322479746007494354584795662e-27L,
        3.27988923706983791015204172731211193e-30L
    };
    gg_real_t kr;
    gg_real_t r;
    gg_real_t r2;
    gg_real_t ss;
    gg_real_t cc;
    long k;
    unsigned q;
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
    if (kr >= 0.0L) {
        kr += 0.5L;
    } else {
        kr -= 0.5L;
    }
    k = (long)kr;
    kr = (gg_real_t)k;
    r = (((x - (kr * PIO2_1)) - (kr * PIO2_2)) - (kr * PIO2_3)) - (kr * PIO2_4);
    r2 = r * r;
    /* sin r = r - r^3/3! + ...; cos r = 1 - r^2/2! + ... (Horner in r^2) */
    ss = r * horner(SIN_C, SIN_TERMS, r2);
    cc = horner(COS_C, SIN_TERMS, r2);
    {
        const long k4 = k & 3L;
        q = (unsigned)k4;
    }
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
    /* (-1)^n/(2n+1), n = 0..21: atan u = u sum ATAN_C[n] u^2n */
    static const gg_real_t ATAN_C[22] = {
        1.0L,
        -3.33333333333333333333333333333333333e-1L,
        2.0e-1L,
        -1.42857142857142857142857142857142857e-1L,
        1.11111111111111111111111111111111111e-1L,
        -9.09090909090909090909090909090909091e-2L,
        7.69230769230769230769230769230769231e-2L,
        -6.66666666666666666666666666666666667e-2L,
        5.88235294117647058823529411764705882e-2L,
        -5.26315789473684210526315789473684211e-2L,
        4.7619047619047619047619047619047619e-2L,
        -4.34782608695652173913043478260869565e-2L,
        4.0e-2L,
        -3.7037037037037037037037037037037037e-2L,
        3.44827586206896551724137931034482759e-2L,
        -3.22580645161290322580645161290322581e-2L,
        3.0303030303030303030303030303030303e-2L,
        -2.85714285714285714285714285714285714e-2L,
        2.7027027027027027027027027027027027e-2L,
        -2.5641025641025641025641025641025641e-2L,
        2.43902439024390243902439024390243902e-2L,
        -2.32558139534883720930232558139534884e-2L
    };
    gg_real_t u = t;
    gg_real_t u2;
    gg_real_t sum;
    unsigned h;
    for (h = 0U; h < 2U; ++h) {
        u = u / (1.0L + sqrtl(1.0L + (u * u)));
    }
    u2 = u * u;
    sum = u * horner(ATAN_C, ATAN_TERMS, u2);
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

/* ---- double precision (see ggmath.h) ---- */

#define LN2_HI 6.93147180369123816490e-01 /* fdlibm split of ln 2 */
#define LN2_LO 1.90821492927058770002e-10
#define PIO2_HI_D 1.57079632673412561417e+00 /* pi/2 split (double) */
#define PIO2_LO_D 6.07710050650619224932e-11

static double round_d(double x)
{
    return (x >= 0.0) ? (double)(int64_t)(x + 0.5) : -(double)(int64_t)(0.5 - x);
}

/* Powers 2^(2^j) and 2^-(2^j), j = 9..0 (exact binary values). */
static const double p2[10] = {1.3407807929942597e+154, 1.157920892373162e+77, 3.402823669209385e+38,
                                1.8446744073709552e+19, 4294967296.0, 65536.0, 256.0, 16.0, 4.0, 2.0};
static const int32_t p2exp[10] = {512, 256, 128, 64, 32, 16, 8, 4, 2, 1};
static const double p2inv[10] = {7.458340731200207e-155, 8.636168555094445e-78, 2.938735877055719e-39,
                                   5.421010862427522e-20, 2.3283064365386963e-10, 1.52587890625e-05,
                                   0.00390625, 0.0625, 0.25, 0.5};

/* y 2^k for |k| <= 1023 by binary decomposition of k (each factor exact). */
static double ldexp_d(double y, int32_t k)
{
    double r = y;
    int32_t a = (k < 0) ? -k : k;
    int32_t j;
    for (j = 0; j < 10; ++j) {
        const int32_t b = p2exp[j];
        if (a >= b) {
            r *= (k < 0) ? p2inv[j] : p2[j];
            a -= b;
        }
    }
    return r;
}

gg_status_t gg_exp_d(double x, double *y)
{
    double k;
    double r;
    double p;
    int i;
    if (y == NULL) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(x)) {
        return GG_ERR_NONFINITE;
    }
    if (x > 709.0) {
        return GG_ERR_RANGE;
    }
    if (x < -745.0) {
        *y = 0.0;
        return GG_OK;
    }
    /* x = k ln2 + r, |r| <= ln2/2; Taylor to r^14 (error < 1e-17 relative) */
    k = round_d(x / (LN2_HI + LN2_LO));
    r = (x - (k * LN2_HI)) - (k * LN2_LO);
    p = 1.0;
    for (i = 14; i >= 1; --i) {
        p = 1.0 + ((p * r) / (double)i);
    }
    if (k < -1000.0) { /* result subnormal: two steps keep the factors in range */
        *y = ldexp_d(ldexp_d(p, (int32_t)k + 600), -600);
    } else {
        *y = ldexp_d(p, (int32_t)k);
    }
    return GG_OK;
}

gg_status_t gg_log_d(double x, double *y)
{
    int32_t j;
    int32_t e;
    double m;
    double z;
    double z2;
    double s;
    double t;
    int i;
    if (y == NULL) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(x)) {
        return GG_ERR_NONFINITE;
    }
    if (!(x > 0.0)) {
        return GG_ERR_RANGE;
    }
    /* x = m 2^e, m in [1, 2): greedy binary search on the exponent (exact scalings) */
    e = 0;
    m = x;
    if (m < 2.2250738585072014e-308) { /* subnormal: scale by 2^54 first */
        m *= 18014398509481984.0;
        e = -54;
    }
    for (j = 0; j < 10; ++j) {
        const int32_t b = p2exp[j];
        if (m >= p2[j]) {
            m *= p2inv[j];
            e += b;
        }
    }
    for (j = 0; j < 10; ++j) {
        const int32_t b = p2exp[j];
        if ((m * p2[j]) < 2.0) {
            m *= p2[j];
            e -= b;
        }
    }
    if (m > 1.4142135623730951) {
        m *= 0.5;
        e += 1;
    }
    /* ln m = 2 atanh z, z = (m-1)/(m+1), |z| <= 0.1716: series to z^25 */
    z = (m - 1.0) / (m + 1.0);
    z2 = z * z;
    s = 0.0;
    for (i = 25; i >= 1; i -= 2) {
        s = (s * z2) + (1.0 / (double)i);
    }
    t = 2.0 * z * s;
    *y = (((double)e * LN2_HI) + t) + ((double)e * LN2_LO);
    return GG_OK;
}

gg_status_t gg_sincos_d(double x, double *s, double *c)
{
    double j;
    double r;
    double r2;
    double ps;
    double pc;
    double ss;
    double cc;
    int i;
    int64_t q;
    if ((s == NULL) || (c == NULL)) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(x)) {
        return GG_ERR_NONFINITE;
    }
    if ((x > (double)GG_MATH_ARG_MAX) || (x < -(double)GG_MATH_ARG_MAX)) {
        return GG_ERR_RANGE;
    }
    /* x = j pi/2 + r, |r| <= pi/4; Taylor to r^17 / r^16 */
    j = round_d(x / (PIO2_HI_D + PIO2_LO_D));
    r = (x - (j * PIO2_HI_D)) - (j * PIO2_LO_D);
    r2 = r * r;
    ps = 1.0;
    for (i = 17; i >= 3; i -= 2) {
        const int im1 = i - 1;
        ps = 1.0 - ((ps * r2) / ((double)i * (double)im1));
    }
    ps *= r;
    pc = 1.0;
    for (i = 16; i >= 2; i -= 2) {
        const int im1 = i - 1;
        pc = 1.0 - ((pc * r2) / ((double)i * (double)im1));
    }
    q = (int64_t)j;
    q = ((q % 4) + 4) % 4;
    if (q == 0) {
        ss = ps; cc = pc;
    } else if (q == 1) {
        ss = pc; cc = -ps;
    } else if (q == 2) {
        ss = -ps; cc = -pc;
    } else {
        ss = -pc; cc = ps;
    }
    *s = ss;
    *c = cc;
    return GG_OK;
}
