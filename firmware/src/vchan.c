/* Third-order baro-inertial vertical channel; see vchan.h for the design. */
#include "ggins/vchan.h"

#include <stddef.h>

#include "ggins/frame.h"

/* largest p T accepted (keeps the Taylor series short and accurate) */
#define PT_MAX 1.0L
/* Taylor terms for exp(): (x^n / n!) < 1e-40 for |x| <= 1.5 at n = 40 */
#define EXP_TERMS 40U

typedef struct {
    gg_real_t m[3][3];
} mat3_t;

static void mat3_mul(const mat3_t *a, const mat3_t *b, mat3_t *c)
{
    size_t i;
    size_t j;
    size_t k;
    for (i = 0U; i < 3U; ++i) {
        for (j = 0U; j < 3U; ++j) {
            gg_real_t acc = 0.0L;
            for (k = 0U; k < 3U; ++k) {
                acc += a->m[i][k] * b->m[k][j];
            }
            c->m[i][j] = acc;
        }
    }
}

/* exp(M) by its Taylor series (||M|| small: see PT_MAX) */
static void mat3_exp(const mat3_t *m, mat3_t *e)
{
    mat3_t term;
    mat3_t next;
    size_t i;
    size_t j;
    size_t n;
    for (i = 0U; i < 3U; ++i) {
        for (j = 0U; j < 3U; ++j) {
            term.m[i][j] = (i == j) ? 1.0L : 0.0L;
            e->m[i][j] = term.m[i][j];
        }
    }
    for (n = 1U; n <= EXP_TERMS; ++n) {
        mat3_mul(&term, m, &next);
        for (i = 0U; i < 3U; ++i) {
            for (j = 0U; j < 3U; ++j) {
                term.m[i][j] = next.m[i][j] / (gg_real_t)n;
                e->m[i][j] += term.m[i][j];
            }
        }
    }
}

static gg_real_t scalar_exp(gg_real_t x)
{
    gg_real_t term = 1.0L;
    gg_real_t sum = 1.0L;
    size_t n;
    for (n = 1U; n <= EXP_TERMS; ++n) {
        term = (term * x) / (gg_real_t)n;
        sum += term;
    }
    return sum;
}

static gg_real_t det3(const mat3_t *a)
{
    const gg_real_t(*m)[3] = a->m;
    return (m[0][0] * ((m[1][1] * m[2][2]) - (m[1][2] * m[2][1]))) -
           (m[0][1] * ((m[1][0] * m[2][2]) - (m[1][2] * m[2][0]))) +
           (m[0][2] * ((m[1][0] * m[2][1]) - (m[1][1] * m[2][0])));
}

/* Discrete gain K placing eig((I + K C) Phi) at exp(-p_i T); see vchan.h. */
static gg_status_t design(const gg_real_t poles[3], gg_real_t w, gg_real_t t, gg_real_t kd[3])
{
    const mat3_t at = {{{0.0L, t, 0.0L}, {w * t, 0.0L, -t}, {0.0L, 0.0L, 0.0L}}};
    mat3_t phi;
    mat3_t phi2;
    mat3_t phi3;
    mat3_t obs;
    mat3_t alpha;
    gg_real_t z[3];
    gg_real_t c2;
    gg_real_t c1;
    gg_real_t c0;
    gg_real_t d;
    gg_real_t x[3];
    size_t i;
    size_t j;
    mat3_exp(&at, &phi);
    mat3_mul(&phi, &phi, &phi2);
    mat3_mul(&phi2, &phi, &phi3);
    for (j = 0U; j < 3U; ++j) {
        /* rows C Phi, C Phi^2, C Phi^3 (C picks row 0) */
        obs.m[0][j] = phi.m[0][j];
        obs.m[1][j] = phi2.m[0][j];
        obs.m[2][j] = phi3.m[0][j];
    }
    for (i = 0U; i < 3U; ++i) {
        z[i] = scalar_exp(-poles[i] * t);
    }
    /* alpha(z) = (z - z0)(z - z1)(z - z2) = z^3 + c2 z^2 + c1 z + c0 */
    c2 = -((z[0] + z[1]) + z[2]);
    c1 = ((z[0] * z[1]) + (z[0] * z[2])) + (z[1] * z[2]);
    c0 = -(z[0] * z[1] * z[2]);
    for (i = 0U; i < 3U; ++i) {
        for (j = 0U; j < 3U; ++j) {
            alpha.m[i][j] = phi3.m[i][j] + (c2 * phi2.m[i][j]) + (c1 * phi.m[i][j]) +
                            ((i == j) ? c0 : 0.0L);
        }
    }
    /* x = O^-1 e3 by Cramer's rule */
    d = det3(&obs);
    if (!GG_ISFINITE(d) || (d == 0.0L)) {
        return GG_ERR_CONFIG;
    }
    for (j = 0U; j < 3U; ++j) {
        mat3_t oj;
        size_t r;
        size_t q;
        for (r = 0U; r < 3U; ++r) {
            for (q = 0U; q < 3U; ++q) {
                oj.m[r][q] = (q == j) ? ((r == 2U) ? 1.0L : 0.0L) : obs.m[r][q];
            }
        }
        x[j] = det3(&oj) / d;
    }
    for (i = 0U; i < 3U; ++i) {
        kd[i] = -(((alpha.m[i][0] * x[0]) + (alpha.m[i][1] * x[1])) + (alpha.m[i][2] * x[2]));
        if (!GG_ISFINITE(kd[i])) {
            return GG_ERR_CONFIG;
        }
    }
    return GG_OK;
}

gg_status_t gg_vchan_init(gg_vchan_t *st, const gg_vchan_config_t *cfg)
{
    size_t i;
    gg_real_t pmax = 0.0L;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    st->initialized = 0;
    for (i = 0U; i < 3U; ++i) {
        if (!GG_ISFINITE(cfg->poles[i]) || !(cfg->poles[i] > 0.0L)) {
            return GG_ERR_CONFIG;
        }
        if (cfg->poles[i] > pmax) {
            pmax = cfg->poles[i];
        }
    }
    if (!GG_ISFINITE(cfg->omega_s2) || !(cfg->omega_s2 > 0.0L) || (cfg->period_us <= 0) ||
        (cfg->max_age_us < 0) || (cfg->coast_us <= 0) || !GG_ISFINITE(cfg->alt_min_m) ||
        !GG_ISFINITE(cfg->alt_max_m) || !(cfg->alt_max_m > cfg->alt_min_m) ||
        !GG_ISFINITE(cfg->gate_m) || !(cfg->gate_m > 0.0) || (cfg->max_rejects < 1)) {
        return GG_ERR_CONFIG;
    }
    if ((pmax * ((gg_real_t)cfg->period_us * 1.0e-6L)) > PT_MAX) {
        return GG_ERR_CONFIG;
    }
    /* plausibility (finite but absurd values would overflow downstream) */
    if ((cfg->omega_s2 > 1.0e-3L) || (cfg->period_us > 100000000) ||
        (cfg->max_age_us > 100000000) || (cfg->coast_us > GG_TIME_MAX) ||
        (cfg->alt_min_m < -1.0e6) || (cfg->alt_max_m > 1.0e7) || (cfg->gate_m > 1.0e6)) {
        return GG_ERR_RANGE;
    }
    {
        const gg_real_t p1 = cfg->poles[0];
        const gg_real_t p2 = cfg->poles[1];
        const gg_real_t p3 = cfg->poles[2];
        const gg_status_t ds = design(cfg->poles, 2.0L * cfg->omega_s2,
                                      (gg_real_t)cfg->period_us * 1.0e-6L, st->kd);
        if (ds != GG_OK) {
            return ds;
        }
        st->k1 = p1 + p2 + p3;
        st->k2 = ((p1 * p2) + (p1 * p3) + (p2 * p3)) + (2.0L * cfg->omega_s2);
        st->k3 = p1 * p2 * p3;
    }
    st->cfg = *cfg;
    st->a_c = 0.0L;
    st->last_accept_utime = 0;
    st->last_sample_utime = 0;
    st->rejects = 0;
    st->started = 0;
    st->initialized = 1;
    return GG_OK;
}

gg_status_t gg_vchan_step(gg_vchan_t *st, int64_t now_us, gg_real_t h_ins_m,
                          const gg_vchan_sample_t *sample, gg_vchan_output_t *out)
{
    gg_vchan_output_t o;
    if ((st == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(h_ins_m)) {
        return GG_ERR_NONFINITE;
    }
    if ((now_us < 0) || (now_us > GG_TIME_MAX)) {
        return GG_ERR_RANGE; /* differences with it could overflow */
    }
    o.dh_m = 0.0L;
    o.dv_mps = 0.0L;
    o.innov_m = 0.0L;
    o.k_applied[0] = 0.0L;
    o.k_applied[1] = 0.0L;
    o.k_applied[2] = 0.0L;
    o.health = 0U;
    o.accepted = 0;
    if ((sample != NULL) && (sample->status != GG_SENSOR_ABSENT) &&
        ((st->started == 0) || (sample->utime > st->last_sample_utime))) {
        /* a new sample */
        if ((sample->status != GG_SENSOR_OK) || !GG_ISFINITE(sample->alt_m) ||
            (sample->alt_m < st->cfg.alt_min_m) || (sample->alt_m > st->cfg.alt_max_m) ||
            (sample->utime < 0) || (sample->utime > GG_TIME_MAX)) {
            o.health |= GG_VCHAN_INVALID;
        } else if (((now_us - sample->utime) < 0) ||
                   ((now_us - sample->utime) > st->cfg.max_age_us)) {
            o.health |= GG_VCHAN_STALE;
        } else {
            const gg_real_t e = h_ins_m - (gg_real_t)sample->alt_m;
            o.innov_m = e;
            if ((e > (gg_real_t)st->cfg.gate_m) || (e < -(gg_real_t)st->cfg.gate_m)) {
                st->rejects += 1;
                if (st->rejects >= st->cfg.max_rejects) {
                    o.health |= GG_VCHAN_RECAPTURE;
                } else {
                    o.health |= GG_VCHAN_OUTLIER;
                }
            }
            if ((o.health & GG_VCHAN_OUTLIER) == 0U) {
                /* accepted: first sample only starts the clock */
                if (st->started != 0) {
                    int64_t span = sample->utime - st->last_accept_utime;
                    gg_real_t scale;
                    if (span > st->cfg.coast_us) {
                        span = st->cfg.period_us; /* after a coast: one nominal period */
                    }
                    scale = (gg_real_t)span / (gg_real_t)st->cfg.period_us;
                    o.dh_m = st->kd[0] * e * scale;
                    o.dv_mps = st->kd[1] * e * scale;
                    st->a_c += st->kd[2] * e * scale;
                    o.k_applied[0] = st->kd[0] * scale;
                    o.k_applied[1] = st->kd[1] * scale;
                    o.k_applied[2] = st->kd[2] * scale;
                }
                st->started = 1;
                st->rejects = 0;
                st->last_accept_utime = sample->utime;
                o.accepted = 1;
            }
            st->last_sample_utime = sample->utime;
        }
        if ((o.health & (GG_VCHAN_INVALID | GG_VCHAN_STALE)) != 0U) {
            st->last_sample_utime = sample->utime;
        }
    }
    if ((st->started == 0) || ((now_us - st->last_accept_utime) > st->cfg.coast_us)) {
        o.health |= GG_VCHAN_COAST;
    }
    o.a_c = st->a_c;
    *out = o;
    return GG_OK;
}
