/* Shared by the libFuzzer harnesses: the navigation configuration of the
 * welker-perfect flight (r0, v0, G0 at t = 0 of docs/design.md's north flight,
 * point-mass Earth), parity checks on, and the "nothing non-finite" checks. */
#ifndef GGINS_FUZZ_COMMON_H
#define GGINS_FUZZ_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_lcm.h"

#define FUZZ_GM 3.986004418e14L
#define FUZZ_R 6378137.0L

static void fuzz_config(gg_nav2d_config_t *c)
{
    memset(c, 0, sizeof *c);
    c->geometry.a_m = 0.5L;
    c->geometry.b_m = 0.5L;
    c->dt_us = 10000;
    c->dt_tol_us = 0;
    c->r0[0] = FUZZ_R;              /* L0 = 0, h = 0: r = (R, 0) in (x, z) */
    c->v0[2] = 300.0L;              /* due north at 300 m/s: v = V (-sin L, cos L) */
    c->g0[0] = -FUZZ_GM / (FUZZ_R * FUZZ_R);
    c->f_max = 50.0;
    c->asym_max = 1e-6;
    c->fdi_parity_f_max = 1e-11;
    c->fdi_asym_max = 1e-11;
    c->acc_frozen_frames = 5; /* frozen-reading monitor on (navtask.h) */
}

#define FUZZ_FAIL(...)                                    \
    do {                                                  \
        fprintf(stderr, "FUZZ INVARIANT BROKEN: " __VA_ARGS__); \
        fprintf(stderr, "\n");                            \
        abort();                                          \
    } while (0)

static int fuzz_finite_n(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* Every number of a navigation output is finite. */
static void fuzz_check_output(const gg_nav_output_t *o)
{
    if (!fuzz_finite_n(o->r_i, 3) || !fuzz_finite_n(o->v_i, 3) || !fuzz_finite_n(o->g_i, 3) ||
        !fuzz_finite_n(&o->gamma_i[0][0], 9) || !fuzz_finite_n(o->f_i, 3) || !isfinite(o->gamma_asym) ||
        !isfinite(o->h_ins_m) || !isfinite(o->baro_innov_m) || !isfinite(o->g_up_corr) ||
        !fuzz_finite_n(o->parity_f, 2))
        FUZZ_FAIL("non-finite value in the navigation output of seq %lld (status %d, health 0x%x)",
                  (long long)o->seq, (int)o->status, (unsigned)o->health);
}

/* Every number of the navigation state that the public interfaces expose is finite. */
static void fuzz_check_state(const gg_nav2d_t *nav)
{
    gg_real_t r[3], v[3], g[3];
    if (!nav->started) return;
    if (gg_mech_get(&nav->mech, r, v) == GG_OK && (!gg_finite3(r) || !gg_finite3(v)))
        FUZZ_FAIL("non-finite position/velocity in the navigation state");
    if (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER && gg_gravdr_get(&nav->gravdr, g) == GG_OK && !gg_finite3(g))
        FUZZ_FAIL("non-finite G in the gravity dead reckoning");
    for (int j = 0; j < 3; ++j) {
        if (!isfinite(nav->f_c[j])) FUZZ_FAIL("non-finite centre specific force in the state");
        for (int k = 0; k < 3; ++k)
            if (!isfinite(nav->gamma[j][k])) FUZZ_FAIL("non-finite gradient in the state");
    }
    if (!isfinite(nav->a_c) || !isfinite(nav->h_ins) || !isfinite(nav->baro_innov) || !isfinite(nav->asym))
        FUZZ_FAIL("non-finite vertical-channel state");
}

#endif
