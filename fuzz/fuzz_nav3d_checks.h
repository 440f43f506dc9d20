/* Shared by the 3-D libFuzzer harnesses (fuzz_nav3d, fuzz_config3d): the
 * finding macro and the "nothing non-finite" checks of the 3-D task's output
 * and state. */
#ifndef GGINS_FUZZ_NAV3D_CHECKS_H
#define GGINS_FUZZ_NAV3D_CHECKS_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include "ggins/nav3d.h"

#define FAIL(...)                                                   \
    do {                                                            \
        fprintf(stderr, "FUZZ INVARIANT BROKEN: " __VA_ARGS__);     \
        fprintf(stderr, "\n");                                      \
        abort();                                                    \
    } while (0)

static int fin(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static void check_output(const gg_nav3d_output_t *o)
{
    if (!fin(o->r_e, 3) || !fin(o->r_e_lo, 3) || !fin(o->v_e, 3) || !isfinite(o->lat_rad) ||
        !isfinite(o->lon_rad) || !isfinite(o->h_m) || !fin(o->v_n, 3) || !fin(o->g_e, 3) ||
        !fin(o->g_e_lo, 3) || !fin(&o->gamma_e[0][0], 9) || !fin(&o->gamma_b[0][0], 9) ||
        !fin(o->f_b, 3) || !fin(o->q_b_e, 4) || !fin(o->rpy_rad, 3) || !fin(o->omega_b, 3) ||
        !fin(o->omega_dot_b, 3) || !fin(o->parity, 4) || !isfinite(o->h_ins_m) ||
        !isfinite(o->baro_innov_m) || !isfinite(o->g_up_corr) || !isfinite(o->t_s) ||
        !isfinite(o->outage_s) || !isfinite(o->state_lag_s) || !isfinite(o->mm_nis) ||
        !fin(o->mm_sigma, 18) || !fin(o->mm_bias, 6) || !fin(o->mm_corr_m, 3) || !fin(o->mm_innov, 6) ||
        !fin(o->mm_pcov, 18) || !isfinite(o->pf_ess) || !fin(o->pf_spread_m, 2) ||
        !fin(o->pf_corr_m, 2) || !fin(o->pf_mean_m, 2) || !isfinite(o->pf_gzz_s2))
        FAIL("non-finite value in the 3-D output of seq %lld (status %d, health 0x%x)",
             (long long)o->seq, (int)o->status, (unsigned)o->health);
}

static void check_state(const gg_nav3d_t *nav)
{
    gg_real_t r[3], v[3];
    if (!nav->started) return;
    if (gg_mech_get(&nav->mech, r, v) == GG_OK && (!gg_finite3(r) || !gg_finite3(v)))
        FAIL("non-finite position/velocity in the 3-D state");
    for (int j = 0; j < 3; ++j) {
        if (!isfinite(nav->f_b[j]) || !isfinite(nav->w_k[j])) FAIL("non-finite f_b / w in the 3-D state");
        for (int k = 0; k < 3; ++k)
            if (!isfinite(nav->gamma_b[j][k]) || !isfinite(nav->gamma_e[j][k]))
                FAIL("non-finite gradient in the 3-D state");
    }
    for (int j = 0; j < 4; ++j)
        if (!isfinite(nav->q_b_i[j])) FAIL("non-finite attitude in the 3-D state");
}

#endif
