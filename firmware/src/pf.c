/**
 * @file pf.c
 * @brief Bootstrap particle filter for cold-atom partial-gradient position fixing
 *        (Phillips et al., section IV), the filter core: configuration, the shot
 *        (predict, weigh, normalise, resample, regularise, output). The
 *        measurement model is in pf_meas.c, the Rao-Blackwellised process model in
 *        pf_rb.c. See pf.h.
 */
#include "pf_int.h"

#include "ggins/geo.h"
#include "ggins/ggmath.h"


static int pf_cfg_ok(const gg_pf_config_t *c)
{
    const double v[] = {c->k_eff, c->T, c->dz, c->contrast, c->c0, c->c1, c->sigma, c->sigma0_pos,
                        c->sigma0_vel, c->q_pos, c->q_vel, c->dt, c->gain, c->ess_frac,
                        c->sigma0_acc, c->q_acc, c->reg_bw, c->sigma0_jerk, c->q_jerk,
                        c->sigma0_bias, c->q_bias};
    unsigned i;
    for (i = 0; i < ((sizeof v) / (sizeof v[0])); ++i) {
        if (!GG_ISFINITE(v[i])) {
            return 0;
        }
    }
    return (c->n >= 1) && (c->n <= GG_PF_MAX) && (c->map.gzz != NULL) && (c->k_eff > 0.0) && (c->T > 0.0) &&
           (c->dz > 0.0) && (c->contrast > 0.0) && (c->contrast <= 1.0) && (c->sigma > 0.0) &&
           (c->sigma0_pos >= 0.0) && (c->sigma0_vel >= 0.0) && (c->q_pos >= 0.0) && (c->q_vel >= 0.0) &&
           (c->dt > 0.0) && (c->gain > 0.0) && (c->gain <= 1.0) && (c->ess_frac >= 0.0) && (c->ess_frac <= 1.0) &&
           ((c->model == GG_PF_MODEL_RW) || (c->model == GG_PF_MODEL_INS) || (c->model == GG_PF_MODEL_RBPF)) &&
           (c->sigma0_acc >= 0.0) && (c->q_acc >= 0.0) && (c->reg_bw >= 0.0) && (c->sigma0_jerk >= 0.0) &&
           (c->q_jerk >= 0.0) && (c->sigma0_bias >= 0.0) && (c->q_bias >= 0.0) &&
           /* RBPF: the velocity noise keeps the position prediction covariance positive definite */
           ((c->model != GG_PF_MODEL_RBPF) || (c->q_vel > 0.0));
}

/* State dimensions the model uses (4: RW, 6: INS, 12: RBPF, position + linear means). */
static int pf_nx(const gg_pf_config_t *c)
{
    int nx = 4;
    if (c->model == GG_PF_MODEL_INS) {
        nx = 6;
    } else if (c->model == GG_PF_MODEL_RBPF) {
        nx = GG_PF_NX;
    } else {
        nx = 4;
    }
    return nx;
}

/* Dimensions the particles sample (and the regularisation kernel acts on). */
static int pf_nsampled(const gg_pf_config_t *c)
{
    return (c->model == GG_PF_MODEL_RBPF) ? 2 : pf_nx(c);
}

gg_status_t gg_pf_init(gg_pf_t *st, const gg_pf_config_t *cfg)
{
    gg_rng_t rng;
    int i;
    int k;
    gg_status_t s;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    double h = 0.0;
    int nx;
    if (!pf_cfg_ok(cfg)) {
        return GG_ERR_CONFIG;
    }
    nx = pf_nsampled(cfg);
    if (cfg->reg_bw > 0.0) { /* h = reg_bw (4 / ((d + 2) N))^(1 / (d + 4)) */
        double lh = 0.0;
        const double nxd = (double)nx;
        s = gg_log_d(4.0 / ((nxd + 2.0) * (double)cfg->n), &lh);
        if (s == GG_OK) {
            s = gg_exp_d(lh / (nxd + 4.0), &h);
        }
        if (s != GG_OK) {
            return GG_ERR_CONFIG;
        }
        h *= cfg->reg_bw;
        if (!(h < 1.0)) { /* the shrinkage a = sqrt(1 - h^2) needs h < 1 */
            return GG_ERR_CONFIG;
        }
    }
    s = gg_rng_seed(&rng, cfg->seed);
    for (i = 0; (i < cfg->n) && (s == GG_OK); ++i) {
        for (k = 0; (k < nx) && (s == GG_OK); ++k) {
            double z = 0.0;
            s = gg_rng_normal(&rng, &z);
            st->xs[i][k] = z * ((k < 2) ? cfg->sigma0_pos : ((k < 4) ? cfg->sigma0_vel : cfg->sigma0_acc));
        }
        for (k = nx; k < GG_PF_NX; ++k) {
            st->xs[i][k] = 0.0;
        }
    }
    if (s != GG_OK) {
        return s;
    }
    st->reg_h = h;
    for (i = 0; i < GG_PF_NL; ++i) { /* RBPF: linear states start at zero mean, covariance P */
        for (k = 0; k < GG_PF_NL; ++k) {
            st->P[i][k] = 0.0;
        }
    }
    if (cfg->model == GG_PF_MODEL_RBPF) {
        const double sd[GG_PF_NL] = {cfg->sigma0_vel,  cfg->sigma0_vel,  cfg->sigma0_acc,  cfg->sigma0_acc,
                                     cfg->sigma0_acc,  cfg->sigma0_jerk, cfg->sigma0_jerk, cfg->sigma0_jerk,
                                     cfg->sigma0_bias, cfg->sigma0_bias};
        for (i = 0; i < GG_PF_NL; ++i) {
            st->P[i][i] = sd[i] * sd[i];
        }
    }
    for (i = 0; i < cfg->n; ++i) {
        for (k = 0; k < GG_PF_NX; ++k) {
            st->x[i][k] = st->xs[i][k];
        }
        st->w[i] = 1.0 / (double)cfg->n;
        st->ll[i] = 0.0;
    }
    st->cfg = *cfg;
    st->rng = rng;
    st->corr[0] = 0.0;
    st->corr[1] = 0.0;
    st->n_steps = 0u;
    st->n_updates = 0u;
    st->n_skipped = 0u;
    st->n_resampled = 0u;
    st->n_degenerate = 0u;
    st->shot_open = 0;
    st->sh_next = 0;
    st->initialized = 1;
    return GG_OK;
}

/* Systematic resampling (one uniform; particle i gets floor or ceil of N w_i copies). */
static gg_status_t pf_resample(gg_pf_t *st)
{
    const int n = st->cfg.n;
    double u0 = 0.0;
    double cum;
    int i = 0;
    int j;
    int k;
    gg_status_t s = gg_rng_uniform(&st->rng, &u0);
    if (s != GG_OK) {
        return s;
    }
    cum = st->w[0];
    for (j = 0; j < n; ++j) {
        const double target = (u0 + (double)j) / (double)n;
        /* MISRA 14.1: the loop counter is the integer i; the float term only ends the loop early */
        /* cppcheck-suppress misra-c2012-14.1 */
        for (; (i < (n - 1)) && (cum < target); ++i) {
            cum += st->w[i + 1];
        }
        for (k = 0; k < GG_PF_NX; ++k) {
            st->xs[j][k] = st->x[i][k];
        }
    }
    for (j = 0; j < n; ++j) {
        for (k = 0; k < GG_PF_NX; ++k) {
            st->x[j][k] = st->xs[j][k];
        }
        st->w[j] = 1.0 / (double)n;
    }
    return GG_OK;
}


/* Kernel of the regularisation: weighted mean and lower Cholesky factor of the covariance. */
typedef struct {
    double m[GG_PF_NX];
    double el[GG_PF_NX][GG_PF_NX];
} pf_kernel_t;

/* Weighted mean m and covariance of the first nx states, and the lower Cholesky
 * factor L of the covariance (columns of dimensions without spread left zero).
 * Called before resampling, with the weights of the update. */
static void pf_moments(const gg_pf_t *st, int nx, pf_kernel_t *kn)
{
    double cv[GG_PF_NX][GG_PF_NX];
    int i;
    int j;
    int k;
    int q;
    for (j = 0; j < GG_PF_NX; ++j) {
        kn->m[j] = 0.0;
        for (k = 0; k < GG_PF_NX; ++k) {
            cv[j][k] = 0.0;
            kn->el[j][k] = 0.0;
        }
    }
    for (i = 0; i < st->cfg.n; ++i) {
        for (j = 0; j < nx; ++j) {
            kn->m[j] += st->w[i] * st->x[i][j];
        }
    }
    for (i = 0; i < st->cfg.n; ++i) {
        double dx[GG_PF_NX];
        for (j = 0; j < nx; ++j) {
            dx[j] = st->x[i][j] - kn->m[j];
        }
        for (j = 0; j < nx; ++j) {
            for (k = 0; k <= j; ++k) {
                cv[j][k] += st->w[i] * dx[j] * dx[k];
            }
        }
    }
    /* Cholesky; a pivot below 1e-12 of its variance (no spread, or linearly dependent
     * on the previous dimensions) leaves the column zero: no kernel along it */
    for (j = 0; j < nx; ++j) {
        double p = cv[j][j];
        for (q = 0; q < j; ++q) {
            p -= kn->el[j][q] * kn->el[j][q];
        }
        if ((cv[j][j] > 0.0) && (p > (1e-12 * cv[j][j]))) {
            const double d = gg_sqrt_d(p);
            kn->el[j][j] = d;
            for (k = j + 1; k < nx; ++k) {
                double a = cv[k][j];
                for (q = 0; q < j; ++q) {
                    a -= kn->el[k][q] * kn->el[j][q];
                }
                kn->el[k][j] = a / d;
            }
        }
    }
}

/* Regularisation after resampling (Liu & West 2001 shrinkage kernel):
 * x_i <- a x_i + (1 - a) m + h L z_i, a = sqrt(1 - h^2); keeps mean and covariance. */
static gg_status_t pf_regularise(gg_pf_t *st, int nx, const pf_kernel_t *kn)
{
    const double h = st->reg_h;
    const double a = gg_sqrt_d(1.0 - (h * h));
    int i;
    int j;
    int k;
    for (i = 0; i < st->cfg.n; ++i) {
        double z[GG_PF_NX];
        for (j = 0; j < nx; ++j) {
            const gg_status_t s = gg_rng_normal(&st->rng, &z[j]);
            if (s != GG_OK) {
                return s;
            }
        }
        for (j = 0; j < nx; ++j) {
            double e = 0.0;
            for (k = 0; k <= j; ++k) {
                e += kn->el[j][k] * z[k];
            }
            st->x[i][j] = (a * st->x[i][j]) + ((1.0 - a) * kn->m[j]) + (h * e);
        }
    }
    return GG_OK;
}

/* RBPF regularisation after resampling: Liu-West kernel on the position (d = 2),
 * the linear means shifted along the cloud's regression on the position:
 * with L the Cholesky factor of the cloud's covariance (columns 0, 1: L_rr, L_mr),
 * w = (a - 1) L_rr^-1 (r - r_bar) + h z, x += L_(.,0:1) w, i.e.
 * r <- a r + (1 - a) r_bar + h L_rr z and m += L_mr L_rr^-1 (r_new - r). */
static gg_status_t pf_regularise_rb(gg_pf_t *st, const pf_kernel_t *kn)
{
    const double h = st->reg_h;
    const double a = gg_sqrt_d(1.0 - (h * h));
    const double l00 = kn->el[0][0];
    const double l10 = kn->el[1][0];
    const double l11 = kn->el[1][1];
    int i;
    int k;
    for (i = 0; i < st->cfg.n; ++i) {
        double z0 = 0.0;
        double z1 = 0.0;
        double y0 = 0.0;
        double y1 = 0.0;
        gg_status_t s = gg_rng_normal(&st->rng, &z0);
        if (s == GG_OK) {
            s = gg_rng_normal(&st->rng, &z1);
        }
        if (s != GG_OK) {
            return s;
        }
        if (l00 > 0.0) {
            y0 = (st->x[i][0] - kn->m[0]) / l00;
        }
        if (l11 > 0.0) {
            y1 = ((st->x[i][1] - kn->m[1]) - (l10 * y0)) / l11;
        }
        {
            const double w0 = (l00 > 0.0) ? (((a - 1.0) * y0) + (h * z0)) : 0.0;
            const double w1 = (l11 > 0.0) ? (((a - 1.0) * y1) + (h * z1)) : 0.0;
            for (k = 0; k < GG_PF_NX; ++k) {
                st->x[i][k] += (kn->el[k][0] * w0) + (kn->el[k][1] * w1);
            }
        }
    }
    return GG_OK;
}

gg_status_t gg_pf_step_begin(gg_pf_t *st, const gg_pf_input_t *in)
{
    const gg_pf_config_t *c;
    double sl = 0.0;
    double cl = 1.0;
    pf_radii_t r;
    gg_status_t s;
    if ((st == NULL) || (in == NULL)) {
        return GG_ERR_NULL;
    }
    if (!st->initialized) {
        return GG_ERR_NOT_INIT;
    }
    if (st->shot_open != 0) {
        return GG_ERR_SEQUENCE; /* the previous shot was not ended */
    }
    if (!GG_ISFINITE(in->lat) || !GG_ISFINITE(in->lon) || !GG_ISFINITE(in->h) || !GG_ISFINITE(in->vn) ||
        !GG_ISFINITE(in->ve) || ((in->shot_ok != 0) && (!GG_ISFINITE(in->s0) || !GG_ISFINITE(in->s1)))) {
        return GG_ERR_NONFINITE;
    }
    if ((in->lat > GG_LIM_PF_LAT_MAX_RAD) || (in->lat < -GG_LIM_PF_LAT_MAX_RAD) ||
        (in->lon > GG_LIM_PF_LON_MAX_RAD) || (in->lon < -GG_LIM_PF_LON_MAX_RAD) || (in->h < GG_LIM_PF_H_MIN_M) ||
        (in->h > GG_LIM_PF_H_MAX_M) || (in->vn > GG_LIM_PF_V_MAX_MPS) || (in->vn < -GG_LIM_PF_V_MAX_MPS) ||
        (in->ve > GG_LIM_PF_V_MAX_MPS) || (in->ve < -GG_LIM_PF_V_MAX_MPS) ||
        ((in->shot_ok != 0) && ((in->s0 > GG_LIM_PF_S_MAX) || (in->s0 < -GG_LIM_PF_S_MAX) ||
                                (in->s1 > GG_LIM_PF_S_MAX) || (in->s1 < -GG_LIM_PF_S_MAX)))) {
        return GG_ERR_RANGE;
    }
    c = &st->cfg;
    /* geometry first (the only failure mode after validation): state untouched on error */
    s = gg_sincos_d(in->lat, &sl, &cl);
    if (s != GG_OK) {
        return s;
    }
    r = pf_radii(sl, in->h);
    if (c->model == GG_PF_MODEL_RBPF) {
        s = pf_rb_common(st, in, sl, cl, r); /* commits P; untouched on error */
        if (s != GG_OK) {
            return s;
        }
    }
    st->sh_rm = r.rm;                                  /* meridian radius + h */
    st->sh_rn = r.rnh * cl;                            /* (prime vertical + h) cos(lat) */
    st->sh_ws2 = PF_G0 / gg_sqrt_d(r.rm * r.rnh);        /* Schuler w_s^2 = g0 / R */
    st->sh_fcor = 2.0 * PF_OMEGA_E * sl;                    /* Coriolis 2 Omega sinL */
    st->sh_in = *in;
    st->sh_next = 0;
    st->sh_llmax = 0.0;
    st->sh_have = 0;
    st->sh_health = 0u;
    if (in->shot_ok == 0) {
        st->sh_health = GG_PF_H_SKIPPED;
    }
    st->shot_open = 1;
    st->n_steps++;
    return GG_OK;
}

gg_status_t gg_pf_step_chunk(gg_pf_t *st, int max_particles, int *done)
{
    const gg_pf_config_t *c;
    const gg_pf_input_t *in;
    double qk[6];
    double scale;
    double amp;
    double inv2s2;
    int nx;
    int i;
    int i_end;
    int k;
    gg_status_t s = GG_OK;
    if ((st == NULL) || (done == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->shot_open == 0) {
        return GG_ERR_SEQUENCE;
    }
    if (max_particles < 1) {
        return GG_ERR_RANGE;
    }
    c = &st->cfg;
    in = &st->sh_in;
    nx = pf_nx(c);
    qk[0] = c->q_pos;
    qk[1] = c->q_pos;
    qk[2] = c->q_vel;
    qk[3] = c->q_vel;
    qk[4] = c->q_acc;
    qk[5] = c->q_acc;
    scale = c->k_eff * c->dz * c->T * c->T; /* dphi = k_eff Gamma_zz dz T^2 (paper eq. 2) */
    amp = 0.5 * c->contrast;
    inv2s2 = 1.0 / (2.0 * c->sigma * c->sigma);
    i_end = ((c->n - st->sh_next) > max_particles) ? (st->sh_next + max_particles) : c->n;
    for (i = st->sh_next; (i < i_end) && (s == GG_OK); ++i) {
        double z[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        /* 1. predict (the generator draws in particle order: chunking gives the same sequence) */
        if (c->model == GG_PF_MODEL_RBPF) {
            s = gg_rng_normal(&st->rng, &z[0]);
            if (s == GG_OK) {
                s = gg_rng_normal(&st->rng, &z[1]);
            }
            if (s == GG_OK) {
                pf_rb_particle(st, i, z[0], z[1]);
            }
        } else {
            for (k = 0; (k < nx) && (k < 6) && (s == GG_OK); ++k) {
                /* the RW model draws all four (as before); the INS model only where q > 0 */
                if ((c->model == GG_PF_MODEL_RW) || (qk[k] > 0.0)) {
                    s = gg_rng_normal(&st->rng, &z[k]);
                }
                z[k] *= qk[k];
            }
            if ((s == GG_OK) && (c->model == GG_PF_MODEL_INS)) {
                /* semi-implicit (symplectic) Euler of the Schuler loop: velocity first */
                const double vn = st->x[i][2];
                const double ve = st->x[i][3];
                const double an = ((-st->sh_ws2 * st->x[i][0]) + st->x[i][4]) - (st->sh_fcor * ve);
                const double ae = ((-st->sh_ws2 * st->x[i][1]) + st->x[i][5]) + (st->sh_fcor * vn);
                st->x[i][2] = vn + (an * c->dt) + z[2];
                st->x[i][3] = ve + (ae * c->dt) + z[3];
                st->x[i][0] += (st->x[i][2] * c->dt) + z[0];
                st->x[i][1] += (st->x[i][3] * c->dt) + z[1];
                st->x[i][4] += z[4];
                st->x[i][5] += z[5];
            } else if (s == GG_OK) { /* RW */
                st->x[i][0] += (st->x[i][2] * c->dt) + z[0];
                st->x[i][1] += (st->x[i][3] * c->dt) + z[1];
                st->x[i][2] += z[2];
                st->x[i][3] += z[3];
            } else {
                /* no draw failure mode: nothing to do */
            }
        }
        /* 3. log-likelihood of the pair at the particle's candidate position (paper eq. 6) */
        if ((s == GG_OK) && (in->shot_ok != 0)) {
            double g = 0.0;
            double d = 0.0;
            gg_status_t sm = c->map.gzz(c->map.ctx, in->lat + (st->x[i][0] / st->sh_rm),
                                        in->lon + (st->x[i][1] / st->sh_rn), in->h, &g);
            if ((sm == GG_OK) && GG_ISFINITE(g)) {
                sm = gg_pf_ellipse_distance(in->s0, in->s1, c->c0, c->c1, amp, scale * g, &d);
            } else {
                sm = GG_ERR_RANGE;
            }
            if (sm == GG_OK) {
                st->ll[i] = -d * d * inv2s2;
                st->xs[i][0] = g;
                if ((st->sh_have == 0) || (st->ll[i] > st->sh_llmax)) {
                    st->sh_llmax = st->ll[i];
                }
                st->sh_have = 1;
            } else {
                st->ll[i] = 1.0; /* marker: no likelihood (ll <= 0 otherwise) */
                st->xs[i][0] = 0.0;
                st->sh_health |= GG_PF_H_MAP_MISS;
            }
        }
    }
    if (s != GG_OK) {
        return s; /* cannot happen: the generator has no failure mode */
    }
    st->sh_next = i_end;
    *done = 0;
    if (i_end >= c->n) {
        *done = 1;
    }
    return GG_OK;
}

gg_status_t gg_pf_step_end(gg_pf_t *st, gg_pf_output_t *out)
{
    const gg_pf_config_t *c;
    double mean[GG_PF_NX];
    double ess;
    double sw2;
    double gzz_mean = 0.0;
    uint32_t health;
    int i;
    int k;
    int n;
    gg_status_t s = GG_OK;
    if ((st == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if ((st->shot_open == 0) || (st->sh_next < st->cfg.n)) {
        return GG_ERR_SEQUENCE; /* not begun, or particles left */
    }
    c = &st->cfg;
    n = c->n;
    health = st->sh_health;
    if (st->sh_in.shot_ok == 0) {
        st->n_skipped++;
    } else {
        double sw = 0.0;
        for (i = 0; (i < n) && (st->sh_have != 0); ++i) {
            double e = 0.0;
            if (st->ll[i] <= 0.0) {
                (void)gg_exp_d(st->ll[i] - st->sh_llmax, &e); /* argument <= 0: always GG_OK */
            }
            st->w[i] *= e;
            sw += st->w[i];
        }
        if ((st->sh_have == 0) || !(sw > 0.0) || !GG_ISFINITE(sw)) {
            for (i = 0; i < n; ++i) {
                st->w[i] = 1.0 / (double)n;
            }
            health |= GG_PF_H_DEGENERATE;
            st->n_degenerate++;
        } else {
            for (i = 0; i < n; ++i) {
                st->w[i] /= sw;
                gzz_mean += st->w[i] * st->xs[i][0];
            }
        }
        st->n_updates++;
    }
    /* 4. effective sample size, systematic resampling */
    sw2 = 0.0;
    for (i = 0; i < n; ++i) {
        sw2 += st->w[i] * st->w[i];
    }
    ess = 1.0 / sw2;
    if (ess < (c->ess_frac * (double)n)) {
        pf_kernel_t kn;
        const int nx = pf_nx(c);
        if (st->reg_h > 0.0) {
            pf_moments(st, nx, &kn);
        }
        s = pf_resample(st);
        if ((s == GG_OK) && (st->reg_h > 0.0)) {
            s = (c->model == GG_PF_MODEL_RBPF) ? pf_regularise_rb(st, &kn) : pf_regularise(st, nx, &kn);
        }
        health |= GG_PF_H_RESAMPLED;
        st->n_resampled++;
    }
    st->shot_open = 0;
    if (s != GG_OK) {
        return s; /* cannot happen: the generator has no failure mode */
    }
    /* 5. mean (paper eq. 7) and fixed-gain smoothing (eqs. 9-10) */
    for (k = 0; k < GG_PF_NX; ++k) {
        mean[k] = 0.0;
    }
    for (i = 0; i < n; ++i) {
        for (k = 0; k < GG_PF_NX; ++k) {
            mean[k] += st->w[i] * st->x[i][k];
        }
    }
    st->corr[0] += c->gain * (mean[0] - st->corr[0]);
    st->corr[1] += c->gain * (mean[1] - st->corr[1]);
    out->corr[0] = st->corr[0];
    out->corr[1] = st->corr[1];
    for (k = 0; k < GG_PF_NX; ++k) {
        out->mean[k] = mean[k];
    }
    out->ess = ess;
    out->gzz_mean = gzz_mean;
    out->health = health;
    return GG_OK;
}

gg_status_t gg_pf_step(gg_pf_t *st, const gg_pf_input_t *in, gg_pf_output_t *out)
{
    int done = 0;
    gg_status_t s;
    if ((st == NULL) || (in == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    s = gg_pf_step_begin(st, in);
    if (s == GG_OK) {
        s = gg_pf_step_chunk(st, GG_PF_MAX, &done);
    }
    if (s == GG_OK) {
        s = gg_pf_step_end(st, out);
    }
    return s;
}
