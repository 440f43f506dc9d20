/* Gravity dead reckoning: Welker, Pachter & Huffman, section IV, eqs. (5)-(6),
 * discretised with the trapezoidal rule along each step's displacement. */
#include "ggins/gravdr.h"

#include <stddef.h>

static int all_finite_33(const gg_real_t m[3][3])
{
    size_t j;
    size_t k;
    int ok = 1;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            if (!GG_ISFINITE(m[j][k])) {
                ok = 0;
            }
        }
    }
    return ok;
}

gg_status_t gg_gravdr_init(gg_gravdr_t *st, const gg_gravdr_config_t *cfg)
{
    size_t j;
    size_t k;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    if ((gg_finite3(cfg->g0) == 0) || (all_finite_33(cfg->gamma0) == 0)) {
        return GG_ERR_CONFIG;
    }
    if ((cfg->trapezoid_only != 0) && (cfg->trapezoid_only != 1)) {
        return GG_ERR_CONFIG;
    }
    for (j = 0U; j < 3U; ++j) {
        gg_acc_set(&st->g[j], cfg->g0[j]);
        for (k = 0U; k < 3U; ++k) {
            st->gamma[j][k] = cfg->gamma0[j][k];
            st->gamma_prev[j][k] = cfg->gamma0[j][k];
        }
        st->dr_prev[j] = 0.0L;
    }
    st->have_prev = 0;
    st->trapezoid_only = cfg->trapezoid_only;
    st->initialized = 1;
    return GG_OK;
}

gg_status_t gg_gravdr_step(gg_gravdr_t *st, const gg_real_t gamma_new[3][3],
                           const gg_real_t dr[3])
{
    size_t j;
    size_t k;
    if ((st == NULL) || (gamma_new == NULL) || (dr == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if ((all_finite_33(gamma_new) == 0) || (gg_finite3(dr) == 0)) {
        return GG_ERR_NONFINITE;
    }
    {
        int corrected = 0;
        if ((st->have_prev != 0) && (st->trapezoid_only == 0)) {
            corrected = 1;
        }
        for (j = 0U; j < 3U; ++j) {
            gg_real_t trap = 0.0L;
            gg_real_t corr = 0.0L;
            for (k = 0U; k < 3U; ++k) {
                const gg_real_t d1 = gamma_new[j][k] - st->gamma[j][k];
                trap += 0.5L * (st->gamma[j][k] + gamma_new[j][k]) * dr[k];
                if (corrected != 0) {
                    const gg_real_t d2 = d1 - (st->gamma[j][k] - st->gamma_prev[j][k]);
                    /* row j of  dGamma (dr_k - dr_{k-1}) - d2Gamma dr_k */
                    corr += (d1 * (dr[k] - st->dr_prev[k])) - (d2 * dr[k]);
                }
            }
            gg_acc_add(&st->g[j], trap);
            gg_acc_add(&st->g[j], corr / 12.0L);
        }
    }
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            st->gamma_prev[j][k] = st->gamma[j][k];
            st->gamma[j][k] = gamma_new[j][k];
        }
        st->dr_prev[j] = dr[j];
    }
    st->have_prev = 1;
    return GG_OK;
}

gg_status_t gg_gravdr_get(const gg_gravdr_t *st, gg_real_t g[3])
{
    gg_acc_t acc[3];
    gg_status_t status = GG_ERR_NULL;
    if (g != NULL) {
        status = gg_gravdr_get_acc(st, acc);
    }
    if (status == GG_OK) {
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            g[j] = gg_acc_value(&acc[j]);
        }
    }
    return status;
}

gg_status_t gg_gravdr_get_acc(const gg_gravdr_t *st, gg_acc_t g[3])
{
    size_t j;
    if ((st == NULL) || (g == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (j = 0U; j < 3U; ++j) {
        g[j] = st->g[j];
    }
    return GG_OK;
}

gg_status_t gg_gravdr_correct(gg_gravdr_t *st, const gg_real_t dg[3])
{
    size_t j;
    if ((st == NULL) || (dg == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (gg_finite3(dg) == 0) {
        return GG_ERR_NONFINITE;
    }
    for (j = 0U; j < 3U; ++j) {
        gg_acc_add(&st->g[j], dg[j]);
    }
    return GG_OK;
}
