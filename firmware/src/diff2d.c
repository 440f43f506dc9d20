/* 2-D accelerometer differencing: Welker, Pachter & Huffman, section III,
 * eqs. (1)-(4) differenced, and the centre average after them. */
#include "ggins/diff2d.h"

#include <stddef.h>

gg_status_t gg_diff2d_init(gg_diff2d_t *st, const gg_diff2d_config_t *cfg)
{
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(cfg->a_m) || !GG_ISFINITE(cfg->b_m) || !(cfg->a_m > 0.0L) ||
        !(cfg->b_m > 0.0L)) {
        return GG_ERR_CONFIG;
    }
    st->cfg = *cfg;
    st->initialized = 1;
    return GG_OK;
}

gg_status_t gg_diff2d_step(const gg_diff2d_t *st, const gg_diff2d_input_t *in,
                           gg_diff2d_output_t *out)
{
    size_t i;
    size_t ax;
    if ((st == NULL) || (in == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (i = 0U; i < 4U; ++i) {
        for (ax = 0U; ax < 2U; ++ax) {
            if (!GG_ISFINITE(in->f[i][ax]) || !GG_ISFINITE(in->f_lo[i][ax])) {
                return GG_ERR_NONFINITE;
            }
        }
    }
    {
        /* sensors: 0 = 1:(+a,0), 1 = 2:(0,+b), 2 = 3:(-a,0), 3 = 4:(0,-b);
         * axis 0 = x, axis 1 = z in the input. */
        const gg_real_t inv2a = 1.0L / (2.0L * st->cfg.a_m);
        const gg_real_t inv2b = 1.0L / (2.0L * st->cfg.b_m);
        gg_diff2d_output_t o;
        size_t j;
        size_t k;
        for (j = 0U; j < 3U; ++j) {
            for (k = 0U; k < 3U; ++k) {
                o.gamma[j][k] = 0.0L;
            }
            o.f_c[j] = 0.0L;
        }
        for (ax = 0U; ax < 2U; ++ax) {
            const size_t row = ax * 2U; /* input axis 0 -> x (0), 1 -> z (2) */
            const gg_real_t h1 = (gg_real_t)in->f[0][ax];
            const gg_real_t h2 = (gg_real_t)in->f[1][ax];
            const gg_real_t h3 = (gg_real_t)in->f[2][ax];
            const gg_real_t h4 = (gg_real_t)in->f[3][ax];
            const gg_real_t l1 = (gg_real_t)in->f_lo[0][ax];
            const gg_real_t l2 = (gg_real_t)in->f_lo[1][ax];
            const gg_real_t l3 = (gg_real_t)in->f_lo[2][ax];
            const gg_real_t l4 = (gg_real_t)in->f_lo[3][ax];
            o.gamma[row][0] = ((h3 - h1) + (l3 - l1)) * inv2a; /* dG/dx */
            o.gamma[row][2] = ((h4 - h2) + (l4 - l2)) * inv2b; /* dG/dz */
            o.f_c[row] = 0.25L * (((h1 + h3) + (h2 + h4)) + ((l1 + l3) + (l2 + l4)));
        }
        o.asym = o.gamma[0][2] - o.gamma[2][0];
        *out = o;
    }
    return GG_OK;
}
