/* Third-order baro-inertial vertical channel; see vchan.h for the design. */
#include "ggins/vchan.h"

#include <stddef.h>

#include "ggins/frame.h"

/* |p T| bound that keeps the Euler-discretised poles within 1 % */
#define PT_MAX 0.02L

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
    {
        const gg_real_t p1 = cfg->poles[0];
        const gg_real_t p2 = cfg->poles[1];
        const gg_real_t p3 = cfg->poles[2];
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
    o.dh_m = 0.0L;
    o.dv_mps = 0.0L;
    o.innov_m = 0.0L;
    o.health = 0U;
    o.accepted = 0;
    if ((sample != NULL) && (sample->status != GG_SENSOR_ABSENT) &&
        ((st->started == 0) || (sample->utime > st->last_sample_utime))) {
        /* a new sample */
        const int64_t age = now_us - sample->utime;
        if ((sample->status != GG_SENSOR_OK) || !GG_ISFINITE(sample->alt_m) ||
            (sample->alt_m < st->cfg.alt_min_m) || (sample->alt_m > st->cfg.alt_max_m)) {
            o.health |= GG_VCHAN_INVALID;
        } else if ((age < 0) || (age > st->cfg.max_age_us)) {
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
                    gg_real_t t;
                    if (span > st->cfg.coast_us) {
                        span = st->cfg.period_us; /* after a coast: one nominal period */
                    }
                    t = (gg_real_t)span * 1.0e-6L;
                    o.dh_m = -st->k1 * e * t;
                    o.dv_mps = -st->k2 * e * t;
                    st->a_c += st->k3 * e * t;
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
