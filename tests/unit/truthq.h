/* Truth for the precision audit in IEEE binary128 (__float128, libquadmath):
 * independent of the width of `long double`, so the same truth serves the
 * native build (64-bit mantissa long double), the -mlong-double-64 build
 * (long double = double, the Cortex-M ABI) and the naive build. Spherical
 * point-mass Earth and the analytic north flight of docs/design.md. */
#ifndef GGINS_TESTS_TRUTHQ_H
#define GGINS_TESTS_TRUTHQ_H

/* binary128 in every variant: x87 extended truth (64-bit mantissa) was
 * tried and is not enough - its own rounding along a 10 h walk showed up as
 * 2.6e-6 m of "error" in the native loop test. */
#include <quadmath.h>
typedef __float128 q_t;
#define Q_(x) x##Q

#define Q_GM Q_(3.986004418e14)
#define Q_RE Q_(6378137.0)

/* G = -GM p/|p|^3 */
static inline void q_point_mass_g(const q_t p[3], q_t g[3])
{
    const q_t r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const q_t rn = sqrtq(r2);
    const q_t k = Q_GM / (r2 * rn);
    for (int j = 0; j < 3; ++j) g[j] = -k * p[j];
}

/* Gamma = (GM/|p|^3)(3 p^ p^T - I) */
static inline void q_point_mass_gamma(const q_t p[3], q_t gam[3][3])
{
    const q_t r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const q_t rn = sqrtq(r2);
    const q_t k = Q_GM / (r2 * rn);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) gam[j][i] = k * (3 * p[j] * p[i] / r2 - (i == j ? 1 : 0));
}

typedef struct {
    q_t v, h, lat0;
} q_flight_t;

/* r = (R+h)(cos L, 0, sin L), v = V(-sin L, 0, cos L), a = -(V^2/(R+h)) r^, L = L0 + V t/(R+h) */
static inline void q_flight(const q_flight_t *fl, q_t t, q_t r[3], q_t v[3], q_t a[3])
{
    const q_t rho = Q_RE + fl->h;
    const q_t lat = fl->lat0 + fl->v * t / rho;
    const q_t c = cosq(lat), s = sinq(lat);
    const q_t w2 = fl->v * fl->v / rho;
    r[0] = rho * c; r[1] = 0; r[2] = rho * s;
    v[0] = -fl->v * s; v[1] = 0; v[2] = fl->v * c;
    a[0] = -w2 * c; a[1] = 0; a[2] = -w2 * s;
}

/* f_i = a - G(r + d_i) at offsets 1:(+a,0) 2:(0,+b) 3:(-a,0) 4:(0,-b) */
static inline void q_sensor_forces(const q_t r[3], const q_t acc[3], q_t a_m, q_t b_m,
                                   q_t f[4][3])
{
    const q_t off[4][3] = {{a_m, 0, 0}, {0, 0, b_m}, {-a_m, 0, 0}, {0, 0, -b_m}};
    for (int i = 0; i < 4; ++i) {
        q_t p[3], g[3];
        for (int j = 0; j < 3; ++j) p[j] = r[j] + off[i][j];
        q_point_mass_g(p, g);
        for (int j = 0; j < 3; ++j) f[i][j] = acc[j] - g[j];
    }
}

static inline double q_norm_diff(const q_t a[3], const q_t b[3])
{
    q_t s = 0;
    for (int j = 0; j < 3; ++j) s += (a[j] - b[j]) * (a[j] - b[j]);
    return (double)sqrtq(s);
}
#endif
