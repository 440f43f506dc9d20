/* The cold-atom particle filter as an aiding source of the 3-D task
 * (aid_pf.h), against independent truth:
 *  - closed loop through the task: an eastbound flight (closed-form truth,
 *    truth3.h) that starts 60 m south of the truth, over a map whose Gamma_zz
 *    is linear in latitude; no process noise and no resampling, so the sum of
 *    the corrections fed back into the state must be the posterior mean of
 *    the north error given the shots, computed on a grid with brute-force
 *    ellipse distances (libm), and the state must have moved by exactly that
 *    sum; the unobserved east keeps its prior; the correction leaves the
 *    Earth-relative velocity as it was, and with the velocity fed back too it
 *    moves by exactly the filter's velocity correction;
 *  - the schedule: a shot takes 1 + ceil(N / chunk) + ceil(passes / end_chunk)
 *    steps, a shot arriving while one is in progress waits, a third is dropped;
 *  - bad input: a NaN pair is a failed shot (the filter predicted only, bit
 *    for bit as the bare filter), a bad INS solution leaves the aid untouched,
 *    a shot without a tile is predicted only and flagged. */
#include "test_common.h"
#include "truth3.h"
#include "ggins/aid_pf.h"
#include "ggins/gmap.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define DT_US 10000
#define N_PART 200
#define SIG_LIKE 0.01
#define AMP 0.25 /* contrast 0.5 */
#define DN0 60.0 /* the start is this far south of the truth, m (true - estimate = +60 m north) */
#define GE_M 3.0e-9 /* Gamma_zz change per metre north, s^-2/m */
#define G0_S2 3.08e-6
#define N_SHOTS 10

static gg_gmap_tile_t g_tile;
static gg_gmap_t g_map;
static gg_nav3d_t g_nav;
static gg_nav3d_t g_ref;
static gg_aid_pf_t g_aid;
static gg_aid_pf_t g_aid2;
static gg_pf_t g_bare;

static long double rm_of(long double lat, long double h)
{
    const long double e2 = F_WGS * (2.0L - F_WGS), s = sinl(lat), w2 = 1.0L - e2 * s * s;
    return A_WGS * (1.0L - e2) / (w2 * sqrtl(w2)) + h;
}

static void flight_truth(truth3_t *T)
{
    memset(T, 0, sizeof *T);
    T->lat0 = 0.7L;
    T->lon0 = 0.2L;
    T->h0 = 3000.0L;
    for (int j = 0; j < 3; ++j) {
        T->hb[j] = 0.5L;
        T->c0[j][j] = 1.0L;
    }
    const long double e2 = F_WGS * (2.0L - F_WGS);
    const long double n = A_WGS / sqrtl(1.0L - e2 * sinl(T->lat0) * sinl(T->lat0));
    T->lon_rate = 100.0L / ((n + T->h0) * cosl(T->lat0)); /* 100 m/s east */
}

/* Gamma_zz = G0 + ge (lat - lat0) R_M: linear, so the bicubic tile is exact. */
static void build_map_ge(const truth3_t *T, double ge)
{
    const double rm = (double)rm_of(T->lat0, T->h0);
    memset(&g_tile, 0, sizeof g_tile);
    g_tile.nlat = 40;
    g_tile.nlon = 60;
    g_tile.dlat_rad = 2.0e-5;
    g_tile.dlon_rad = 5.0e-5;
    g_tile.lat0_rad = (double)T->lat0 - 19.5 * g_tile.dlat_rad;
    g_tile.lon0_rad = (double)T->lon0 - 10.0 * g_tile.dlon_rad;
    g_tile.h0_m = (double)T->h0;
    g_tile.h_range_m = 500.0;
    for (int i = 0; i < g_tile.nlat; ++i)
        for (int j = 0; j < g_tile.nlon; ++j) {
            const double lat = g_tile.lat0_rad + i * g_tile.dlat_rad;
            g_tile.node[i * g_tile.nlon + j][GG_GMAP_C_DD] = G0_S2 + ge * (lat - (double)T->lat0) * rm;
        }
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
}
static void build_map(const truth3_t *T) { build_map_ge(T, GE_M); }

typedef struct {
    const gg_gmap_t *map;
    int calls;
} store_t;

static gg_status_t store_tile_at(void *ctx, uint32_t kind, double lat, double lon, double h, const gg_gmap_t **tile)
{
    (void)h;
    store_t *s = (store_t *)ctx;
    const gg_gmap_tile_t *t = &s->map->tile;
    s->calls++;
    if (kind != GG_GMAP_KIND_GZZ) return GG_ERR_RANGE; /* the aid asks for the tiles of its kind */
    if (lat < t->lat0_rad || lat > t->lat0_rad + (t->nlat - 1) * t->dlat_rad || lon < t->lon0_rad ||
        lon > t->lon0_rad + (t->nlon - 1) * t->dlon_rad)
        return GG_ERR_RANGE;
    *tile = s->map;
    return GG_OK;
}

static uint64_t g_rng = 0x9E3779B97F4A7C15ull;
static double urand(void)
{
    g_rng ^= g_rng >> 12;
    g_rng ^= g_rng << 25;
    g_rng ^= g_rng >> 27;
    return ((double)((g_rng * 2685821657736338717ull) >> 11) + 0.5) / 9007199254740992.0;
}
static double nrand(void)
{
    const double u1 = urand(), u2 = urand();
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

static double scale_of(void) { return 4 * M_PI / 852.347e-9 * 1.0 * 0.16 * 0.16; }

/* a pair of the gradiometer at Gamma_zz g: uniform laser phase, noise per signal */
static void make_pair(double g, double s[2])
{
    const double t = 2 * M_PI * urand(), dphi = scale_of() * g;
    s[0] = 0.5 - AMP * cos(t) + 0.5 * SIG_LIKE * nrand();
    s[1] = 0.5 - AMP * cos(t + dphi) + 0.5 * SIG_LIKE * nrand();
}

/* brute force: dense sampling of the parameter, then golden-section refinement */
static double brute_dist(double s0, double s1, double dphi)
{
    const int m = 1000;
    double best = 1e300, bt = 0;
    for (int i = 0; i < m; ++i) {
        const double t = 2 * M_PI * i / m;
        const double dx = s0 - (0.5 - AMP * cos(t)), dy = s1 - (0.5 - AMP * cos(t + dphi));
        if (dx * dx + dy * dy < best) { best = dx * dx + dy * dy; bt = t; }
    }
    double lo = bt - 2 * M_PI / m, hi = bt + 2 * M_PI / m;
    for (int it = 0; it < 60; ++it) {
        const double a = lo + 0.382 * (hi - lo), b = lo + 0.618 * (hi - lo);
        const double fa = pow(s0 - (0.5 - AMP * cos(a)), 2) + pow(s1 - (0.5 - AMP * cos(a + dphi)), 2);
        const double fb = pow(s0 - (0.5 - AMP * cos(b)), 2) + pow(s1 - (0.5 - AMP * cos(b + dphi)), 2);
        if (fa < fb) hi = b; else lo = a;
    }
    const double t = 0.5 * (lo + hi);
    return hypot(s0 - (0.5 - AMP * cos(t)), s1 - (0.5 - AMP * cos(t + dphi)));
}

static void pf_config(gg_aid_pf_config_t *a, uint64_t seed)
{
    memset(a, 0, sizeof *a);
    a->enable = 1;
    a->chunk = 50;
    a->end_chunk = 100;
    gg_pf_config_t *c = &a->pf;
    c->n = N_PART;
    c->seed = seed;
    c->k_eff = 4 * M_PI / 852.347e-9;
    c->T = 0.16;
    c->dz = 1.0;
    c->contrast = 0.5;
    c->c0 = 0.5;
    c->c1 = 0.5;
    c->sigma = SIG_LIKE;
    c->sigma0_pos = 100.0;
    c->model = GG_PF_MODEL_RW; /* no process noise: a static problem */
    c->dt = 1.0;
    c->gain = 1.0;
    c->ess_frac = 0.0; /* no resampling: the weighted particles are importance samples */
}

typedef struct {
    double corr_n, corr_e;       /* sum of the corrections fed back, m */
    double spread_n, spread_e;   /* the cloud after the last shot */
    double ess;
    double err_n_end;            /* truth - state, north, after the last correction, m */
    double dv_applied;           /* largest velocity correction component applied, m/s */
    double dv_jump;              /* largest change of the Earth-relative velocity (ECEF axes) at a correction step beyond the reference's, m/s */
    double s[N_SHOTS][2];        /* the shots */
    double e_ins[N_SHOTS];       /* open-loop north position of the INS relative to the truth at each shot, m */
    int steps_to_corr;           /* steps from the first shot to its correction */
    uint32_t dropped, updates, shots;
} pf_flight_t;

static void north_east_err(const truth3_t *T, long long k, const gg_nav3d_output_t *o, double *en, double *ee)
{
    const long double t = (long double)k * DT_US * 1e-6L;
    const long double lon_t = T->lon0 + T->lon_rate * t;
    const long double h = T->h0;
    const long double e2 = F_WGS * (2.0L - F_WGS);
    const long double rn = A_WGS / sqrtl(1.0L - e2 * sinl(T->lat0) * sinl(T->lat0)) + h;
    *en = (double)((T->lat0 - (long double)o->lat_rad) * rm_of(T->lat0, h));
    *ee = (double)((lon_t - (long double)o->lon_rad) * rn * cosl(T->lat0));
}

static pf_flight_t fly(uint64_t seed, int feed_vel)
{
    truth3_t T;
    gg_nav3d_config_t cfg, cref;
    gg_nav3d_output_t out, oref, prev = {0}, prevref = {0};
    gg_frame_t fr;
    store_t store = {&g_map, 0};
    gg_hal_map_t hm = {&store, store_tile_at};
    gg_hal_t hal;
    pf_flight_t f;
    memset(&f, 0, sizeof f);
    flight_truth(&T);
    make_config(&T, GG_PLATFORM_STABILIZED, 0, DT_US, &cfg);
    {
        /* start DN0 south: r0 -= DN0 * north */
        const long double sl = sinl(T.lat0), cl = cosl(T.lat0), so = sinl(T.lon0), co = cosl(T.lon0);
        const long double nrow[3] = {-sl * co, -sl * so, cl};
        for (int j = 0; j < 3; ++j) cfg.r0_e[j] -= (gg_real_t)(DN0 * nrow[j]);
    }
    cref = cfg;
    pf_config(&cfg.aid_pf, seed);
    if (feed_vel != 0) { /* velocity corrections too: a velocity spread to correct */
        cfg.aid_pf.feedback = GG_AID_PF_FB_POS_VEL;
        cfg.aid_pf.pf.sigma0_vel = 0.1;
    }
    assert_int_equal(gg_nav3d_init(&g_nav, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_init(&g_ref, &cref), GG_OK);
    memset(&hal, 0, sizeof hal);
    hal.map = &hm;
    int shot = 0, k_first = -1;
    double a_sum = 0.0; /* corrections applied so far (north) */
    const long long n_steps = 100LL * N_SHOTS + 100;
    for (long long k = 0; k <= n_steps; ++k) {
        make_frame(&T, k, DT_US, &fr);
        fr.ca_status = GG_SENSOR_ABSENT;
        if (k >= 100 && (k % 100) == 0 && shot < N_SHOTS) {
            make_pair(G0_S2, f.s[shot]); /* the truth flies along lat0 */
            fr.ca_s[0] = f.s[shot][0];
            fr.ca_s[1] = f.s[shot][1];
            fr.ca_utime = fr.utime;
            fr.ca_status = GG_SENSOR_OK;
        }
        assert_int_equal(gg_nav3d_step(&g_nav, &fr, &hal, &out), GG_OK);
        assert_int_equal(gg_nav3d_step(&g_ref, &fr, NULL, &oref), GG_OK);
        assert_true((out.health & (GG_HEALTH_PF_FAIL | GG_HEALTH_PF_SHOT_INVALID)) == 0U);
        if (fr.ca_status == GG_SENSOR_OK) {
            double en, ee;
            north_east_err(&T, k, &out, &en, &ee);
            f.e_ins[shot] = -en - a_sum; /* INS - truth, open loop */
            if (k_first < 0) k_first = (int)k;
            ++shot;
        }
        if (out.pf_corrected != 0) {
            if (f.steps_to_corr == 0) f.steps_to_corr = (int)k - k_first;
            a_sum += out.pf_corr_m[0];
            /* the Earth-relative velocity moves by the velocity correction (ECEF axes), nothing else */
            const double sl = sin(out.lat_rad), cl = cos(out.lat_rad), so = sin(out.lon_rad), co = cos(out.lon_rad);
            const double nrow[3] = {-sl * co, -sl * so, cl}, erow[3] = {-so, co, 0.0};
            const double dvn = g_nav.aid_pf.last.mean[2] * (feed_vel != 0 ? 1.0 : 0.0);
            const double dve = g_nav.aid_pf.last.mean[3] * (feed_vel != 0 ? 1.0 : 0.0);
            for (int j = 0; j < 3; ++j) {
                const double want = dvn * nrow[j] + dve * erow[j];
                const double jump = fabs((out.v_e[j] - prev.v_e[j]) - (oref.v_e[j] - prevref.v_e[j]) - want);
                if (jump > f.dv_jump) f.dv_jump = jump;
                if (fabs(want) > f.dv_applied) f.dv_applied = fabs(want);
            }
        }
        prev = out;
        prevref = oref;
    }
    double en, ee;
    north_east_err(&T, n_steps, &out, &en, &ee);
    f.err_n_end = en;
    f.corr_n = g_nav.aid_pf.corr_total_m[0];
    f.corr_e = g_nav.aid_pf.corr_total_m[1];
    f.spread_n = out.pf_spread_m[0];
    f.spread_e = out.pf_spread_m[1];
    f.ess = out.pf_ess;
    f.dropped = out.pf_dropped;
    f.updates = out.pf_updates;
    f.shots = out.pf_shots;
    assert_true(fabs(a_sum - f.corr_n) < 1e-9);
    assert_true(store.calls >= N_SHOTS);
    return f;
}

/* Posterior of the total north correction C (true - open-loop INS) on a grid:
 * prior N(0, 100^2), shot k at the candidate's Gamma_zz G0 + GE (e_k + C). */
static void grid_posterior(const pf_flight_t *f, double *mean, double *sd)
{
    enum { NG = 801 };
    static double lp[NG];
    double lmax = -1e300;
    for (int i = 0; i < NG; ++i) {
        const double c = -400.0 + 1.0 * i;
        lp[i] = -0.5 * c * c / (100.0 * 100.0);
        for (int k = 0; k < N_SHOTS; ++k) {
            const double d = brute_dist(f->s[k][0], f->s[k][1], scale_of() * (G0_S2 + GE_M * (f->e_ins[k] + c)));
            lp[i] -= d * d / (2 * SIG_LIKE * SIG_LIKE);
        }
        lmax = fmax(lmax, lp[i]);
    }
    double z = 0, m = 0, m2 = 0;
    for (int i = 0; i < NG; ++i) {
        const double c = -400.0 + 1.0 * i, p = exp(lp[i] - lmax);
        z += p; m += p * c; m2 += p * c * c;
    }
    *mean = m / z;
    *sd = sqrt(m2 / z - (*mean) * (*mean));
}

static void test_closed_loop_posterior(void **state)
{
    (void)state;
    truth3_t T;
    flight_truth(&T);
    build_map(&T);
    const int runs = 12;
    double d_mean = 0, pm = 0, psd = 0, gm_avg = 0, gsd_avg = 0, en_mean = 0, ess_min = 1e9, worst_state = 0;
    double worst_dv = 0;
    int steps = 0;
    for (int r = 0; r < runs; ++r) {
        g_rng = 0x9E3779B97F4A7C15ull + 7919u * (uint64_t)r;
        const pf_flight_t f = fly(100u + (uint64_t)r, 0);
        double gm, gsd;
        grid_posterior(&f, &gm, &gsd);
        assert_int_equal(f.shots, N_SHOTS);
        assert_int_equal(f.updates, N_SHOTS);
        assert_int_equal(f.dropped, 0);
        d_mean += (f.corr_n - gm) / runs;
        gm_avg += gm / runs;
        gsd_avg += gsd / runs;
        pm += f.corr_e / runs;
        psd += f.spread_e / runs;
        en_mean += f.spread_n / runs;
        ess_min = fmin(ess_min, f.ess);
        /* the state moved by the corrections: error = DN0 - sum, up to the INS's own drift */
        worst_state = fmax(worst_state, fabs(f.err_n_end - (DN0 - f.corr_n)));
        worst_dv = fmax(worst_dv, f.dv_jump);
        steps = f.steps_to_corr;
    }
    print_message("closed loop, %d flights of %d shots: sum of corrections - grid posterior mean %.2f m "
                  "(posterior mean %.1f sd %.1f; cloud spread N %.1f); east corr %.1f m, spread %.1f m "
                  "(prior 0, 100); ESS >= %.0f; |state error - (%.0f - sum)| <= %.4f m; velocity jump %.2e m/s; "
                  "shot to correction %d steps\n",
                  runs, N_SHOTS, d_mean, gm_avg, gsd_avg, en_mean, pm, psd, ess_min, DN0, worst_state, worst_dv,
                  steps);
    /* Monte Carlo error of the importance estimate, averaged over the runs */
    assert_true(fabs(d_mean) < 4 * gsd_avg / sqrt(runs * ess_min));
    assert_true(fabs(en_mean - gsd_avg) < 0.15 * gsd_avg);
    assert_true(gsd_avg < 40.0); /* the shots constrained the north */
    assert_true(fabs(pm) < 4 * 100.0 / sqrt(runs * ess_min));
    assert_true(fabs(psd - 100.0) < 15.0);
    assert_true(worst_state < 0.05);
    assert_true(worst_dv < 1e-5); /* omega x dr would be ~3e-3 m/s per 60 m */
    /* begin + ceil(200 / 50) predict chunks + ceil(3 x 200 / 100) end steps (no resampling) */
    assert_int_equal(steps, 1 + 4 + 6 - 1);
    /* position and velocity fed back: the state's velocity moves by gain x the particles' mean velocity */
    g_rng = 0x9E3779B97F4A7C15ull;
    const pf_flight_t fv = fly(300u, 1);
    print_message("position and velocity fed back: largest velocity correction %.3e m/s, velocity change beyond it "
                  "%.2e m/s; sum of north corrections %.1f m\n", fv.dv_applied, fv.dv_jump, fv.corr_n);
    assert_true(fv.dv_applied > 1e-3);
    assert_true(fv.dv_jump < 1e-5);
}

/* Aid-level schedule and bad input, with a store of one tile. */
static void ins_at(gg_aid_pf_in_t *in, int present, int ok, double s0, double s1)
{
    memset(in, 0, sizeof *in);
    in->lat_rad = 0.7;
    in->lon_rad = 0.2;
    in->h_m = 3000.0;
    in->vn_mps = 0.0;
    in->ve_mps = 100.0;
    in->shot_present = present;
    in->shot_ok = ok;
    in->s[0] = s0;
    in->s[1] = s1;
}

static void test_schedule_and_bad_input(void **state)
{
    (void)state;
    truth3_t T;
    flight_truth(&T);
    build_map(&T);
    store_t store = {&g_map, 0};
    gg_hal_map_t hm = {&store, store_tile_at};
    gg_aid_pf_config_t cfg;
    gg_aid_pf_in_t in;
    gg_aid_pf_corr_t corr;
    pf_config(&cfg, 5u);
    cfg.pf.model = GG_PF_MODEL_RBPF;
    cfg.pf.q_vel = 1.5e-4;
    cfg.pf.q_acc = 2e-5;
    cfg.pf.reg_bw = 1.0;
    cfg.pf.ess_frac = 0.5;
    cfg.pf.gain = 0.05;
    /* config */
    {
        gg_aid_pf_config_t bad = cfg;
        bad.chunk = 0;
        assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_ERR_CONFIG);
        bad = cfg;
        bad.end_chunk = 8 * GG_PF_MAX + 1;
        assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_ERR_CONFIG);
        bad = cfg;
        bad.pf.sigma = 0.0;
        assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_ERR_CONFIG);
        bad = cfg;
        bad.enable = 0;
        assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_OK);
        assert_int_equal(g_aid.initialized, 0);
        ins_at(&in, 0, 0, 0, 0);
        assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_ERR_NOT_INIT);
    }
    /* a NaN pair: a failed shot, the filter predicted only, bit for bit as the bare filter */
    assert_int_equal(gg_aid_pf_init(&g_aid, &cfg), GG_OK);
    {
        gg_pf_config_t pc = g_aid.cfg.pf;
        assert_int_equal(gg_pf_init(&g_bare, &pc), GG_OK);
        gg_pf_input_t pin = {0.7, 0.2, 3000.0, 0, 0.0, 0.0, 0.0, 100.0};
        gg_pf_output_t po;
        assert_int_equal(gg_pf_step(&g_bare, &pin, &po), GG_OK);
    }
    ins_at(&in, 1, 1, NAN, 0.5);
    int steps = 0;
    do {
        assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_OK);
        if (steps == 0) assert_true((g_aid.health & GG_AID_PF_H_SHOT_INVALID) != 0U);
        /* nothing measured, nothing fed: no correction at any step of the shot */
        assert_int_equal(corr.valid, 0);
        ins_at(&in, 0, 0, 0, 0);
        ++steps;
    } while (g_aid.phase != GG_AID_PF_PH_IDLE && steps < 100);
    assert_int_equal(g_aid.n_corrections, 0);
    assert_int_equal(g_aid.n_invalid, 1);
    assert_int_equal(g_aid.n_failed, 1);
    assert_int_equal(g_aid.n_updates, 0);
    assert_int_equal(memcmp(g_aid.pf.x, g_bare.x, sizeof g_bare.x), 0);
    assert_int_equal(memcmp(g_aid.pf.w, g_bare.w, sizeof g_bare.w), 0);
    /* begin + 4 predict chunks + end: NORM, MEAN (no weighing, no resampling) = 400 passes / 100 */
    assert_int_equal(steps, 1 + 4 + 4);
    assert_int_equal(gg_aid_pf_applied(&g_aid, &corr, 1), GG_OK);
    /* three shots on consecutive steps: the first begins, the second waits, the third is dropped */
    for (int j = 0; j < 3; ++j) {
        ins_at(&in, 1, 1, 0.4, 0.6);
        assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_OK);
        if (j == 2) assert_true((g_aid.health & GG_AID_PF_H_DROPPED) != 0U);
    }
    assert_int_equal(g_aid.n_dropped, 1);
    assert_int_equal(g_aid.held_valid, 1);
    int corrections = 0;
    for (int j = 0; j < 100; ++j) {
        ins_at(&in, 0, 0, 0, 0);
        assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_OK);
        if (corr.valid) {
            assert_int_equal(gg_aid_pf_applied(&g_aid, &corr, 1), GG_OK);
            ++corrections;
        }
    }
    assert_int_equal(corrections, 2);
    assert_int_equal(g_aid.n_updates, 2);
    assert_int_equal(g_aid.n_shots, 4);
    /* a bad INS solution: error, aid untouched */
    g_aid2 = g_aid;
    ins_at(&in, 1, 1, 0.4, 0.6);
    in.h_m = NAN;
    assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_ERR_NONFINITE);
    ins_at(&in, 1, 1, 0.4, 0.6);
    in.lat_rad = 2.0;
    assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_ERR_RANGE);
    assert_int_equal(memcmp(&g_aid, &g_aid2, sizeof g_aid), 0);
    /* no map storage: predicted only, NO_MAP */
    ins_at(&in, 1, 1, 0.4, 0.6);
    assert_int_equal(gg_aid_pf_step(&g_aid, &in, NULL, &corr), GG_OK);
    assert_true((g_aid.health & GG_AID_PF_H_NO_MAP) != 0U);
    assert_int_equal(g_aid.n_no_map, 1);
    /* off the tile: the same */
    for (int j = 0; j < 30; ++j) {
        ins_at(&in, 0, 0, 0, 0);
        assert_int_equal(gg_aid_pf_step(&g_aid, &in, NULL, &corr), GG_OK);
    }
    ins_at(&in, 1, 1, 0.4, 0.6);
    in.lat_rad = 0.71;
    assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_OK);
    assert_true((g_aid.health & GG_AID_PF_H_NO_MAP) != 0U);
    assert_int_equal(g_aid.n_no_map, 2);
    assert_int_equal(g_aid.n_updates, 2);
}

/* The information gate (aid_pf.h): shots at a fixed INS position on the truth, the RBPF,
 * corrections not applied (open loop). Returns the weighed shots' corrections fed and
 * withheld, the last info and the info at the first shot fed. */
typedef struct {
    uint32_t fed, withheld, updates;
    double info_last, info_first_fed;
} gate_run_t;

static gate_run_t gate_flight(double info_min, int shots)
{
    store_t store = {&g_map, 0};
    gg_hal_map_t hm = {&store, store_tile_at};
    gg_aid_pf_config_t cfg;
    gg_aid_pf_in_t in;
    gg_aid_pf_corr_t corr;
    gate_run_t r = {0, 0, 0, -2.0, -2.0};
    pf_config(&cfg, 21u);
    cfg.pf.model = GG_PF_MODEL_RBPF;
    cfg.pf.q_vel = 1.5e-4;
    cfg.pf.q_acc = 2e-5;
    cfg.pf.reg_bw = 1.0;
    cfg.pf.ess_frac = 0.5;
    cfg.pf.gain = 0.05;
    cfg.info_min = info_min;
    assert_int_equal(gg_aid_pf_init(&g_aid, &cfg), GG_OK);
    g_rng = 0x9E3779B97F4A7C15ull;
    for (int n = 0; n < shots; ++n) {
        double s[2];
        make_pair(G0_S2, s); /* the INS sits on the truth (lat0, where Gamma_zz = G0) */
        ins_at(&in, 1, 1, s[0], s[1]);
        int steps = 0;
        do {
            assert_int_equal(gg_aid_pf_step(&g_aid, &in, &hm, &corr), GG_OK);
            if (corr.valid != 0) {
                if (r.fed == 0U) r.info_first_fed = g_aid.last.info;
                r.fed++;
                assert_true((g_aid.health & GG_AID_PF_H_UNINFORMATIVE) == 0U);
            }
            assert_int_equal(gg_aid_pf_applied(&g_aid, &corr, 0), GG_OK);
            ins_at(&in, 0, 0, 0, 0);
            ++steps;
        } while (g_aid.phase != GG_AID_PF_PH_IDLE && steps < 100);
        assert_true(steps < 100);
    }
    r.withheld = g_aid.n_uninformative;
    r.updates = g_aid.n_updates;
    r.info_last = g_aid.last.info;
    return r;
}

static void test_information_gate(void **state)
{
    (void)state;
    truth3_t T;
    flight_truth(&T);
    const int shots = 30;
    /* a flat map: the pairs say nothing about the position, the cloud stays as wide as
     * dead reckoning (info ~ 0), and the gate feeds nothing */
    build_map_ge(&T, 0.0);
    const gate_run_t flat = gate_flight(0.2, shots);
    const gate_run_t flat_open = gate_flight(0.0, shots);
    /* Gamma_zz changing 3 E/km north: the north is fixed within a few shots (the east is
     * not: info <= 1/2 with equal prior spreads) */
    build_map_ge(&T, GE_M);
    const gate_run_t grad = gate_flight(0.2, shots);
    print_message("information gate 0.2, %d shots: flat map fed %u withheld %u (info at the end %.3f; gate off: fed "
                  "%u); north gradient fed %u withheld %u, info at the first fed shot %.3f, at the end %.3f\n",
                  shots, flat.fed, flat.withheld, flat.info_last, flat_open.fed, grad.fed, grad.withheld,
                  grad.info_first_fed, grad.info_last);
    assert_int_equal(flat.updates, shots);
    assert_int_equal(flat.fed, 0);
    assert_int_equal(flat.withheld, shots);
    assert_true(fabs(flat.info_last) < 0.15); /* the cloud's sampling error of a variance, 200 particles */
    assert_int_equal(flat_open.fed, shots);   /* the same flight without the gate feeds every shot */
    assert_int_equal(flat_open.withheld, 0);
    assert_true(grad.fed > 0U);
    assert_int_equal(grad.fed + grad.withheld, shots);
    assert_true(grad.withheld > 0U);          /* the first shots teach less than the gate asks */
    assert_true(grad.info_first_fed >= 0.2);
    assert_true(grad.info_last > 0.3 && grad.info_last <= 0.5 + 0.1);
    /* the gate's bounds */
    gg_aid_pf_config_t bad;
    pf_config(&bad, 1u);
    bad.info_min = 1.0;
    assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_ERR_CONFIG);
    bad.info_min = -0.1;
    assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_ERR_CONFIG);
    bad.info_min = NAN;
    assert_int_equal(gg_aid_pf_init(&g_aid, &bad), GG_ERR_CONFIG);
}

/* The shift of the closed loop: particles and the smoothed correction move, nothing else. */
static void test_shift(void **state)
{
    (void)state;
    gg_aid_pf_config_t cfg;
    pf_config(&cfg, 9u);
    assert_int_equal(gg_aid_pf_init(&g_aid, &cfg), GG_OK);
    g_aid2 = g_aid;
    assert_int_equal(gg_pf_shift(&g_aid.pf, 12.5, -3.0, 0.25, -0.5), GG_OK);
    for (int i = 0; i < N_PART; ++i) {
        assert_true(g_aid.pf.x[i][0] == g_aid2.pf.x[i][0] - 12.5);
        assert_true(g_aid.pf.x[i][1] == g_aid2.pf.x[i][1] + 3.0);
        assert_true(g_aid.pf.x[i][2] == g_aid2.pf.x[i][2] - 0.25);
        assert_true(g_aid.pf.x[i][3] == g_aid2.pf.x[i][3] + 0.5);
        for (int k = 4; k < GG_PF_NX; ++k) assert_true(g_aid.pf.x[i][k] == g_aid2.pf.x[i][k]);
    }
    assert_true(g_aid.pf.corr[0] == -12.5 && g_aid.pf.corr[1] == 3.0);
    assert_int_equal(gg_pf_shift(&g_aid.pf, NAN, 0.0, 0.0, 0.0), GG_ERR_NONFINITE);
    assert_int_equal(gg_pf_shift(&g_aid.pf, 0.0, 0.0, 0.0, INFINITY), GG_ERR_NONFINITE);
    gg_pf_input_t pin = {0.7, 0.2, 3000.0, 0, 0.0, 0.0, 0.0, 100.0};
    assert_int_equal(gg_pf_step_begin(&g_aid.pf, &pin), GG_OK);
    assert_int_equal(gg_pf_shift(&g_aid.pf, 1.0, 0.0, 0.0, 0.0), GG_ERR_SEQUENCE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shift),
        cmocka_unit_test(test_schedule_and_bad_input),
        cmocka_unit_test(test_closed_loop_posterior),
        cmocka_unit_test(test_information_gate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
