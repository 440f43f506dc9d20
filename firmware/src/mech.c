/* Space-stabilized platform mechanization (Welker, Pachter & Huffman,
 * section V) with r'' = f + G (docs/design.md), velocity-Verlet fixed step. */
#include "ggins/mech.h"

#include <stddef.h>

static int finite_acc3(const gg_acc_t v[3])
{
    size_t j;
    int ok = 1;
    for (j = 0U; j < 3U; ++j) {
        if (!GG_ISFINITE(v[j].hi) || !GG_ISFINITE(v[j].lo)) {
            ok = 0;
        }
    }
    return ok;
}

gg_status_t gg_mech_init(gg_mech_t *st, const gg_mech_config_t *cfg)
{
    size_t j;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(cfg->dt_s) || !(cfg->dt_s > 0.0L) || (gg_finite3(cfg->r0) == 0) ||
        (gg_finite3(cfg->v0) == 0) || (gg_finite3(cfg->a0) == 0)) {
        return GG_ERR_CONFIG;
    }
    st->dt_s = cfg->dt_s;
    for (j = 0U; j < 3U; ++j) {
        gg_acc_set(&st->r[j], cfg->r0[j]);
        gg_acc_set(&st->v[j], cfg->v0[j]);
        st->a[j] = cfg->a0[j];
        st->a_prev[j] = cfg->a0[j];
        st->dr[j] = 0.0L;
    }
    st->pending = 0;
    st->have_prev = 0;
    st->initialized = 1;
    return GG_OK;
}

gg_status_t gg_mech_step_position(gg_mech_t *st, gg_real_t dr[3])
{
    size_t j;
    if ((st == NULL) || (dr == NULL)) {
        return GG_ERR_NULL;
    }
    if ((st->initialized == 0) || (st->pending != 0)) {
        return GG_ERR_NOT_INIT;
    }
    for (j = 0U; j < 3U; ++j) {
        const gg_real_t dt = st->dt_s;
        /* dr = v dt + a dt^2/2 + (a - a_prev) dt^2/6, velocity's low part kept */
        const gg_real_t jerk = (st->have_prev != 0) ? ((st->a[j] - st->a_prev[j]) / 6.0L) : 0.0L;
        st->dr[j] =
            (st->v[j].hi * dt) + ((st->v[j].lo * dt) + (((0.5L * st->a[j]) + jerk) * dt * dt));
        dr[j] = st->dr[j];
    }
    for (j = 0U; j < 3U; ++j) {
        st->r_prev[j] = st->r[j];
        gg_acc_add(&st->r[j], st->dr[j]);
    }
    st->pending = 1;
    return GG_OK;
}

static void undo_position(gg_mech_t *st)
{
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        st->r[j] = st->r_prev[j];
    }
    st->pending = 0;
}

gg_status_t gg_mech_step_velocity(gg_mech_t *st, const gg_real_t f_next[3],
                                  const gg_acc_t g_next[3])
{
    size_t j;
    gg_real_t a_next[3];
    if ((st == NULL) || (f_next == NULL) || (g_next == NULL)) {
        return GG_ERR_NULL;
    }
    if ((st->initialized == 0) || (st->pending == 0)) {
        return GG_ERR_NOT_INIT;
    }
    if ((gg_finite3(f_next) == 0) || (finite_acc3(g_next) == 0)) {
        undo_position(st);
        return GG_ERR_NONFINITE;
    }
    for (j = 0U; j < 3U; ++j) {
        /* f ~ -G ~ 10 m/s^2: f + G.hi cancels exactly (Sterbenz lemma, |f|
         * within a factor 2 of |G|); G.lo is then added to the small result. */
        a_next[j] = (f_next[j] + g_next[j].hi) + g_next[j].lo;
    }
    for (j = 0U; j < 3U; ++j) {
        gg_real_t dv = 0.5L * (st->a[j] + a_next[j]) * st->dt_s;
        if (st->have_prev != 0) {
            const gg_real_t d2 = (a_next[j] - (2.0L * st->a[j])) + st->a_prev[j];
            dv -= (d2 * st->dt_s) / 12.0L;
        }
        gg_acc_add(&st->v[j], dv);
        st->a_prev[j] = st->a[j];
        st->a[j] = a_next[j];
    }
    st->have_prev = 1;
    st->pending = 0;
    return GG_OK;
}

gg_status_t gg_mech_correct(gg_mech_t *st, const gg_real_t dr[3], const gg_real_t dv[3],
                            const gg_real_t da[3])
{
    size_t j;
    if ((st == NULL) || (dr == NULL) || (dv == NULL) || (da == NULL)) {
        return GG_ERR_NULL;
    }
    if ((st->initialized == 0) || (st->pending != 0)) {
        return GG_ERR_NOT_INIT;
    }
    if ((gg_finite3(dr) == 0) || (gg_finite3(dv) == 0) || (gg_finite3(da) == 0)) {
        return GG_ERR_NONFINITE;
    }
    for (j = 0U; j < 3U; ++j) {
        gg_acc_add(&st->r[j], dr[j]);
        gg_acc_add(&st->v[j], dv[j]);
        st->a[j] += da[j];
        st->a_prev[j] += da[j]; /* a shift, not a jerk */
    }
    return GG_OK;
}

gg_status_t gg_mech_get(const gg_mech_t *st, gg_real_t r[3], gg_real_t v[3])
{
    gg_acc_t ra[3];
    gg_acc_t va[3];
    gg_status_t status;
    if ((r == NULL) || (v == NULL)) {
        return GG_ERR_NULL;
    }
    status = gg_mech_get_acc(st, ra, va);
    if (status == GG_OK) {
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            r[j] = gg_acc_value(&ra[j]);
            v[j] = gg_acc_value(&va[j]);
        }
    }
    return status;
}

gg_status_t gg_mech_get_acc(const gg_mech_t *st, gg_acc_t r[3], gg_acc_t v[3])
{
    size_t j;
    if ((st == NULL) || (r == NULL) || (v == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (j = 0U; j < 3U; ++j) {
        r[j] = st->r[j];
        v[j] = st->v[j];
    }
    return GG_OK;
}
