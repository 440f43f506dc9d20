/* The particle filter's units shared between its source files (pf.c: the
 * filter core; pf_meas.c: the measurement model; pf_rb.c: the
 * Rao-Blackwellised process model). Internal to the firmware library. */
#ifndef GGINS_PF_INT_H
#define GGINS_PF_INT_H

#include "ggins/geo.h"
#include "ggins/pf.h"

#define PF_G0 ((double)GG_G0_STD_MPS2)          /* m/s^2, Schuler frequency w_s^2 = g0 / R */
#define PF_OMEGA_E ((double)GG_WGS84_OMEGA_IE)  /* rad/s, Earth rate (Coriolis) */
#define PF_RB_NDYN 7 /* RBPF states 0..6 move; 7..11 (j, b) are constant in the model (rows of F = I) */

/* WGS-84 radii at geodetic latitude (sin sl) and height h: meridian radius + h and
 * prime-vertical radius + h. */
typedef struct {
    double rm;
    double rnh;
} pf_radii_t;

pf_radii_t pf_radii(double sl, double h);

/* RBPF prediction, the part shared by all particles: F, Q, the gain and the
 * position noise factor of the shot in the state, P committed (untouched on error). */
gg_status_t pf_rb_common(gg_pf_t *st, const gg_pf_input_t *in, double sl, double cl, pf_radii_t r);

/* RBPF prediction of particle i with the drawn normals (z0, z1):
 * e = L z, r <- F_rr r + F_rl m + e, m <- F_lr r + F_ll m + K e. */
static inline void pf_rb_particle(gg_pf_t *st, int i, double z0, double z1)
{
    double xn[GG_PF_NX];
    const double e0 = st->rb_L[0] * z0;
    const double e1 = (st->rb_L[1] * z0) + (st->rb_L[2] * z1);
    int j;
    int q;
    for (j = 0; j < PF_RB_NDYN; ++j) {
        double a = 0.0;
        for (q = 0; q < GG_PF_NX; ++q) {
            a += st->rb_F[j][q] * st->x[i][q];
        }
        xn[j] = a;
    }
    for (j = PF_RB_NDYN; j < GG_PF_NX; ++j) { /* gyro bias and accelerometer error: F rows = I exactly */
        xn[j] = st->x[i][j];
    }
    xn[0] += e0;
    xn[1] += e1;
    for (j = 0; j < GG_PF_NL; ++j) {
        xn[2 + j] += (st->rb_K[j][0] * e0) + (st->rb_K[j][1] * e1);
    }
    for (j = 0; j < GG_PF_NX; ++j) {
        st->x[i][j] = xn[j];
    }
}
/* (inline: the per-particle inner loop of the shot) */

#endif /* GGINS_PF_INT_H */
