/* Pair-mean accommodation of unusable 3-D readings; see fdi3d.h. */
#include "ggins/fdi3d.h"

#include <stddef.h>

gg_status_t gg_fdi3d_init(gg_fdi3d_t *st)
{
    size_t p;
    size_t j;
    if (st == NULL) {
        return GG_ERR_NULL;
    }
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            st->mean_good[p][j] = 0.0L;
        }
    }
    st->have_good = 0;
    st->initialized = 1;
    return GG_OK;
}

/* mask bit of reading (s, j): GG_FDI3D_BIT with the shift's range evident */
static uint32_t rbit(size_t s, size_t j)
{
    const uint32_t sh = (uint32_t)(((3U * s) + j) & 31U);
    return (uint32_t)1U << sh;
}

static gg_real_t rd3(double f[6][3], double f_lo[6][3], size_t s, size_t j)
{
    return (gg_real_t)f[s][j] + (gg_real_t)f_lo[s][j];
}

gg_status_t gg_fdi3d_step(gg_fdi3d_t *st, uint32_t known_bad, double f[6][3], double f_lo[6][3],
                          uint32_t *rebuilt)
{
    gg_real_t m[3][3];
    double nf[6][3];
    double nlo[6][3];
    uint32_t rb = 0U;
    size_t s;
    size_t p;
    size_t j;
    if ((st == NULL) || (f == NULL) || (f_lo == NULL) || (rebuilt == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (s = 0U; s < 6U; ++s) {
        for (j = 0U; j < 3U; ++j) {
            if (((known_bad & rbit(s, j)) == 0U) &&
                (!GG_ISFINITE(f[s][j]) || !GG_ISFINITE(f_lo[s][j]))) {
                return GG_ERR_NONFINITE;
            }
            nf[s][j] = f[s][j];
            nlo[s][j] = f_lo[s][j];
        }
    }
    if ((known_bad != 0U) && (st->have_good == 0)) {
        return GG_ERR_SENSOR; /* no curvature differences known yet */
    }
    for (j = 0U; j < 3U; ++j) {
        int n_whole = 0;
        gg_real_t sum_whole = 0.0L;
        gg_real_t sum_good_whole = 0.0L;
        for (p = 0U; p < 3U; ++p) {
            const uint32_t b0 = known_bad & rbit(p, j);
            const uint32_t b1 = known_bad & rbit(p + 3U, j);
            if ((b0 != 0U) && (b1 != 0U)) {
                return GG_ERR_SENSOR; /* both readings of a pair on this axis */
            }
            if ((b0 == 0U) && (b1 == 0U)) {
                m[p][j] = 0.5L * (rd3(f, f_lo, p, j) + rd3(f, f_lo, p + 3U, j));
                sum_whole += m[p][j];
                sum_good_whole += st->mean_good[p][j];
                n_whole += 1;
            }
        }
        for (p = 0U; p < 3U; ++p) {
            const uint32_t b0 = known_bad & rbit(p, j);
            const uint32_t b1 = known_bad & rbit(p + 3U, j);
            if ((b0 != 0U) || (b1 != 0U)) {
                size_t bad = p + 3U;
                size_t partner = p;
                gg_real_t v;
                double hi;
                if (b0 != 0U) {
                    bad = p;
                    partner = p + 3U;
                }
                if (n_whole == 0) {
                    return GG_ERR_SENSOR; /* no whole pair on this axis */
                }
                /* mean over the whole pairs q of m_q + (m_p - m_q)_last */
                m[p][j] = (sum_whole + (((gg_real_t)n_whole * st->mean_good[p][j]) - sum_good_whole)) /
                          (gg_real_t)n_whole;
                v = (2.0L * m[p][j]) - rd3(f, f_lo, partner, j);
                hi = (double)v;
                nf[bad][j] = hi;
                nlo[bad][j] = (double)(v - (gg_real_t)hi);
                rb |= rbit(bad, j);
            }
        }
    }
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            st->mean_good[p][j] = m[p][j];
        }
    }
    st->have_good = 1;
    for (s = 0U; s < 6U; ++s) {
        for (j = 0U; j < 3U; ++j) {
            f[s][j] = nf[s][j];
            f_lo[s][j] = nlo[s][j];
        }
    }
    *rebuilt = rb;
    return GG_OK;
}
