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
           ((c->model != GG_PF_MODEL_RBPF) || (c->q_vel > 0.0)) &&
           /* upper bounds (limits.h): absurd but finite settings would overflow the cloud */
           (c->k_eff <= GG_LIM_PF_K_EFF_MAX) && (c->T <= GG_LIM_PF_T_MAX_S) && (c->dz <= GG_LIM_PF_DZ_MAX_M) &&
           (c->dt <= GG_LIM_PF_DT_MAX_S) && (c->sigma <= GG_LIM_PF_S_MAX) && (c->c0 >= -GG_LIM_PF_S_MAX) &&
           (c->c0 <= GG_LIM_PF_S_MAX) && (c->c1 >= -GG_LIM_PF_S_MAX) && (c->c1 <= GG_LIM_PF_S_MAX) &&
           (c->sigma0_pos <= GG_LIM_PF_POS_SIGMA_MAX_M) && (c->q_pos <= GG_LIM_PF_POS_SIGMA_MAX_M) &&
           (c->sigma0_vel <= GG_LIM_PF_VEL_SIGMA_MAX_MPS) && (c->q_vel <= GG_LIM_PF_VEL_SIGMA_MAX_MPS) &&
           (c->sigma0_acc <= GG_LIM_PF_ACC_SIGMA_MAX_MPS2) && (c->q_acc <= GG_LIM_PF_ACC_SIGMA_MAX_MPS2) &&
           (c->sigma0_bias <= GG_LIM_PF_ACC_SIGMA_MAX_MPS2) && (c->q_bias <= GG_LIM_PF_ACC_SIGMA_MAX_MPS2) &&
           (c->sigma0_jerk <= GG_LIM_PF_JERK_SIGMA_MAX_MPS3) && (c->q_jerk <= GG_LIM_PF_JERK_SIGMA_MAX_MPS3);
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
    for (i = 0; i < GG_PF_NX; ++i) {
        for (k = 0; k < GG_PF_NX; ++k) {
            st->P_fi[i][k] = 0.0;
        }
    }
    if (cfg->model == GG_PF_MODEL_RBPF) {
        const double sd[GG_PF_NL] = {cfg->sigma0_vel,  cfg->sigma0_vel,  cfg->sigma0_acc,  cfg->sigma0_acc,
                                     cfg->sigma0_acc,  cfg->sigma0_jerk, cfg->sigma0_jerk, cfg->sigma0_jerk,
                                     cfg->sigma0_bias, cfg->sigma0_bias};
        for (i = 0; i < GG_PF_NL; ++i) {
            st->P[i][i] = sd[i] * sd[i];
            st->P_fi[2 + i][2 + i] = sd[i] * sd[i];
        }
        st->P_fi[0][0] = cfg->sigma0_pos * cfg->sigma0_pos;
        st->P_fi[1][1] = st->P_fi[0][0];
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
    st->sh_stage = -1;
    st->initialized = 1;
    return GG_OK;
}

/* Lower Cholesky factor of the cloud's covariance (kn.cv, lower triangle) into kn.el;
 * a pivot below 1e-12 of its variance (no spread, or linearly dependent on the
 * previous dimensions) leaves the column zero: no kernel along it. */
static void pf_kernel_chol(gg_pf_kernel_t *kn, int nx)
{
    int j;
    int k;
    int q;
    for (j = 0; j < nx; ++j) {
        double p = kn->cv[j][j];
        for (q = 0; q < j; ++q) {
            p -= kn->el[j][q] * kn->el[j][q];
        }
        if ((kn->cv[j][j] > 0.0) && (p > (1e-12 * kn->cv[j][j]))) {
            const double d = gg_sqrt_d(p);
            kn->el[j][j] = d;
            for (k = j + 1; k < nx; ++k) {
                double t = kn->cv[k][j];
                for (q = 0; q < j; ++q) {
                    t -= kn->el[k][q] * kn->el[j][q];
                }
                kn->el[k][j] = t / d;
            }
        }
    }
}

/* Regularisation of particle i after resampling (Liu & West 2001 shrinkage kernel):
 * x_i <- a x_i + (1 - a) m + h L z_i, a = sqrt(1 - h^2); keeps mean and covariance. */
static gg_status_t pf_regularise_one(gg_pf_t *st, int i, int nx, const gg_pf_kernel_t *kn)
{
    const double h = st->reg_h;
    const double a = gg_sqrt_d(1.0 - (h * h));
    double z[GG_PF_NX];
    int j;
    int k;
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
    return GG_OK;
}

/* RBPF regularisation of particle i after resampling: Liu-West kernel on the position (d = 2),
 * the linear means shifted along the cloud's regression on the position:
 * with L the Cholesky factor of the cloud's covariance (columns 0, 1: L_rr, L_mr),
 * w = (a - 1) L_rr^-1 (r - r_bar) + h z, x += L_(.,0:1) w, i.e.
 * r <- a r + (1 - a) r_bar + h L_rr z and m += L_mr L_rr^-1 (r_new - r). */
static gg_status_t pf_regularise_rb_one(gg_pf_t *st, int i, const gg_pf_kernel_t *kn)
{
    const double h = st->reg_h;
    const double a = gg_sqrt_d(1.0 - (h * h));
    const double l00 = kn->el[0][0];
    const double l10 = kn->el[1][0];
    const double l11 = kn->el[1][1];
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
        for (int k = 0; k < GG_PF_NX; ++k) {
            st->x[i][k] += (kn->el[k][0] * w0) + (kn->el[k][1] * w1);
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
    st->sh_stage = -1;
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

/* Stages of the end of a shot (gg_pf_step_end_chunk), each a pass over the particles. */
#define PF_E_WEIGH 0    /* w_i <- w_i exp(ll_i - ll_max), sum (measured shots only) */
#define PF_E_NORM 1     /* w_i / sum (or uniform when degenerate), Gamma_zz mean, sum w^2 */
#define PF_E_MOM_MEAN 2 /* regularisation kernel: weighted mean */
#define PF_E_MOM_COV 3  /* weighted covariance (then its Cholesky factor) */
#define PF_E_PICK 4     /* systematic resampling: ancestors into the scratch */
#define PF_E_COPY 5     /* scratch back, weights 1/N */
#define PF_E_REG 6      /* regularisation kernel draw */
#define PF_E_MEAN 7     /* particle mean, position spread */
#define PF_E_DONE 8

/* The end's bookkeeping after the normalisation: ESS, whether to resample. */
static int pf_end_after_norm(gg_pf_t *st)
{
    const gg_pf_config_t *c = &st->cfg;
    int next = PF_E_MEAN;
    st->sh_ess = 1.0 / st->sh_sw2;
    if (st->sh_ess < (c->ess_frac * (double)c->n)) {
        st->sh_health |= GG_PF_H_RESAMPLED;
        st->n_resampled++;
        if (st->reg_h > 0.0) {
            next = PF_E_MOM_MEAN;
        } else {
            next = PF_E_PICK;
        }
    }
    return next;
}

/* One particle (index st->sh_i) of the current end stage. */
static gg_status_t pf_end_particle(gg_pf_t *st, int nx)
{
    const int n = st->cfg.n;
    const int i = st->sh_i;
    gg_pf_kernel_t *kn = &st->kn;
    int j;
    int k;
    gg_status_t s = GG_OK;
    switch (st->sh_stage) {
    case PF_E_WEIGH: {
        double e = 0.0;
        if (st->ll[i] <= 0.0) {
            (void)gg_exp_d(st->ll[i] - st->sh_llmax, &e); /* argument <= 0: always GG_OK */
        }
        st->w[i] *= e;
        st->sh_sw += st->w[i];
        break;
    }
    case PF_E_NORM:
        if (st->sh_degen != 0) {
            st->w[i] = 1.0 / (double)n;
        } else if (st->sh_in.shot_ok != 0) {
            st->w[i] /= st->sh_sw;
            st->sh_gzz += st->w[i] * st->xs[i][0];
            if (st->ll[i] <= 0.0) { /* on the map: ll = -d^2 / (2 sigma^2) */
                st->sh_q += st->w[i] * (-2.0 * st->ll[i]);
            }
        } else {
            /* failed shot: the weights stay */
        }
        st->sh_sw2 += st->w[i] * st->w[i];
        break;
    case PF_E_MOM_MEAN:
        for (j = 0; j < nx; ++j) {
            kn->m[j] += st->w[i] * st->x[i][j];
        }
        break;
    case PF_E_MOM_COV: {
        double dx[GG_PF_NX];
        for (j = 0; j < nx; ++j) {
            dx[j] = st->x[i][j] - kn->m[j];
        }
        for (j = 0; j < nx; ++j) {
            for (k = 0; k <= j; ++k) {
                kn->cv[j][k] += st->w[i] * dx[j] * dx[k];
            }
        }
        break;
    }
    case PF_E_PICK: {
        /* systematic resampling: one uniform; particle r gets floor or ceil of N w_r copies */
        const double target = (st->sh_u0 + (double)i) / (double)n;
        int r = st->sh_ri;
        /* MISRA 14.1: the loop counter is the integer r; the float term only ends the loop early */
        /* cppcheck-suppress misra-c2012-14.1 */
        for (; (r < (n - 1)) && (st->sh_cum < target); ++r) {
            st->sh_cum += st->w[r + 1];
        }
        st->sh_ri = r;
        for (k = 0; k < GG_PF_NX; ++k) {
            st->xs[i][k] = st->x[r][k];
        }
        break;
    }
    case PF_E_COPY:
        for (k = 0; k < GG_PF_NX; ++k) {
            st->x[i][k] = st->xs[i][k];
        }
        st->w[i] = 1.0 / (double)n;
        break;
    case PF_E_REG:
        s = (st->cfg.model == GG_PF_MODEL_RBPF) ? pf_regularise_rb_one(st, i, kn)
                                                : pf_regularise_one(st, i, nx, kn);
        break;
    default: /* PF_E_MEAN */
        for (k = 0; k < GG_PF_NX; ++k) {
            st->sh_mean[k] += st->w[i] * st->x[i][k];
        }
        st->sh_m2[0] += st->w[i] * st->x[i][0] * st->x[i][0];
        st->sh_m2[1] += st->w[i] * st->x[i][1] * st->x[i][1];
        break;
    }
    return s;
}

/* The next stage once every particle of the current one is done. */
static gg_status_t pf_end_stage_done(gg_pf_t *st, int nx, gg_pf_output_t *out)
{
    const gg_pf_config_t *c = &st->cfg;
    int k;
    gg_status_t s = GG_OK;
    int next = PF_E_DONE;
    switch (st->sh_stage) {
    case PF_E_WEIGH:
        if ((st->sh_have == 0) || !(st->sh_sw > 0.0) || !GG_ISFINITE(st->sh_sw)) {
            st->sh_degen = 1;
            st->sh_health |= GG_PF_H_DEGENERATE;
            st->n_degenerate++;
        }
        st->n_updates++;
        next = PF_E_NORM;
        break;
    case PF_E_NORM:
        next = pf_end_after_norm(st);
        break;
    case PF_E_MOM_MEAN:
        next = PF_E_MOM_COV;
        break;
    case PF_E_MOM_COV:
        pf_kernel_chol(&st->kn, nx);
        next = PF_E_PICK;
        break;
    case PF_E_PICK:
        next = PF_E_COPY;
        break;
    case PF_E_COPY:
        if (st->reg_h > 0.0) {
            next = PF_E_REG;
        } else {
            next = PF_E_MEAN;
        }
        break;
    case PF_E_REG:
        next = PF_E_MEAN;
        break;
    default: { /* PF_E_MEAN: fixed-gain smoothing (paper eqs. 9-10) and the output */
        double v0;
        double v1;
        st->corr[0] += c->gain * (st->sh_mean[0] - st->corr[0]);
        st->corr[1] += c->gain * (st->sh_mean[1] - st->corr[1]);
        out->corr[0] = st->corr[0];
        out->corr[1] = st->corr[1];
        for (k = 0; k < GG_PF_NX; ++k) {
            out->mean[k] = st->sh_mean[k];
        }
        v0 = st->sh_m2[0] - (st->sh_mean[0] * st->sh_mean[0]);
        v1 = st->sh_m2[1] - (st->sh_mean[1] * st->sh_mean[1]);
        out->spread[0] = (v0 > 0.0) ? gg_sqrt_d(v0) : 0.0;
        out->spread[1] = (v1 > 0.0) ? gg_sqrt_d(v1) : 0.0;
        out->ess = st->sh_ess;
        if (c->model == GG_PF_MODEL_RBPF) {
            const double vfi = st->P_fi[0][0] + st->P_fi[1][1];
            out->spread_fi[0] = gg_sqrt_d(st->P_fi[0][0]);
            out->spread_fi[1] = gg_sqrt_d(st->P_fi[1][1]);
            out->info = (vfi > 0.0) ? (1.0 - (((out->spread[0] * out->spread[0]) + (out->spread[1] * out->spread[1])) / vfi))
                                    : 0.0;
        } else {
            out->spread_fi[0] = 0.0;
            out->spread_fi[1] = 0.0;
            out->info = -1.0;
        }
        out->gzz_mean = st->sh_gzz;
        out->nis = ((st->sh_in.shot_ok != 0) && (st->sh_degen == 0)) ? st->sh_q : -1.0;
        out->health = st->sh_health;
        next = PF_E_DONE;
        break;
    }
    }
    if (next == PF_E_PICK) {
        s = gg_rng_uniform(&st->rng, &st->sh_u0);
        st->sh_cum = st->w[0];
        st->sh_ri = 0;
    }
    if ((next == PF_E_MOM_MEAN) || (next == PF_E_MEAN)) {
        for (int j = 0; j < GG_PF_NX; ++j) {
            st->kn.m[j] = 0.0;
            st->sh_mean[j] = 0.0;
            for (k = 0; k < GG_PF_NX; ++k) {
                st->kn.cv[j][k] = 0.0;
                st->kn.el[j][k] = 0.0;
            }
        }
        st->sh_m2[0] = 0.0;
        st->sh_m2[1] = 0.0;
    }
    st->sh_stage = next;
    st->sh_i = 0;
    return s;
}

gg_status_t gg_pf_step_end_chunk(gg_pf_t *st, int max_particles, gg_pf_output_t *out, int *done)
{
    int budget;
    int nx;
    gg_status_t s = GG_OK;
    if ((st == NULL) || (out == NULL) || (done == NULL)) {
        return GG_ERR_NULL;
    }
    if ((st->shot_open == 0) || (st->sh_next < st->cfg.n)) {
        return GG_ERR_SEQUENCE; /* not begun, or particles left to predict and weigh */
    }
    if (max_particles < 1) {
        return GG_ERR_RANGE;
    }
    nx = pf_nx(&st->cfg);
    if (st->sh_stage < 0) { /* first call of this shot's end */
        if (st->sh_in.shot_ok != 0) {
            st->sh_stage = PF_E_WEIGH;
        } else {
            st->sh_stage = PF_E_NORM;
        }
        st->sh_i = 0;
        st->sh_sw = 0.0;
        st->sh_sw2 = 0.0;
        st->sh_gzz = 0.0;
        st->sh_q = 0.0;
        st->sh_degen = 0;
        if (st->sh_in.shot_ok == 0) {
            st->n_skipped++;
        } else if (st->sh_have == 0) {
            st->sh_stage = PF_E_NORM; /* no candidate on the map: degenerate, weights reset */
            st->sh_degen = 1;
            st->sh_health |= GG_PF_H_DEGENERATE;
            st->n_degenerate++;
            st->n_updates++;
        } else {
            /* weighed below */
        }
    }
    budget = max_particles;
    /* bounded: at most max_particles particle passes plus one hand-over per stage */
    while ((s == GG_OK) && (st->sh_stage != PF_E_DONE) && (budget > 0)) {
        if (st->sh_i < st->cfg.n) {
            s = pf_end_particle(st, nx);
            st->sh_i++;
            budget--;
        }
        if ((s == GG_OK) && (st->sh_i >= st->cfg.n)) {
            s = pf_end_stage_done(st, nx, out);
        }
    }
    *done = 0;
    if ((s != GG_OK) || (st->sh_stage == PF_E_DONE)) {
        st->shot_open = 0; /* an error cannot happen: the generator has no failure mode */
        st->sh_stage = -1;
        if (s == GG_OK) {
            *done = 1;
        } else {
            *done = 0;
        }
    }
    return s;
}

gg_status_t gg_pf_step_end(gg_pf_t *st, gg_pf_output_t *out)
{
    int done = 0;
    /* every stage in one call: eight passes over at most GG_PF_MAX particles */
    gg_status_t s = gg_pf_step_end_chunk(st, 8 * GG_PF_MAX, out, &done);
    if ((s == GG_OK) && (done == 0)) {
        s = GG_ERR_SEQUENCE; /* not reached: eight passes cover every stage */
    }
    return s;
}

/* Closed loop: the correction (dn, de) was added to the INS position and (dvn, dve)
 * to its velocity, so the particles (corrections to the INS) and the smoothed
 * correction move by minus them. */
gg_status_t gg_pf_shift(gg_pf_t *st, double dn_m, double de_m, double dvn_mps, double dve_mps)
{
    int i;
    if (st == NULL) {
        return GG_ERR_NULL;
    }
    if (!st->initialized) {
        return GG_ERR_NOT_INIT;
    }
    if (st->shot_open != 0) {
        return GG_ERR_SEQUENCE;
    }
    if (!GG_ISFINITE(dn_m) || !GG_ISFINITE(de_m) || !GG_ISFINITE(dvn_mps) || !GG_ISFINITE(dve_mps)) {
        return GG_ERR_NONFINITE;
    }
    for (i = 0; i < st->cfg.n; ++i) {
        st->x[i][0] -= dn_m;
        st->x[i][1] -= de_m;
        st->x[i][2] -= dvn_mps;
        st->x[i][3] -= dve_mps;
    }
    st->corr[0] -= dn_m;
    st->corr[1] -= de_m;
    return GG_OK;
}

gg_status_t gg_pf_set_map(gg_pf_t *st, const gg_pf_map_t *map)
{
    if ((st == NULL) || (map == NULL)) {
        return GG_ERR_NULL;
    }
    if (map->gzz == NULL) {
        return GG_ERR_CONFIG;
    }
    st->cfg.map = *map;
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
