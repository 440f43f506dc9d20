/* Parity-space fault detection, isolation and accommodation; see fdi2d.h. */
#include "ggins/fdi2d.h"

#include <stddef.h>

#define N_READ 8U

/* reading value hi + lo */
static gg_real_t rd(const gg_diff2d_input_t *in, uint32_t s, uint32_t ax)
{
    return (gg_real_t)in->f[s][ax] + (gg_real_t)in->f_lo[s][ax];
}

static void wr(gg_diff2d_input_t *in, uint32_t s, uint32_t ax, gg_real_t v)
{
    const double hi = (double)v;
    in->f[s][ax] = hi;
    in->f_lo[s][ax] = (double)(v - (gg_real_t)hi);
}

static void parity(const gg_fdi2d_t *st, const gg_diff2d_input_t *in, gg_real_t *px,
                   gg_real_t *pz, gg_real_t *ps)
{
    *px = 0.5L * ((rd(in, 0U, 0U) + rd(in, 2U, 0U)) - (rd(in, 1U, 0U) + rd(in, 3U, 0U)));
    *pz = 0.5L * ((rd(in, 0U, 1U) + rd(in, 2U, 1U)) - (rd(in, 1U, 1U) + rd(in, 3U, 1U)));
    /* differences of neighbouring readings: hi - hi exactly, then the lo parts */
    const gg_real_t dx = ((gg_real_t)in->f[3][0] - (gg_real_t)in->f[1][0]) +
                         ((gg_real_t)in->f_lo[3][0] - (gg_real_t)in->f_lo[1][0]);
    const gg_real_t dz = ((gg_real_t)in->f[2][1] - (gg_real_t)in->f[0][1]) +
                         ((gg_real_t)in->f_lo[2][1] - (gg_real_t)in->f_lo[0][1]);
    *ps = (dx / (2.0L * st->cfg.b_m)) - (dz / (2.0L * st->cfg.a_m));
}

static uint32_t popcount8(uint32_t m)
{
    uint32_t n = 0U;
    uint32_t i;
    for (i = 0U; i < N_READ; ++i) {
        n += (m >> i) & 1U;
    }
    return n;
}

/* Rebuild reading (s, ax) from its group's parity relation, p = p_exp (the
 * expected finite-baseline curvature term). */
static void rebuild(gg_diff2d_input_t *in, uint32_t s, uint32_t ax, gg_real_t p_exp)
{
    /* p = ((r0 + r2) - (r1 + r3))/2: r_s from the other three */
    const gg_real_t p2 = 2.0L * p_exp;
    const gg_real_t r0 = rd(in, 0U, ax);
    const gg_real_t r1 = rd(in, 1U, ax);
    const gg_real_t r2 = rd(in, 2U, ax);
    const gg_real_t r3 = rd(in, 3U, ax);
    gg_real_t v;
    if (s == 0U) {
        v = ((r1 + r3) - r2) + p2;
    } else if (s == 1U) {
        v = ((r0 + r2) - r3) - p2;
    } else if (s == 2U) {
        v = ((r1 + r3) - r0) + p2;
    } else {
        v = ((r0 + r2) - r1) - p2;
    }
    wr(in, s, ax, v);
}

gg_status_t gg_fdi2d_init(gg_fdi2d_t *st, const gg_fdi2d_config_t *cfg)
{
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    st->initialized = 0;
    if (!GG_ISFINITE(cfg->a_m) || !(cfg->a_m > 0.0L) || !GG_ISFINITE(cfg->b_m) ||
        !(cfg->b_m > 0.0L) || !GG_ISFINITE(cfg->parity_f_max) || (cfg->parity_f_max < 0.0) ||
        !GG_ISFINITE(cfg->asym_max) || (cfg->asym_max < 0.0)) {
        return GG_ERR_CONFIG;
    }
    st->cfg = *cfg;
    st->excluded = 0U;
    {
        uint32_t ax;
        uint32_t k;
        for (ax = 0U; ax < 2U; ++ax) {
            for (k = 0U; k < 3U; ++k) {
                st->held[ax][k] = 0.0L;
            }
        }
    }
    st->have_good = 0;
    st->initialized = 1;
    return GG_OK;
}

/* Which single reading explains the residuals (p_x, p_z, p_s) best?
 * Returns its bit, or 0 when none fits; *pair set for the ambiguous pairs. */
static uint32_t isolate(const gg_fdi2d_t *st, gg_real_t px, gg_real_t pz, gg_real_t ps,
                        uint32_t *pair)
{
    const gg_real_t ia = 1.0L / (2.0L * st->cfg.a_m);
    const gg_real_t ib = 1.0L / (2.0L * st->cfg.b_m);
    /* residuals normalised by their thresholds so the three are comparable */
    const gg_real_t tf = (st->cfg.parity_f_max > 0.0) ? (gg_real_t)st->cfg.parity_f_max : 1.0L;
    const gg_real_t ts = (st->cfg.asym_max > 0.0) ? (gg_real_t)st->cfg.asym_max : 1.0L;
    const gg_real_t sig[6][3] = {
        {-0.5L, 0.0L, -ib}, /* 2x */
        {-0.5L, 0.0L, ib},  /* 4x */
        {0.0L, 0.5L, ia},   /* 1z */
        {0.0L, 0.5L, -ia},  /* 3z */
        {0.5L, 0.0L, 0.0L}, /* 1x or 3x */
        {0.0L, -0.5L, 0.0L} /* 2z or 4z */
    };
    const uint32_t bits[6] = {GG_FDI_BIT(1, 0), GG_FDI_BIT(3, 0), GG_FDI_BIT(0, 1),
                              GG_FDI_BIT(2, 1), GG_FDI_BIT(0, 0) | GG_FDI_BIT(2, 0),
                              GG_FDI_BIT(1, 1) | GG_FDI_BIT(3, 1)};
    const gg_real_t p[3] = {px / tf, pz / tf, ps / ts};
    gg_real_t best = -1.0L;
    uint32_t best_bits = 0U;
    size_t c;
    for (c = 0U; c < 6U; ++c) {
        const gg_real_t s[3] = {sig[c][0] / tf, sig[c][1] / tf, sig[c][2] / ts};
        const gg_real_t ss = (s[0] * s[0]) + (s[1] * s[1]) + (s[2] * s[2]);
        const gg_real_t sp = (s[0] * p[0]) + (s[1] * p[1]) + (s[2] * p[2]);
        const gg_real_t d = sp / ss; /* least-squares fault size */
        const gg_real_t e0 = p[0] - (d * s[0]);
        const gg_real_t e1 = p[1] - (d * s[1]);
        const gg_real_t e2 = p[2] - (d * s[2]);
        const gg_real_t res = (e0 * e0) + (e1 * e1) + (e2 * e2);
        if ((best < 0.0L) || (res < best)) {
            best = res;
            best_bits = bits[c];
        }
    }
    /* the best fit must explain the residuals: what is left must be below
     * the thresholds (normalised: below 1 in each) */
    if (best > 1.0L) {
        best_bits = 0U;
    }
    *pair = 0U;
    if (popcount8(best_bits) == 2U) {
        *pair = 1U;
    }
    return best_bits;
}

/* Readings of axis group ax (mask). */
static uint32_t group_mask(uint32_t ax)
{
    uint32_t m = 0x55u;
    if (ax != 0U) {
        m = 0xAAu;
    }
    return m;
}

/* Readings a fired parity test involves: p_x the x group, p_z the z group,
 * p_s the off-diagonal pairs (2x, 4x, 1z, 3z). */
static uint32_t test_readings(int fx, int fz, int fs)
{
    uint32_t m = 0U;
    if (fx != 0) {
        m |= 0x55u;
    }
    if (fz != 0) {
        m |= 0xAAu;
    }
    if (fs != 0) {
        m |= GG_FDI_BIT(1, 0) | GG_FDI_BIT(3, 0) | GG_FDI_BIT(0, 1) | GG_FDI_BIT(2, 1);
    }
    return m;
}

/* Group quantities of axis group ax (fdi2d.h): centre mean mA of pair A
 * (sensors 1, 3), difference dA = r3 - r1 of pair A, difference dB = r4 - r2
 * of pair B (sensors 2, 4), from four valid readings. */
static void group_quantities(const gg_diff2d_input_t *in, uint32_t ax, gg_real_t q[3])
{
    q[0] = 0.5L * (rd(in, 0U, ax) + rd(in, 2U, ax));
    q[1] = (((gg_real_t)in->f[2][ax] - (gg_real_t)in->f[0][ax]) +
            ((gg_real_t)in->f_lo[2][ax] - (gg_real_t)in->f_lo[0][ax]));
    q[2] = (((gg_real_t)in->f[3][ax] - (gg_real_t)in->f[1][ax]) +
            ((gg_real_t)in->f_lo[3][ax] - (gg_real_t)in->f_lo[1][ax]));
}

/* Degraded group ax: it lost more readings (bad) than its parity relation can
 * rebuild. Its three quantities are taken, in this order of preference, from
 * (1) its own usable readings, (2) the symmetry of the gradient (the group's
 * off-diagonal difference from the other group's, Gxz = Gzx: x pair B <-> z
 * pair A, scaled by the baselines), when that pair of the other group is
 * usable (avail_other), (3) the values held from the last good frame; then
 * all four readings are synthesised consistently (pair B's mean = mA - p_exp).
 * Flags of what was held into *flags. */
static gg_status_t degrade_group(const gg_fdi2d_t *st, gg_diff2d_input_t *w, uint32_t ax,
                                 uint32_t bad, int avail_other, gg_real_t p_exp, uint32_t *flags)
{
    const gg_real_t a = st->cfg.a_m;
    const gg_real_t b = st->cfg.b_m;
    const uint32_t usable = ~bad;
    const uint32_t u0 = usable & GG_FDI_BIT(0, ax);
    const uint32_t u1 = usable & GG_FDI_BIT(1, ax);
    const uint32_t u2 = usable & GG_FDI_BIT(2, ax);
    const uint32_t u3 = usable & GG_FDI_BIT(3, ax);
    gg_real_t q[3];
    gg_real_t other[3];
    uint32_t fl = GG_FDI_DEGRADED;
    /* the other group's off-diagonal difference, in this group's scale:
     * x group dB = 2b Gxz = 2b Gzx = (b/a) * (z group dA); z group dA = (a/b) * (x group dB) */
    group_quantities(w, 1U - ax, other);
    q[0] = 0.0L;
    q[1] = 0.0L;
    q[2] = 0.0L;
    if ((u0 != 0U) && (u2 != 0U)) {
        q[1] = (((gg_real_t)w->f[2][ax] - (gg_real_t)w->f[0][ax]) +
                ((gg_real_t)w->f_lo[2][ax] - (gg_real_t)w->f_lo[0][ax]));
    } else if ((ax == 1U) && (avail_other != 0)) {
        q[1] = (a / b) * other[2];
    } else if (st->have_good != 0) {
        q[1] = st->held[ax][1];
        if (ax == 0U) {
            fl |= GG_FDI_COAST_GXX;
        } else {
            fl |= GG_FDI_COAST_OFFD;
        }
    } else {
        return GG_ERR_SENSOR; /* nothing to hold yet */
    }
    if ((u1 != 0U) && (u3 != 0U)) {
        q[2] = (((gg_real_t)w->f[3][ax] - (gg_real_t)w->f[1][ax]) +
                ((gg_real_t)w->f_lo[3][ax] - (gg_real_t)w->f_lo[1][ax]));
    } else if ((ax == 0U) && (avail_other != 0)) {
        q[2] = (b / a) * other[1];
    } else if (st->have_good != 0) {
        q[2] = st->held[ax][2];
        if (ax == 0U) {
            fl |= GG_FDI_COAST_OFFD;
        } else {
            fl |= GG_FDI_COAST_GZZ;
        }
    } else {
        return GG_ERR_SENSOR;
    }
    /* centre mean of pair A from whatever reading is left */
    if ((u0 != 0U) && (u2 != 0U)) {
        q[0] = 0.5L * (rd(w, 0U, ax) + rd(w, 2U, ax));
    } else if ((u1 != 0U) && (u3 != 0U)) {
        q[0] = (0.5L * (rd(w, 1U, ax) + rd(w, 3U, ax))) + p_exp;
    } else if (u0 != 0U) {
        q[0] = rd(w, 0U, ax) + (0.5L * q[1]);
    } else if (u2 != 0U) {
        q[0] = rd(w, 2U, ax) - (0.5L * q[1]);
    } else if (u1 != 0U) {
        q[0] = (rd(w, 1U, ax) + (0.5L * q[2])) + p_exp;
    } else if (u3 != 0U) {
        q[0] = (rd(w, 3U, ax) - (0.5L * q[2])) + p_exp;
    } else if (st->have_good != 0) {
        q[0] = st->held[ax][0];
        fl |= GG_FDI_HOLD_FORCE;
    } else {
        return GG_ERR_SENSOR;
    }
    {
        const gg_real_t mb = q[0] - p_exp;
        wr(w, 0U, ax, q[0] - (0.5L * q[1]));
        wr(w, 2U, ax, q[0] + (0.5L * q[1]));
        wr(w, 1U, ax, mb - (0.5L * q[2]));
        wr(w, 3U, ax, mb + (0.5L * q[2]));
    }
    *flags |= fl;
    return GG_OK;
}

/* Accommodate the unusable readings `bad` in w: a group with one is rebuilt
 * from its parity relation, a group with more is degraded (degrade_group).
 * *rebuilt gets the readings written. */
static gg_status_t accommodate_groups(const gg_fdi2d_t *st, gg_diff2d_input_t *w, uint32_t bad,
                               const gg_real_t p_exp[2], uint32_t *rebuilt, uint32_t *flags)
{
    gg_status_t res = GG_OK;
    uint32_t deg = 0U; /* degraded groups: bit ax */
    uint32_t s;
    uint32_t ax;
    for (ax = 0U; ax < 2U; ++ax) {
        const uint32_t g = bad & group_mask(ax);
        if (popcount8(g) > 1U) {
            deg |= 1U << ax;
        } else {
            for (s = 0U; s < 4U; ++s) {
                if ((g & GG_FDI_BIT(s, ax)) != 0U) {
                    rebuild(w, s, ax, p_exp[ax]);
                    *rebuilt |= GG_FDI_BIT(s, ax);
                }
            }
        }
    }
    for (ax = 0U; (ax < 2U) && (res == GG_OK); ++ax) {
        if ((deg & (1U << ax)) != 0U) {
            /* symmetry source: z pair A (1z, 3z) for the x group, x pair B (2x, 4x) for z */
            uint32_t src = GG_FDI_BIT(0, 1) | GG_FDI_BIT(2, 1);
            int avail = 0;
            if (ax == 1U) {
                src = GG_FDI_BIT(1, 0) | GG_FDI_BIT(3, 0);
            }
            if (((deg & (1U << (1U - ax))) == 0U) || ((bad & src) == 0U)) {
                avail = 1;
            }
            res = degrade_group(st, w, ax, bad, avail, p_exp[ax], flags);
            *rebuilt |= group_mask(ax);
        }
    }
    return res;
}

gg_status_t gg_fdi2d_step(gg_fdi2d_t *st, uint32_t known_bad, const gg_real_t p_exp[2],
                          gg_diff2d_input_t *in, gg_fdi2d_output_t *out)
{
    gg_diff2d_input_t w;
    gg_fdi2d_output_t o;
    gg_status_t res;
    uint32_t s;
    uint32_t ax;
    uint32_t excluded;
    uint32_t bad;
    if ((st == NULL) || (in == NULL) || (out == NULL) || (p_exp == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(p_exp[0]) || !GG_ISFINITE(p_exp[1])) {
        return GG_ERR_NONFINITE;
    }
    for (s = 0U; s < 4U; ++s) {
        for (ax = 0U; ax < 2U; ++ax) {
            if (((known_bad & GG_FDI_BIT(s, ax)) == 0U) &&
                (!GG_ISFINITE(in->f[s][ax]) || !GG_ISFINITE(in->f_lo[s][ax]))) {
                return GG_ERR_NONFINITE;
            }
        }
    }
    w = *in;
    excluded = st->excluded;
    bad = known_bad | excluded;
    o.flags = 0U;
    o.rebuilt = 0U;
    res = accommodate_groups(st, &w, bad, p_exp, &o.rebuilt, &o.flags);
    if (res != GG_OK) {
        return res;
    }
    parity(st, &w, &o.p_x, &o.p_z, &o.p_s);
    o.p_x -= p_exp[0];
    o.p_z -= p_exp[1];
    {
        /* a group with a rebuilt reading has no parity left to test; a
         * degraded group's synthesised pairs make the symmetry residual
         * vanish by construction */
        int test_x = 0;
        int test_z = 0;
        int test_s = 0;
        if (((o.rebuilt & 0x55u) == 0U) && (st->cfg.parity_f_max > 0.0)) {
            test_x = 1;
        }
        if (((o.rebuilt & 0xAAu) == 0U) && (st->cfg.parity_f_max > 0.0)) {
            test_z = 1;
        }
        if ((st->cfg.asym_max > 0.0) && ((o.flags & GG_FDI_DEGRADED) == 0U)) {
            test_s = 1;
        }
        const gg_real_t fx = (test_x != 0) ? o.p_x : 0.0L;
        const gg_real_t fz = (test_z != 0) ? o.p_z : 0.0L;
        const gg_real_t fs = (test_s != 0) ? o.p_s : 0.0L;
        const gg_real_t lf = (gg_real_t)st->cfg.parity_f_max;
        const gg_real_t ls = (gg_real_t)st->cfg.asym_max;
        int hit_x = 0;
        int hit_z = 0;
        int hit_s = 0;
        if ((test_x != 0) && ((fx > lf) || (fx < -lf))) {
            hit_x = 1;
        }
        if ((test_z != 0) && ((fz > lf) || (fz < -lf))) {
            hit_z = 1;
        }
        if ((test_s != 0) && ((fs > ls) || (fs < -ls))) {
            hit_s = 1;
        }
        if ((hit_x != 0) || (hit_z != 0) || (hit_s != 0)) {
            uint32_t pair = 0U;
            uint32_t which = isolate(st, fx, fz, fs, &pair);
            o.flags |= GG_FDI_DETECTED;
            if ((which & bad) != 0U) {
                which = 0U;
            }
            uint32_t which_group = 0xAAu;
            if ((which & 0x55u) != 0U) {
                which_group = 0x55u;
            }
            if ((which != 0U) && (pair == 0U) && (popcount8((bad | which) & which_group) > 1U)) {
                /* isolated, but its group already lost a reading: exclude it
                 * for good and degrade the group */
                excluded |= which;
                o.flags |= GG_FDI_NEW_EXCL;
                w = *in;
                o.rebuilt = 0U;
                res = accommodate_groups(st, &w, bad | which, p_exp, &o.rebuilt, &o.flags);
            } else if ((which != 0U) && (pair == 0U)) {
                /* isolated: exclude for good and rebuild it */
                excluded |= which;
                o.flags |= GG_FDI_NEW_EXCL;
                for (s = 0U; s < 4U; ++s) {
                    for (ax = 0U; ax < 2U; ++ax) {
                        if ((which & GG_FDI_BIT(s, ax)) != 0U) {
                            rebuild(&w, s, ax, p_exp[ax]);
                            o.rebuilt |= GG_FDI_BIT(s, ax);
                        }
                    }
                }
            } else if ((which != 0U) && (st->have_good != 0) && ((which & 0x55u) != 0U)) {
                /* 1x or 3x: centre x force from sensors 2, 4; Gxx coasts */
                const gg_real_t m = 0.5L * (rd(&w, 1U, 0U) + rd(&w, 3U, 0U));
                wr(&w, 0U, 0U, (m + p_exp[0]) - (0.5L * st->held[0][1]));
                wr(&w, 2U, 0U, (m + p_exp[0]) + (0.5L * st->held[0][1]));
                o.flags |= GG_FDI_COAST_GXX;
            } else if ((which != 0U) && (st->have_good != 0)) {
                /* 2z or 4z: centre z force from sensors 1, 3; Gzz coasts */
                const gg_real_t m = 0.5L * (rd(&w, 0U, 1U) + rd(&w, 2U, 1U));
                wr(&w, 1U, 1U, (m - p_exp[1]) - (0.5L * st->held[1][2]));
                wr(&w, 3U, 1U, (m - p_exp[1]) + (0.5L * st->held[1][2]));
                o.flags |= GG_FDI_COAST_GZZ;
            } else {
                /* no single reading explains the residuals (several faults):
                 * every reading of the tests that fired is suspect on this
                 * frame, and so is the whole group of a suspect whose own
                 * test passed (a second fault there may cancel in it) or
                 * which holds a rebuilt reading (built from all the others);
                 * their groups degrade */
                uint32_t sus = test_readings(hit_x, hit_z, hit_s) & ~bad;
                const int tested[2] = {test_x, test_z};
                for (ax = 0U; ax < 2U; ++ax) {
                    const uint32_t gm = group_mask(ax);
                    if (((sus & gm) != 0U) && ((tested[ax] != 0) || ((o.rebuilt & gm) != 0U))) {
                        sus |= gm & ~bad;
                    }
                }
                w = *in;
                o.rebuilt = 0U;
                o.flags |= GG_FDI_SUSPECT;
                res = accommodate_groups(st, &w, bad | sus, p_exp, &o.rebuilt, &o.flags);
            }
        }
    }
    if (res != GG_OK) {
        return res;
    }
    if (o.rebuilt != 0U) {
        o.flags |= GG_FDI_REBUILT;
    }
    /* hold the group quantities of this frame (held ones stay as they were) */
    for (ax = 0U; ax < 2U; ++ax) {
        group_quantities(&w, ax, st->held[ax]);
    }
    st->have_good = 1;
    st->excluded = excluded;
    o.excluded = excluded;
    *in = w;
    *out = o;
    return GG_OK;
}

gg_status_t gg_fdi2d_expected_parity(gg_real_t a_m, gg_real_t b_m, gg_real_t mu,
                                     const gg_real_t r[3], gg_real_t p_exp[2])
{
    gg_real_t r2;
    gg_real_t rn;
    gg_real_t r5;
    gg_real_t r7;
    uint32_t k;
    if ((r == NULL) || (p_exp == NULL)) {
        return GG_ERR_NULL;
    }
    if ((gg_finite3(r) == 0) || !GG_ISFINITE(mu) || !GG_ISFINITE(a_m) || !GG_ISFINITE(b_m)) {
        return GG_ERR_NONFINITE;
    }
    r2 = (r[0] * r[0]) + (r[1] * r[1]) + (r[2] * r[2]);
    if (!(r2 > 1.0L)) {
        return GG_ERR_RANGE;
    }
    rn = sqrtl(r2);
    r5 = r2 * r2 * rn;
    r7 = r5 * r2;
    for (k = 0U; k < 2U; ++k) {
        const gg_real_t xi = r[2U * k]; /* component i = x (k = 0) or z (k = 1) */
        const gg_real_t x = r[0];
        const gg_real_t z = r[2];
        /* D_i,xx and D_i,zz */
        const gg_real_t dxx = mu * ((-15.0L * xi * x * x / r7) +
                                    (3.0L * (xi + (2.0L * ((k == 0U) ? x : 0.0L))) / r5));
        const gg_real_t dzz = mu * ((-15.0L * xi * z * z / r7) +
                                    (3.0L * (xi + (2.0L * ((k == 1U) ? z : 0.0L))) / r5));
        p_exp[k] = -0.5L * ((a_m * a_m * dxx) - (b_m * b_m * dzz));
    }
    return GG_OK;
}
