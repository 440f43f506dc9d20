/* 3-D differencing on a rotating body; equations in diff3d.h (Gao et al.
 * eqs. 24-27; Welker, Pachter & Huffman Fig. 1 layout). */
#include "ggins/diff3d.h"

#include <stddef.h>

gg_status_t gg_diff3d_init(gg_diff3d_t *st, const gg_diff3d_config_t *cfg)
{
    size_t k;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    st->initialized = 0;
    for (k = 0U; k < 3U; ++k) {
        if (!GG_ISFINITE(cfg->half_base_m[k]) || !(cfg->half_base_m[k] > 0.0L)) {
            return GG_ERR_CONFIG;
        }
    }
    st->cfg = *cfg;
    st->initialized = 1;
    return GG_OK;
}

gg_status_t gg_diff3d_step(const gg_diff3d_t *st, const gg_diff3d_input_t *in,
                           gg_diff3d_output_t *out)
{
    gg_diff3d_output_t o;
    gg_real_t m[3][3];
    gg_real_t w2[3][3];
    size_t i;
    size_t j;
    size_t k;
    if ((st == NULL) || (in == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (i = 0U; i < 6U; ++i) {
        for (j = 0U; j < 3U; ++j) {
            if (!GG_ISFINITE(in->f[i][j]) || !GG_ISFINITE(in->f_lo[i][j])) {
                return GG_ERR_NONFINITE;
            }
        }
    }
    if (gg_finite3(in->omega_b) == 0) {
        return GG_ERR_NONFINITE;
    }
    /* M[j][k] = (f_j(+d_k) - f_j(-d_k)) / 2 d_k, hi and lo differenced apart */
    for (k = 0U; k < 3U; ++k) {
        const gg_real_t inv = 1.0L / (2.0L * st->cfg.half_base_m[k]);
        for (j = 0U; j < 3U; ++j) {
            const gg_real_t dh = (gg_real_t)in->f[k][j] - (gg_real_t)in->f[k + 3U][j];
            const gg_real_t dl = (gg_real_t)in->f_lo[k][j] - (gg_real_t)in->f_lo[k + 3U][j];
            m[j][k] = (dh + dl) * inv;
        }
    }
    /* [Omega x]^2 = Omega Omega^T - |Omega|^2 I */
    {
        const gg_real_t *w = in->omega_b;
        const gg_real_t ww = (w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]);
        for (j = 0U; j < 3U; ++j) {
            for (k = 0U; k < 3U; ++k) {
                w2[j][k] = (w[j] * w[k]) - ((j == k) ? ww : 0.0L);
            }
        }
    }
    o.trace = 0.0L;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            o.gamma[j][k] = w2[j][k] - (0.5L * (m[j][k] + m[k][j]));
        }
        o.trace += o.gamma[j][j];
    }
    /* antisymmetric part A = (M - M^T)/2 = [Omega' x]: A[2][1] = w'x, A[0][2] = w'y, A[1][0] = w'z */
    o.omega_dot[0] = 0.5L * (m[2][1] - m[1][2]);
    o.omega_dot[1] = 0.5L * (m[0][2] - m[2][0]);
    o.omega_dot[2] = 0.5L * (m[1][0] - m[0][1]);
    for (j = 0U; j < 3U; ++j) {
        gg_real_t sh = 0.0L;
        gg_real_t sl = 0.0L;
        for (i = 0U; i < 6U; ++i) {
            sh += (gg_real_t)in->f[i][j];
            sl += (gg_real_t)in->f_lo[i][j];
        }
        o.f_c[j] = (sh + sl) / 6.0L;
    }
    *out = o;
    return GG_OK;
}
