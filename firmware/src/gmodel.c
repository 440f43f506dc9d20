/* Zonal-harmonic gravitation model; equations in gmodel.h. */
#include "ggins/gmodel.h"
#include "ggins/ggmath.h"

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
    if ((cfg->n_pm < 0) || (cfg->n_pm > GG_GMODEL_MAX_PM)) {
        return GG_ERR_CONFIG;
    }
    /* plausibility: an Earth-like body (finite but absurd values overflow) */
    if ((cfg->gm < 1.0e10L) || (cfg->gm > 1.0e16L) || (cfg->a_m < 1.0e5L) || (cfg->a_m > 1.0e8L)) {
        return GG_ERR_RANGE;
    }
    for (n = 2U; n <= (size_t)GG_GMODEL_MAX_DEGREE; ++n) {
        if ((cfg->j[n] > 1.0L) || (cfg->j[n] < -1.0L)) {
            return GG_ERR_RANGE;
        }
    }
    for (n = 0U; n < (size_t)cfg->n_pm; ++n) {
        if ((gg_finite3(cfg->pm_pos[n]) == 0) || !GG_ISFINITE(cfg->pm_gm[n])) {
            return GG_ERR_CONFIG;
        }
        if ((cfg->pm_gm[n] > 1.0e10L) || (cfg->pm_gm[n] < -1.0e10L) ||
            (cfg->pm_pos[n][0] > 1.0e8L) || (cfg->pm_pos[n][0] < -1.0e8L) ||
            (cfg->pm_pos[n][1] > 1.0e8L) || (cfg->pm_pos[n][1] < -1.0e8L) ||
            (cfg->pm_pos[n][2] > 1.0e8L) || (cfg->pm_pos[n][2] < -1.0e8L)) {
            return GG_ERR_RANGE;
        }
    }
    if (cfg->grid.n_th != 0) {
        const gg_gmodel_grid_t *gr = &cfg->grid;
        gg_real_t e2;
        int32_t last_node;
        if ((gr->n_th < 2) || (gr->n_rho < 2) || (gr->n_th > GG_GMODEL_GRID_MAX) ||
            (gr->n_rho > (GG_GMODEL_GRID_MAX / gr->n_th)) || !GG_ISFINITE(gr->c0) ||
            !GG_ISFINITE(gr->s0) || !GG_ISFINITE(gr->th0_rad) || !GG_ISFINITE(gr->dth_rad) ||
            !GG_ISFINITE(gr->rho0_m) || !GG_ISFINITE(gr->drho_m) || !(gr->dth_rad > 0.0L) ||
            !(gr->drho_m > 0.0L)) {
            return GG_ERR_CONFIG;
        }
        e2 = (gr->c0 * gr->c0) + (gr->s0 * gr->s0);
        if ((e2 > (1.0L + 2.0e-9L)) || (e2 < (1.0L - 2.0e-9L))) {
            return GG_ERR_CONFIG;
        }
        /* the grid within +-45 deg of e0 (atan range), nodes 0.01 m .. 1000 km
         * apart, radii of the Earth's neighbourhood */
        last_node = gr->n_th - 1;
        if ((gr->th0_rad < -0.785L) ||
            ((gr->th0_rad + (gr->dth_rad * (gg_real_t)last_node)) > 0.785L) ||
            (gr->dth_rad < 1.0e-9L) || (gr->drho_m < 0.01L) || (gr->drho_m > 1.0e6L) ||
            (gr->rho0_m < (0.5L * cfg->a_m)) || (gr->rho0_m > 1.0e8L)) {
            return GG_ERR_RANGE;
        }
        for (n = 0U; n < ((size_t)gr->n_th * (size_t)gr->n_rho); ++n) {
            if (!GG_ISFINITE(gr->dg[n][0]) || !GG_ISFINITE(gr->dg[n][1])) {
                return GG_ERR_CONFIG;
            }
            if ((gr->dg[n][0] > 1.0) || (gr->dg[n][0] < -1.0) || (gr->dg[n][1] > 1.0) ||
                (gr->dg[n][1] < -1.0)) {
                return GG_ERR_RANGE;
            }
        }
    }
    st->initialized = 1;
    return GG_OK;
}

/* Programmed point masses: sum of -gm_i (r - p_i)/|r - p_i|^3 into g. */
static gg_status_t add_point_masses(const gg_gmodel_config_t *c, const gg_real_t r[3],
                                    gg_real_t g[3])
{
    size_t n;
    size_t j;
    for (n = 0U; n < (size_t)c->n_pm; ++n) {
        gg_real_t d[3];
        gg_real_t d2 = 0.0L;
        for (j = 0U; j < 3U; ++j) {
            d[j] = r[j] - c->pm_pos[n][j];
            d2 += d[j] * d[j];
        }
        if (!(d2 > 1.0L)) {
            return GG_ERR_RANGE;
        }
        {
            const gg_real_t k = c->pm_gm[n] / (d2 * sqrtl(d2));
            for (j = 0U; j < 3U; ++j) {
                g[j] -= k * d[j];
            }
        }
    }
    return GG_OK;
}

/* Programmed grid: bilinear interpolation of (dG_t, dG_r) at the polar
 * coordinates (theta, rho) of (r_x, r_z), rotated into x and z. */
static uint32_t add_grid(const gg_gmodel_grid_t *gr, const gg_real_t r[3], gg_real_t g[3])
{
    uint32_t flags = 0U;
    if (gr->n_th != 0) {
        const gg_real_t xp = (gr->c0 * r[0]) + (gr->s0 * r[2]);
        const gg_real_t zp = (gr->c0 * r[2]) - (gr->s0 * r[0]);
        const gg_real_t rho = sqrtl((r[0] * r[0]) + (r[2] * r[2]));
        gg_real_t th = 0.0L;
        int inside = 0;
        if ((xp > 0.0L) && (zp <= xp) && (zp >= -xp) &&
            (gg_atan2(zp, xp, &th) == GG_OK)) {
            inside = 1;
        }
        if (inside != 0) {
            const gg_real_t u = (th - gr->th0_rad) / gr->dth_rad;
            const gg_real_t w = (rho - gr->rho0_m) / gr->drho_m;
            const gg_real_t umax = (gg_real_t)gr->n_th - 1.0L;
            const gg_real_t wmax = (gg_real_t)gr->n_rho - 1.0L;
            if ((u < 0.0L) || (w < 0.0L) || (u > umax) || (w > wmax)) {
                inside = 0;
            } else {
                /* cell (i, k) with i <= u < i + 1, clamped to the last cell */
                int32_t i = (int32_t)u;
                int32_t k = (int32_t)w;
                gg_real_t fu;
                gg_real_t fw;
                gg_real_t v[2];
                size_t c;
                if (i > (gr->n_th - 2)) {
                    i = gr->n_th - 2;
                }
                if (k > (gr->n_rho - 2)) {
                    k = gr->n_rho - 2;
                }
                fu = u - (gg_real_t)i;
                fw = w - (gg_real_t)k;
                for (c = 0U; c < 2U; ++c) {
                    const size_t n00 = ((size_t)k * (size_t)gr->n_th) + (size_t)i;
                    const size_t n10 = n00 + 1U;
                    const size_t n01 = n00 + (size_t)gr->n_th;
                    const size_t n11 = n01 + 1U;
                    v[c] = (((1.0L - fu) * (1.0L - fw)) * (gg_real_t)gr->dg[n00][c]) +
                           ((fu * (1.0L - fw)) * (gg_real_t)gr->dg[n10][c]) +
                           (((1.0L - fu) * fw) * (gg_real_t)gr->dg[n01][c]) +
                           ((fu * fw) * (gg_real_t)gr->dg[n11][c]);
                }
                /* t^ = (-z, x)/rho, r^ = (x, z)/rho */
                g[0] += ((v[1] * r[0]) - (v[0] * r[2])) / rho;
                g[2] += ((v[1] * r[2]) + (v[0] * r[0])) / rho;
            }
        }
        if (inside == 0) {
            flags |= GG_GMODEL_OUTSIDE_GRID;
        }
    }
    return flags;
}

gg_status_t gg_gmodel_eval(const gg_gmodel_t *st, const gg_gmodel_config_t *cfg,
                           const gg_real_t r[3], gg_real_t g[3], uint32_t *flags)
{
    gg_real_t rr;
    gg_real_t rn;
    gg_real_t gz[3];
    gg_status_t status;
    uint32_t fl;
    if ((st == NULL) || (cfg == NULL) || (r == NULL) || (g == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(r[0]) || !GG_ISFINITE(r[1]) || !GG_ISFINITE(r[2])) {
        return GG_ERR_NONFINITE;
    }
    rr = (r[0] * r[0]) + (r[1] * r[1]) + (r[2] * r[2]);
    if (!(rr > (0.25L * cfg->a_m * cfg->a_m))) {
        return GG_ERR_RANGE;
    }
    rn = sqrtl(rr);
    {
        const gg_real_t u = r[2] / rn;
        const gg_real_t q = cfg->a_m / rn;
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
            s_r += (nn + 1.0L) * cfg->j[n] * qn * p_n;
            s_u += cfg->j[n] * qn * d_n;
            p_nm2 = p_nm1;
            p_nm1 = p_n;
            d_nm1 = d_n;
        }
        dvdr = -(cfg->gm / rr) * (1.0L - s_r);
        dvdu = -(cfg->gm / rn) * s_u;
        for (j = 0U; j < 3U; ++j) {
            const gg_real_t rhat = r[j] / rn;
            const gg_real_t zhat = (j == 2U) ? 1.0L : 0.0L;
            gz[j] = (dvdr * rhat) + ((dvdu * (zhat - (u * rhat))) / rn);
        }
    }
    status = add_point_masses(cfg, r, gz);
    if (status != GG_OK) {
        return status;
    }
    fl = add_grid(&cfg->grid, r, gz);
    g[0] = gz[0];
    g[1] = gz[1];
    g[2] = gz[2];
    if (flags != NULL) {
        *flags = fl;
    }
    return GG_OK;
}
