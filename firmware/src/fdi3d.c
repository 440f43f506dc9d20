/* Pair-mean fault detection, isolation and accommodation of the 3-D
 * readings; see fdi3d.h. */
#include "ggins/fdi3d.h"

#include <stddef.h>

/* Rounds of detection and setting aside in one step: each round sets aside
 * at least one more of the 18 readings (after at most FDI3D_RESCUE_ROUNDS
 * in which consistent pairs are given back), so 24 is never reached. */
#define FDI3D_MAX_ROUNDS 24
#define FDI3D_RESCUE_ROUNDS 3

/* mask bit of reading (s, j) or pair-axis (p, j), the shift's range evident */
static uint32_t rbit(size_t s, size_t j)
{
    const uint32_t sh = (uint32_t)(((3U * s) + j) & 31U);
    return (uint32_t)1U << sh;
}

static gg_real_t rd3(double f[6][3], double f_lo[6][3], size_t s, size_t j)
{
    return (gg_real_t)f[s][j] + (gg_real_t)f_lo[s][j];
}

static void wr3(double f[6][3], double f_lo[6][3], size_t s, size_t j, gg_real_t v)
{
    const double hi = (double)v;
    f[s][j] = hi;
    f_lo[s][j] = (double)(v - (gg_real_t)hi);
}

static gg_real_t absr(gg_real_t x)
{
    return (x < 0.0L) ? -x : x;
}

/* column entry M[j][p] = (f_p,j - f_p+3,j) / (2 h_p) */
static gg_real_t m_entry(const gg_fdi3d_t *st, double f[6][3], double f_lo[6][3], size_t j, size_t p)
{
    return ((((gg_real_t)f[p][j] - (gg_real_t)f[p + 3U][j]) +
             ((gg_real_t)f_lo[p][j] - (gg_real_t)f_lo[p + 3U][j])) /
            (2.0L * st->cfg.half_base_m[p]));
}

/* [v x][j][p] */
static gg_real_t cross_entry(const gg_real_t v[3], size_t j, size_t p)
{
    gg_real_t c = 0.0L;
    if ((j == 0U) && (p == 1U)) {
        c = -v[2];
    } else if ((j == 0U) && (p == 2U)) {
        c = v[1];
    } else if ((j == 1U) && (p == 0U)) {
        c = v[2];
    } else if ((j == 1U) && (p == 2U)) {
        c = -v[0];
    } else if ((j == 2U) && (p == 0U)) {
        c = -v[1];
    } else if ((j == 2U) && (p == 1U)) {
        c = v[0];
    } else {
        /* diagonal: 0 */
    }
    return c;
}

gg_status_t gg_fdi3d_init(gg_fdi3d_t *st, const gg_fdi3d_config_t *cfg)
{
    size_t p;
    size_t j;
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    st->initialized = 0;
    for (p = 0U; p < 3U; ++p) {
        if (!GG_ISFINITE(cfg->half_base_m[p]) || !(cfg->half_base_m[p] > 0.0L)) {
            return GG_ERR_CONFIG;
        }
    }
    if (!GG_ISFINITE(cfg->parity_f_max) || (cfg->parity_f_max < 0.0) || (cfg->stabilized < 0) ||
        (cfg->stabilized > 1)) {
        return GG_ERR_CONFIG;
    }
    st->cfg = *cfg;
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            st->mean_good[p][j] = 0.0L;
        }
    }
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            st->m_good[j][p] = 0.0L;
            st->m_prior[j][p] = 0.0L;
        }
    }
    st->have_prior = 0;
    st->excluded = 0U;
    st->excluded_pairs = 0U;
    st->have_good = 0;
    st->initialized = 1;
    return GG_OK;
}

/* The angular acceleration the antisymmetric part must show: 0 on a
 * stabilized platform, the reference otherwise; 0 (unknown) without one. */
static int wd_known(const gg_fdi3d_t *st, const gg_real_t wd_ref[3], gg_real_t wd[3])
{
    int known = 0;
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        wd[j] = 0.0L;
    }
    if (st->cfg.stabilized != 0) {
        known = 1;
    } else if (wd_ref != NULL) {
        for (j = 0U; j < 3U; ++j) {
            wd[j] = wd_ref[j];
        }
        known = 1;
    } else {
        /* unknown */
    }
    return known;
}

/* Rebuild the readings of bad (single per pair-axis) and of the excluded
 * pair-axes in nf/nlo (copies of the frame's readings). */
static gg_status_t accommodate(const gg_fdi3d_t *st, uint32_t bad, uint32_t pairs,
                               const gg_real_t w[3], const gg_real_t wd[3], int wd_ok,
                               double nf[6][3], double nlo[6][3], uint32_t *rebuilt)
{
    gg_real_t mean_p[3][3];
    uint32_t rb = 0U;
    size_t p;
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        int n_whole = 0;
        gg_real_t sum_whole = 0.0L;
        gg_real_t sum_good_whole = 0.0L;
        for (p = 0U; p < 3U; ++p) {
            const uint32_t b0 = bad & rbit(p, j);
            const uint32_t b1 = bad & rbit(p + 3U, j);
            const uint32_t bp = pairs & rbit(p, j);
            if ((bp == 0U) && (b0 != 0U) && (b1 != 0U)) {
                return GG_ERR_SENSOR; /* both readings of a pair on this axis */
            }
            if ((bp == 0U) && (b0 == 0U) && (b1 == 0U)) {
                sum_whole += 0.5L * (rd3(nf, nlo, p, j) + rd3(nf, nlo, p + 3U, j));
                sum_good_whole += st->mean_good[p][j];
                n_whole += 1;
            }
        }
        for (p = 0U; p < 3U; ++p) {
            const uint32_t b0 = bad & rbit(p, j);
            const uint32_t b1 = bad & rbit(p + 3U, j);
            const uint32_t bp = pairs & rbit(p, j);
            if ((bp != 0U) || (b0 != 0U) || (b1 != 0U)) {
                if (n_whole == 0) {
                    return GG_ERR_SENSOR; /* no whole pair on this axis */
                }
                /* mean over the whole pairs q of m_q + (m_p - m_q)_last */
                mean_p[p][j] =
                    (sum_whole + (((gg_real_t)n_whole * st->mean_good[p][j]) - sum_good_whole)) /
                    (gg_real_t)n_whole;
            }
            if ((bp == 0U) && ((b0 != 0U) || (b1 != 0U))) {
                size_t bad_s = p + 3U;
                size_t partner = p;
                if (b0 != 0U) {
                    bad_s = p;
                    partner = p + 3U;
                }
                wr3(nf, nlo, bad_s, j, (2.0L * mean_p[p][j]) - rd3(nf, nlo, partner, j));
                rb |= rbit(bad_s, j);
            }
        }
    }
    /* excluded pair-axes: the column entry from symmetry or the trace */
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            if ((pairs & rbit(p, j)) != 0U) {
                gg_real_t mjp;
                if (j == p) {
                    /* trace of Gamma = -2|w|^2 - tr M = 0 */
                    size_t k;
                    mjp = -2.0L * ((w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]));
                    for (k = 0U; k < 3U; ++k) {
                        if (k != p) {
                            if ((pairs & rbit(k, k)) != 0U) {
                                return GG_ERR_SENSOR;
                            }
                            mjp -= m_entry(st, nf, nlo, k, k);
                        }
                    }
                } else {
                    /* (M - M^T)/2 = [w' x] */
                    if ((wd_ok == 0) || ((pairs & rbit(j, p)) != 0U)) {
                        return GG_ERR_SENSOR;
                    }
                    mjp = m_entry(st, nf, nlo, p, j) + (2.0L * cross_entry(wd, j, p));
                }
                wr3(nf, nlo, p, j, mean_p[p][j] + (st->cfg.half_base_m[p] * mjp));
                wr3(nf, nlo, p + 3U, j, mean_p[p][j] - (st->cfg.half_base_m[p] * mjp));
                rb |= rbit(p, j) | rbit(p + 3U, j);
            }
        }
    }
    *rebuilt = rb;
    return GG_OK;
}

/* What a degraded rebuild knows: pair means mean[p][j], column entries
 * m[j][p] (bits rbit(p, j) in km / kM). */
typedef struct {
    gg_real_t mean[3][3];
    gg_real_t m[3][3];
    uint32_t km;
    uint32_t kM;
    uint32_t held_m;     /* column entries held (or from the prior), bit rbit(p, j) */
    uint32_t held_force; /* axes whose centre force is held, bit j */
} solve_t;

/* reading s of axis j usable in the degraded rebuild */
static int usable(uint32_t unus, size_t s, size_t j)
{
    int u = 0;
    if ((unus & rbit(s, j)) == 0U) {
        u = 1;
    }
    return u;
}

/* readings of the pair-axes in pairs, as reading bits */
static uint32_t pair_readings(uint32_t pairs)
{
    uint32_t r = 0U;
    size_t p;
    size_t j;
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            if ((pairs & rbit(p, j)) != 0U) {
                r |= rbit(p, j) | rbit(p + 3U, j);
            }
        }
    }
    return r;
}

/* One pass of the rules: an axis with a known pair mean gives the others
 * (keeping the last curvature differences); a pair with one usable reading
 * gives its mean from its column entry or the entry from its mean; the
 * symmetry (M - M^T)/2 = [w' x] gives an entry from its mirror; the trace
 * (-2|w|^2 - tr M = 0) the last diagonal entry. 1 when anything was learnt. */
static int solve_pass(const gg_fdi3d_t *st, solve_t *sv, uint32_t unus, const gg_real_t w[3],
                      const gg_real_t wd[3], int wd_ok, double nf[6][3], double nlo[6][3])
{
    int learnt = 0;
    size_t p;
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        int n = 0;
        gg_real_t sum = 0.0L;
        gg_real_t sum_good = 0.0L;
        for (p = 0U; p < 3U; ++p) {
            if ((sv->km & rbit(p, j)) != 0U) {
                sum += sv->mean[p][j];
                sum_good += st->mean_good[p][j];
                n += 1;
            }
        }
        for (p = 0U; (p < 3U) && (n > 0); ++p) {
            if ((sv->km & rbit(p, j)) == 0U) {
                sv->mean[p][j] =
                    (sum + (((gg_real_t)n * st->mean_good[p][j]) - sum_good)) / (gg_real_t)n;
                sv->km |= rbit(p, j);
                learnt = 1;
            }
        }
    }
    for (p = 0U; p < 3U; ++p) {
        const gg_real_t h = st->cfg.half_base_m[p];
        for (j = 0U; j < 3U; ++j) {
            const int u0 = usable(unus, p, j);
            const int u1 = usable(unus, p + 3U, j);
            if ((u0 + u1) == 1) {
                size_t s = p + 3U;
                gg_real_t sg = -1.0L;
                if (u0 != 0) {
                    s = p;
                    sg = 1.0L;
                }
                /* f_s = mean + sg h M[j][p] */
                if (((sv->km & rbit(p, j)) != 0U) && ((sv->kM & rbit(p, j)) == 0U)) {
                    sv->m[j][p] = sg * (rd3(nf, nlo, s, j) - sv->mean[p][j]) / h;
                    sv->kM |= rbit(p, j);
                    learnt = 1;
                } else if (((sv->kM & rbit(p, j)) != 0U) && ((sv->km & rbit(p, j)) == 0U)) {
                    sv->mean[p][j] = rd3(nf, nlo, s, j) - (sg * h * sv->m[j][p]);
                    sv->km |= rbit(p, j);
                    learnt = 1;
                } else {
                    /* nothing to learn from it yet */
                }
            }
        }
    }
    for (p = 0U; (p < 3U) && (wd_ok != 0); ++p) {
        for (j = 0U; j < 3U; ++j) {
            /* M[j][p] = M[p][j] + 2 [w' x][j][p]; M[p][j] is bit rbit(j, p) */
            if ((j != p) && ((sv->kM & rbit(p, j)) == 0U) && ((sv->kM & rbit(j, p)) != 0U)) {
                sv->m[j][p] = sv->m[p][j] + (2.0L * cross_entry(wd, j, p));
                sv->kM |= rbit(p, j);
                learnt = 1;
            }
        }
    }
    {
        int n_unknown = 0;
        size_t last = 0U;
        gg_real_t t = -2.0L * ((w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]));
        for (p = 0U; p < 3U; ++p) {
            if ((sv->kM & rbit(p, p)) == 0U) {
                n_unknown += 1;
                last = p;
            } else {
                t -= sv->m[p][p];
            }
        }
        if (n_unknown == 1) {
            sv->m[last][last] = t;
            sv->kM |= rbit(last, last);
            learnt = 1;
        }
    }
    return learnt;
}

static void solve_fix(const gg_fdi3d_t *st, solve_t *sv, uint32_t unus, const gg_real_t w[3],
                      const gg_real_t wd[3], int wd_ok, double nf[6][3], double nlo[6][3])
{
    int pass;
    for (pass = 0; pass < 24; ++pass) {
        if (solve_pass(st, sv, unus, w, wd, wd_ok, nf, nlo) == 0) {
            break;
        }
    }
}

/* the value a column entry holds: the prior (onboard model) when one is set,
 * else the last frame used */
static gg_real_t held_entry(const gg_fdi3d_t *st, size_t j, size_t p)
{
    gg_real_t v = st->m_good[j][p];
    if (st->have_prior != 0) {
        v = st->m_prior[j][p];
    }
    return v;
}

/* One last resort when the rules are stuck (1 if one was taken): an axis
 * with no pair mean but a usable reading holds that pair's column entry;
 * an axis with no usable reading at all holds its centre force; otherwise
 * the first unknown column entry is held. */
static int solve_hold(const gg_fdi3d_t *st, solve_t *sv, uint32_t unus)
{
    size_t p;
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        if ((sv->km & (rbit(0U, j) | rbit(1U, j) | rbit(2U, j))) == 0U) {
            for (p = 0U; p < 3U; ++p) {
                if (((usable(unus, p, j) + usable(unus, p + 3U, j)) > 0) &&
                    ((sv->kM & rbit(p, j)) == 0U)) {
                    sv->m[j][p] = held_entry(st, j, p);
                    sv->kM |= rbit(p, j);
                    sv->held_m |= rbit(p, j);
                    return 1;
                }
            }
            for (p = 0U; p < 3U; ++p) {
                sv->mean[p][j] = st->mean_good[p][j];
                sv->km |= rbit(p, j);
            }
            sv->held_force |= (uint32_t)1U << j;
            return 1;
        }
    }
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            if ((sv->kM & rbit(p, j)) == 0U) {
                sv->m[j][p] = held_entry(st, j, p);
                sv->kM |= rbit(p, j);
                sv->held_m |= rbit(p, j);
                return 1;
            }
        }
    }
    return 0;
}

/* Degraded rebuild: when readings are lost beyond what one per pair-axis
 * rebuilds (both of a pair, every pair of an axis touched, excluded
 * pair-axes whose symmetry or trace partner is lost too, readings set aside
 * for a fault no single reading fits). Each pair mean and column entry M[j][p]
 * comes from what is left - a whole pair, a single reading with the other
 * one known, the axis' other pair means, symmetry, trace - else it is held
 * (an axis without any usable reading: its centre force; a column entry:
 * its last value, or the prior); the unusable readings are then synthesised
 * f_p = mean + h_p M[j][p], f_p+3 = mean - h_p M[j][p]. */
static void degrade(const gg_fdi3d_t *st, uint32_t unus, const gg_real_t w[3],
                    const gg_real_t wd[3], int wd_ok, double nf[6][3], double nlo[6][3],
                    uint32_t *rebuilt, uint32_t *held_m, uint32_t *held_force)
{
    solve_t sv;
    uint32_t rb = 0U;
    size_t p;
    size_t j;
    int round;
    sv.km = 0U;
    sv.kM = 0U;
    sv.held_m = 0U;
    sv.held_force = 0U;
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            sv.mean[p][j] = 0.0L;
            sv.m[j][p] = 0.0L;
            if ((usable(unus, p, j) != 0) && (usable(unus, p + 3U, j) != 0)) {
                sv.mean[p][j] = 0.5L * (rd3(nf, nlo, p, j) + rd3(nf, nlo, p + 3U, j));
                sv.m[j][p] = m_entry(st, nf, nlo, j, p);
                sv.km |= rbit(p, j);
                sv.kM |= rbit(p, j);
            }
        }
    }
    for (round = 0; round < 16; ++round) {
        solve_fix(st, &sv, unus, w, wd, wd_ok, nf, nlo);
        if (solve_hold(st, &sv, unus) == 0) {
            break;
        }
    }
    for (p = 0U; p < 3U; ++p) {
        const gg_real_t h = st->cfg.half_base_m[p];
        for (j = 0U; j < 3U; ++j) {
            if (usable(unus, p, j) == 0) {
                wr3(nf, nlo, p, j, sv.mean[p][j] + (h * sv.m[j][p]));
                rb |= rbit(p, j);
            }
            if (usable(unus, p + 3U, j) == 0) {
                wr3(nf, nlo, p + 3U, j, sv.mean[p][j] - (h * sv.m[j][p]));
                rb |= rbit(p + 3U, j);
            }
        }
    }
    *rebuilt = rb;
    *held_m = sv.held_m;
    *held_force = sv.held_force;
}

/* The readings of axis j set aside as suspects whose pair agrees, reading
 * against reading, with its column entry from symmetry or trace of the
 * usable readings of the other axes (|2 h_p (M[j][p] - M_sym)| <= tau: one
 * faulty reading of a pair moves it by its whole size), and whose mean
 * agrees with the other such pairs': given back (two faulty pairs on one
 * axis leave the third). */
static uint32_t rescue(const gg_fdi3d_t *st, uint32_t unus, uint32_t aside, size_t j,
                       const gg_real_t w[3], const gg_real_t wd[3], int wd_ok, double f[6][3],
                       double f_lo[6][3])
{
    const gg_real_t tau = (gg_real_t)st->cfg.parity_f_max;
    uint32_t back = 0U;
    gg_real_t mu[3] = {0.0L, 0.0L, 0.0L};
    int n_ok = 0;
    size_t p;
    for (p = 0U; p < 3U; ++p) {
        const uint32_t both = rbit(p, j) | rbit(p + 3U, j);
        gg_real_t msym = 0.0L;
        int known = 0;
        if (((aside & both) == both) && ((unus & both) == 0U)) {
            if (p != j) {
                if ((wd_ok != 0) && (usable(unus | aside, j, p) != 0) &&
                    (usable(unus | aside, j + 3U, p) != 0)) {
                    msym = m_entry(st, f, f_lo, p, j) + (2.0L * cross_entry(wd, j, p));
                    known = 1;
                }
            } else {
                size_t k;
                known = 1;
                msym = -2.0L * ((w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]));
                for (k = 0U; k < 3U; ++k) {
                    if (k != p) {
                        if ((usable(unus | aside, k, k) == 0) ||
                            (usable(unus | aside, k + 3U, k) == 0)) {
                            known = 0;
                        }
                        msym -= m_entry(st, f, f_lo, k, k);
                    }
                }
            }
        }
        if ((known != 0) &&
            (absr(2.0L * st->cfg.half_base_m[p] * (m_entry(st, f, f_lo, j, p) - msym)) <= tau)) {
            const gg_real_t m_p = 0.5L * (rd3(f, f_lo, p, j) + rd3(f, f_lo, p + 3U, j));
            size_t q;
            int agree = 1;
            for (q = 0U; q < p; ++q) {
                if ((back & rbit(q, j)) != 0U) {
                    /* as detect compares them */
                    if (absr(m_p - mu[q]) > tau) {
                        agree = 0;
                    }
                }
            }
            if (agree == 0) {
                return 0U;
            }
            mu[p] = m_p;
            back |= rbit(p, j);
            n_ok += 1;
        }
    }
    if (n_ok == 0) {
        return 0U;
    }
    {
        uint32_t r = 0U;
        for (p = 0U; p < 3U; ++p) {
            if ((back & rbit(p, j)) != 0U) {
                r |= rbit(p, j) | rbit(p + 3U, j);
            }
        }
        return r;
    }
}

/* Detection and isolation on the whole pairs; new exclusions into *new_bad,
 * *new_pairs. GG_ERR_SENSOR on a fault that fits no single reading or pair. */
static gg_status_t detect(const gg_fdi3d_t *st, uint32_t bad, uint32_t pairs, const gg_real_t w[3],
                          const gg_real_t wd[3], int wd_ok, double nf[6][3], double nlo[6][3],
                          uint32_t *new_bad, uint32_t *new_pairs, gg_real_t *pmax,
                          uint32_t *flags, gg_real_t expect_out[3][3], uint32_t *suspect)
{
    const gg_real_t tau = (gg_real_t)st->cfg.parity_f_max;
    size_t j;
    size_t p;
    *pmax = 0.0L;
    for (j = 0U; j < 3U; ++j) {
        gg_real_t mu[3] = {0.0L, 0.0L, 0.0L};
        int whole[3] = {0, 0, 0};
        int n_whole = 0;
        gg_real_t worst = 0.0L;
        for (p = 0U; p < 3U; ++p) {
            if (((bad & (rbit(p, j) | rbit(p + 3U, j))) == 0U) && ((pairs & rbit(p, j)) == 0U)) {
                mu[p] = 0.5L * (rd3(nf, nlo, p, j) + rd3(nf, nlo, p + 3U, j));
                whole[p] = 1;
                n_whole += 1;
            }
        }
        for (p = 0U; p < 3U; ++p) {
            size_t q;
            for (q = p + 1U; q < 3U; ++q) {
                if ((whole[p] != 0) && (whole[q] != 0) && (absr(mu[p] - mu[q]) > worst)) {
                    worst = absr(mu[p] - mu[q]);
                }
            }
        }
        if (worst > *pmax) {
            *pmax = worst;
        }
        if ((tau > 0.0L) && (worst > tau)) {
            size_t fp = 0U;
            gg_real_t dev = -1.0L;
            gg_real_t d;
            size_t sensor = 6U;
            *flags |= GG_FDI3D_DETECTED;
            if (n_whole < 3) {
                /* detected, nothing left to isolate with: the compared pairs are suspect */
                for (p = 0U; p < 3U; ++p) {
                    if (whole[p] != 0) {
                        *suspect |= rbit(p, j) | rbit(p + 3U, j);
                    }
                }
                return GG_ERR_SENSOR;
            }
            for (p = 0U; p < 3U; ++p) {
                const gg_real_t others = 0.5L * ((mu[0] + mu[1] + mu[2]) - mu[p]);
                if (absr(mu[p] - others) > dev) {
                    dev = absr(mu[p] - others);
                    fp = p;
                }
            }
            {
                const size_t q = (fp + 1U) % 3U;
                const size_t r = (fp + 2U) % 3U;
                if (absr(mu[q] - mu[r]) > tau) {
                    /* the other two disagree: a double fault; the whole axis is suspect */
                    for (p = 0U; p < 3U; ++p) {
                        *suspect |= rbit(p, j) | rbit(p + 3U, j);
                    }
                    return GG_ERR_SENSOR;
                }
                d = 2.0L * (mu[fp] - (0.5L * (mu[q] + mu[r])));
            }
            if (j == fp) {
                /* the trace moves by -d/(2h) for sensor p, +d/(2h) for p + 3 */
                const gg_real_t expect = absr(d) / (2.0L * st->cfg.half_base_m[fp]);
                gg_real_t t = -2.0L * ((w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]));
                size_t k;
                for (k = 0U; k < 3U; ++k) {
                    t -= m_entry(st, nf, nlo, k, k);
                }
                if (absr(t) >= (0.5L * expect)) {
                    sensor = ((t * d) < 0.0L) ? fp : (fp + 3U);
                    expect_out[fp][j] = expect;
                }
            } else if (wd_ok != 0) {
                /* the antisymmetric part moves by +d/(4h) for sensor p, -d/(4h) for p + 3 */
                const gg_real_t expect = absr(d) / (4.0L * st->cfg.half_base_m[fp]);
                const gg_real_t a = (0.5L * (m_entry(st, nf, nlo, j, fp) - m_entry(st, nf, nlo, fp, j))) -
                                    cross_entry(wd, j, fp);
                if (absr(a) >= (0.5L * expect)) {
                    sensor = ((a * d) > 0.0L) ? fp : (fp + 3U);
                    expect_out[fp][j] = expect;
                }
            } else {
                /* no reference for the antisymmetric part: ambiguous */
            }
            if (sensor < 6U) {
                *new_bad |= rbit(sensor, j);
            } else {
                *new_pairs |= rbit(fp, j);
                /* marked negative: verify checks the whole tensor */
                expect_out[fp][j] = -(absr(d) / (4.0L * st->cfg.half_base_m[fp]));
            }
        }
    }
    return GG_OK;
}

/* After readings were newly isolated and rebuilt: the residual each
 * isolation read (trace for a reading along its own offset, antisymmetric
 * part otherwise) must have dropped below half the move its fault made
 * (expect, as in detect). Two faults at once whose moves add up in one
 * residual (e.g. two readings feeding the same antisymmetric entry) can
 * point the isolation at the good sensor of a pair; the residual then stays.
 * A pair-axis excluded as ambiguous (expect < 0: |d|/(4h)) may be the one
 * good pair of three when the other two carry equal faults (two stuck
 * readings of one axis): then the rebuilt tensor is no gradient - every
 * antisymmetric residual (when the reference is known) and the trace must be
 * below half that move. Either: GG_ERR_SENSOR (a double fault: the frame is
 * rejected, the task coasts). */
static gg_status_t verify(const gg_fdi3d_t *st, const gg_real_t w[3], const gg_real_t wd[3],
                          int wd_ok, double nf[6][3], double nlo[6][3], gg_real_t expect[3][3])
{
    gg_status_t res = GG_OK;
    gg_real_t pair_move = 0.0L;
    size_t p;
    size_t j;
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            if (-expect[p][j] > pair_move) {
                pair_move = -expect[p][j];
            }
        }
    }
    if (pair_move > 0.0L) {
        gg_real_t t = -2.0L * ((w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]));
        for (p = 0U; p < 3U; ++p) {
            t -= m_entry(st, nf, nlo, p, p);
            for (j = p + 1U; (j < 3U) && (wd_ok != 0); ++j) {
                const gg_real_t a = (0.5L * (m_entry(st, nf, nlo, j, p) - m_entry(st, nf, nlo, p, j))) -
                                    cross_entry(wd, j, p);
                if (absr(a) >= (0.5L * pair_move)) {
                    res = GG_ERR_SENSOR;
                }
            }
        }
        if (absr(t) >= pair_move) {
            res = GG_ERR_SENSOR;
        }
    }
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            if (expect[p][j] > 0.0L) {
                gg_real_t r;
                if (j == p) {
                    size_t k;
                    r = -2.0L * ((w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]));
                    for (k = 0U; k < 3U; ++k) {
                        r -= m_entry(st, nf, nlo, k, k);
                    }
                } else {
                    r = (0.5L * (m_entry(st, nf, nlo, j, p) - m_entry(st, nf, nlo, p, j))) -
                        cross_entry(wd, j, p);
                }
                if (absr(r) >= (0.5L * expect[p][j])) {
                    res = GG_ERR_SENSOR;
                }
            }
        }
    }
    return res;
}

/* The readings an isolation that verify refused read. A pair-axis (p, j)
 * excluded as ambiguous may be the one good pair of axis j (equal faults on
 * the other two): every reading of axis j. A reading (s, j): its pair on
 * axis j and the readings of the residual it read - the mirror pair (j on
 * axis p) for a cross-axis reading, every diagonal pair for the trace. */
static uint32_t verify_suspects(uint32_t new_bad, uint32_t new_pairs)
{
    uint32_t r = 0U;
    size_t s;
    size_t j;
    for (s = 0U; s < 3U; ++s) {
        for (j = 0U; j < 3U; ++j) {
            if ((new_pairs & rbit(s, j)) != 0U) {
                size_t q;
                for (q = 0U; q < 3U; ++q) {
                    r |= rbit(q, j) | rbit(q + 3U, j);
                }
            }
        }
    }
    for (s = 0U; s < 6U; ++s) {
        for (j = 0U; j < 3U; ++j) {
            if ((new_bad & rbit(s, j)) != 0U) {
                const size_t p = s % 3U;
                r |= rbit(p, j) | rbit(p + 3U, j);
                if (j != p) {
                    r |= rbit(j, p) | rbit(j + 3U, p);
                } else {
                    size_t k;
                    for (k = 0U; k < 3U; ++k) {
                        r |= rbit(k, k) | rbit(k + 3U, k);
                    }
                }
            }
        }
    }
    return r;
}

/* Copy the frame's readings into nf/nlo and rebuild the unusable ones: one
 * per pair-axis and excluded pair-axes as accommodate does, else the
 * degraded rebuild (GG_FDI3D_DEGRADED). */
static void rebuild_set(const gg_fdi3d_t *st, uint32_t bad, uint32_t pairs, const gg_real_t w[3],
                    const gg_real_t wd[3], int wd_ok, double f[6][3], double f_lo[6][3],
                    double nf[6][3], double nlo[6][3], gg_fdi3d_output_t *o, uint32_t *held_m,
                    uint32_t *held_force)
{
    size_t s;
    size_t j;
    for (s = 0U; s < 6U; ++s) {
        for (j = 0U; j < 3U; ++j) {
            nf[s][j] = f[s][j];
            nlo[s][j] = f_lo[s][j];
        }
    }
    *held_m = 0U;
    *held_force = 0U;
    o->flags &= ~GG_FDI3D_DEGRADED;
    if (accommodate(st, bad, pairs, w, wd, wd_ok, nf, nlo, &o->rebuilt) != GG_OK) {
        for (s = 0U; s < 6U; ++s) {
            for (j = 0U; j < 3U; ++j) {
                nf[s][j] = f[s][j];
                nlo[s][j] = f_lo[s][j];
            }
        }
        degrade(st, bad | pair_readings(pairs), w, wd, wd_ok, nf, nlo, &o->rebuilt, held_m,
                held_force);
        o->flags |= GG_FDI3D_DEGRADED;
    }
}

gg_status_t gg_fdi3d_step(gg_fdi3d_t *st, uint32_t known_bad, const gg_real_t omega_b[3],
                          const gg_real_t omega_dot_ref[3], double f[6][3], double f_lo[6][3],
                          gg_fdi3d_output_t *out)
{
    double nf[6][3];
    double nlo[6][3];
    gg_real_t wd[3];
    gg_fdi3d_output_t o;
    uint32_t bad;
    uint32_t pairs;
    uint32_t new_bad = 0U;
    uint32_t new_pairs = 0U;
    int wd_ok;
    gg_status_t status;
    uint32_t aside = 0U;
    uint32_t held_m = 0U;
    uint32_t held_force = 0U;
    int iter;
    int done = 0;
    gg_real_t expect[3][3];
    size_t s;
    size_t p;
    size_t j;
    if ((st == NULL) || (omega_b == NULL) || (f == NULL) || (f_lo == NULL) || (out == NULL)) {
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
    o.flags = 0U;
    o.rebuilt = 0U;
    o.held_m = 0U;
    o.held_force = 0U;
    o.parity_max = 0.0L;
    o.excluded = st->excluded;
    o.excluded_pairs = st->excluded_pairs;
    *out = o;
    wd_ok = wd_known(st, omega_dot_ref, wd);
    bad = known_bad | st->excluded;
    pairs = st->excluded_pairs;
    if (((bad != 0U) || (pairs != 0U)) && (st->have_good == 0)) {
        return GG_ERR_SENSOR; /* no curvature differences known yet */
    }
    status = GG_OK;
    for (iter = 0; (iter < FDI3D_MAX_ROUNDS) && (done == 0); ++iter) {
        uint32_t suspect = 0U;
        gg_status_t st_det;
        new_bad = 0U;
        new_pairs = 0U;
        for (p = 0U; p < 3U; ++p) {
            for (j = 0U; j < 3U; ++j) {
                expect[p][j] = 0.0L;
            }
        }
        rebuild_set(st, bad | aside, pairs, omega_b, wd, wd_ok, f, f_lo, nf, nlo, &o, &held_m,
                    &held_force);
        st_det = detect(st, bad | aside, pairs, omega_b, wd, wd_ok, nf, nlo, &new_bad, &new_pairs,
                        &o.parity_max, &o.flags, expect, &suspect);
        if (st_det != GG_OK) {
            /* a fault no single reading or pair explains */
            const uint32_t unus = bad | pair_readings(pairs);
            if ((st->have_good == 0) || ((suspect & ~aside) == 0U)) {
                status = GG_ERR_SENSOR;
                done = 1;
            } else {
                aside |= suspect;
                for (j = 0U; (j < 3U) && (iter < FDI3D_RESCUE_ROUNDS); ++j) {
                    aside &= ~rescue(st, unus, aside, j, omega_b, wd, wd_ok, f, f_lo);
                }
                o.flags |= GG_FDI3D_SUSPECT;
            }
        } else if ((new_bad != 0U) || (new_pairs != 0U)) {
            if (st->have_good == 0) {
                status = GG_ERR_SENSOR;
                done = 1;
            } else {
                /* start again from the frame's readings with the new exclusions */
                rebuild_set(st, bad | aside | new_bad, pairs | new_pairs, omega_b, wd, wd_ok, f,
                            f_lo, nf, nlo, &o, &held_m, &held_force);
                if (verify(st, omega_b, wd, wd_ok, nf, nlo, expect) != GG_OK) {
                    /* the isolation did not explain the residual (two faults):
                     * set aside what it read instead of excluding anything */
                    const uint32_t vs = verify_suspects(new_bad, new_pairs);
                    if ((vs & ~aside) == 0U) {
                        status = GG_ERR_SENSOR;
                        done = 1;
                    } else {
                        aside |= vs;
                        for (j = 0U; (j < 3U) && (iter < FDI3D_RESCUE_ROUNDS); ++j) {
                            aside &= ~rescue(st, bad | pair_readings(pairs), aside, j, omega_b,
                                             wd, wd_ok, f, f_lo);
                        }
                        o.flags |= GG_FDI3D_SUSPECT;
                    }
                    new_bad = 0U;
                    new_pairs = 0U;
                } else {
                    o.flags |= GG_FDI3D_NEW_EXCL;
                    done = 1;
                }
            }
        } else {
            done = 1;
        }
    }
    if (done == 0) {
        status = GG_ERR_SENSOR; /* not reached: each round sets more readings aside */
    }
    if (status != GG_OK) {
        /* what the checks saw, for the health word; nothing else changes */
        o.rebuilt = 0U;
        o.held_m = 0U;
        o.held_force = 0U;
        o.flags &= ~(GG_FDI3D_DEGRADED | GG_FDI3D_REBUILT);
        o.excluded = st->excluded;
        o.excluded_pairs = st->excluded_pairs;
        *out = o;
        return status;
    }
    for (p = 0U; p < 3U; ++p) {
        for (j = 0U; j < 3U; ++j) {
            st->mean_good[p][j] = 0.5L * (rd3(nf, nlo, p, j) + rd3(nf, nlo, p + 3U, j));
            st->m_good[j][p] = m_entry(st, nf, nlo, j, p);
        }
    }
    st->excluded |= new_bad;
    st->excluded_pairs |= new_pairs;
    st->have_good = 1;
    for (s = 0U; s < 6U; ++s) {
        for (j = 0U; j < 3U; ++j) {
            f[s][j] = nf[s][j];
            f_lo[s][j] = nlo[s][j];
        }
    }
    if (o.rebuilt != 0U) {
        o.flags |= GG_FDI3D_REBUILT;
    }
    if (st->excluded_pairs != 0U) {
        o.flags |= GG_FDI3D_PAIR;
    }
    o.held_m = held_m;
    o.held_force = held_force;
    if (held_m != 0U) {
        o.flags |= GG_FDI3D_HOLD_GRAD;
    }
    if (held_force != 0U) {
        o.flags |= GG_FDI3D_HOLD_FORCE;
    }
    o.excluded = st->excluded;
    o.excluded_pairs = st->excluded_pairs;
    *out = o;
    return GG_OK;
}

gg_status_t gg_fdi3d_set_prior(gg_fdi3d_t *st, gg_real_t m_prior[3][3])
{
    size_t p;
    size_t j;
    if (st == NULL) {
        return GG_ERR_NULL;
    }
    if (m_prior == NULL) {
        st->have_prior = 0;
        return GG_OK;
    }
    for (j = 0U; j < 3U; ++j) {
        for (p = 0U; p < 3U; ++p) {
            if (!GG_ISFINITE(m_prior[j][p])) {
                return GG_ERR_NONFINITE;
            }
        }
    }
    for (j = 0U; j < 3U; ++j) {
        for (p = 0U; p < 3U; ++p) {
            st->m_prior[j][p] = m_prior[j][p];
        }
    }
    st->have_prior = 1;
    return GG_OK;
}
