/* Zonal-harmonic gravitation model; equations in gmodel.h. */
#include "ggins/gmodel.h"

#include <stddef.h>

gg_status_t gg_gmodel_init(gg_gmodel_t *st, const gg_gmodel_config_t *cfg)
{
    size_t n;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    st->initialized = 0;
    if (!GG_ISFINITE(cfg->gm) || !(cfg->gm > 0.0L) || !GG_ISFINITE(cfg->a_m) ||
        !(cfg->a_m > 0.0L) || (cfg->j[0] != 0.0L) || (cfg->j[1] != 0.0L)) {
        return GG_ERR_CONFIG;
    }
    for (n = 2U; n <= (size_t)GG_GMODEL_MAX_DEGREE; ++n) {
        if (!GG_ISFINITE(cfg->j[n])) {
            return GG_ERR_CONFIG;
        }
    }
    st->cfg = *cfg;
    st->initialized = 1;
    return GG_OK;
}

gg_status_t gg_gmodel_eval(const gg_gmodel_t *st, const gg_real_t r[3], gg_real_t g[3])
{
    gg_real_t rr;
    gg_real_t rn;
    if ((st == NULL) || (r == NULL) || (g == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(r[0]) || !GG_ISFINITE(r[1]) || !GG_ISFINITE(r[2])) {
        return GG_ERR_NONFINITE;
    }
    rr = (r[0] * r[0]) + (r[1] * r[1]) + (r[2] * r[2]);
    if (!(rr > (0.25L * st->cfg.a_m * st->cfg.a_m))) {
        return GG_ERR_RANGE;
    }
    rn = sqrtl(rr);
    {
        const gg_real_t u = r[2] / rn;
        const gg_real_t q = st->cfg.a_m / rn;
        gg_real_t p_nm2 = 1.0L; /* P_0 */
        gg_real_t p_nm1 = u;    /* P_1 */
        gg_real_t d_nm1 = 1.0L; /* P_1' */
        gg_real_t qn = q;       /* (a/r)^1 */
        gg_real_t s_r = 0.0L;   /* sum (n+1) J_n q^n P_n */
        gg_real_t s_u = 0.0L;   /* sum J_n q^n P_n' */
        gg_real_t dvdr;
        gg_real_t dvdu;
        size_t n;
        size_t j;
        for (n = 2U; n <= (size_t)GG_GMODEL_MAX_DEGREE; ++n) {
            const gg_real_t nn = (gg_real_t)n;
            const gg_real_t p_n = ((((2.0L * nn) - 1.0L) * u * p_nm1) - ((nn - 1.0L) * p_nm2)) / nn;
            const gg_real_t d_n = (u * d_nm1) + (nn * p_nm1);
            qn *= q;
            s_r += (nn + 1.0L) * st->cfg.j[n] * qn * p_n;
            s_u += st->cfg.j[n] * qn * d_n;
            p_nm2 = p_nm1;
            p_nm1 = p_n;
            d_nm1 = d_n;
        }
        dvdr = -(st->cfg.gm / rr) * (1.0L - s_r);
        dvdu = -(st->cfg.gm / rn) * s_u;
        for (j = 0U; j < 3U; ++j) {
            const gg_real_t rhat = r[j] / rn;
            const gg_real_t zhat = (j == 2U) ? 1.0L : 0.0L;
            g[j] = (dvdr * rhat) + ((dvdu * (zhat - (u * rhat))) / rn);
        }
    }
    return GG_OK;
}
