/* Shared by the 3-D libFuzzer harnesses (fuzz_nav3d, fuzz_config3d): the
 * finding macro, the "nothing non-finite" checks of the 3-D task's output
 * and state, the map storage of a uniform field (one tile of each kind) and
 * the cold-atom fringe pair of a given Gamma_zz. */
#ifndef GGINS_FUZZ_NAV3D_CHECKS_H
#define GGINS_FUZZ_NAV3D_CHECKS_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <string.h>

#include "ggins/gmap.h"
#include "ggins/hal.h"
#include "ggins/nav3d.h"

#define FAIL(...)                                                   \
    do {                                                            \
        fprintf(stderr, "FUZZ INVARIANT BROKEN: " __VA_ARGS__);     \
        fprintf(stderr, "\n");                                      \
        abort();                                                    \
    } while (0)

static int fin(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static void check_output(const gg_nav3d_output_t *o)
{
    if (!fin(o->r_e, 3) || !fin(o->r_e_lo, 3) || !fin(o->v_e, 3) || !isfinite(o->lat_rad) ||
        !isfinite(o->lon_rad) || !isfinite(o->h_m) || !fin(o->v_n, 3) || !fin(o->g_e, 3) ||
        !fin(o->g_e_lo, 3) || !fin(&o->gamma_e[0][0], 9) || !fin(&o->gamma_b[0][0], 9) ||
        !fin(o->f_b, 3) || !fin(o->q_b_e, 4) || !fin(o->rpy_rad, 3) || !fin(o->omega_b, 3) ||
        !fin(o->omega_dot_b, 3) || !fin(o->parity, 4) || !isfinite(o->h_ins_m) ||
        !isfinite(o->baro_innov_m) || !isfinite(o->g_up_corr) || !isfinite(o->t_s) ||
        !isfinite(o->outage_s) || !isfinite(o->state_lag_s) || !isfinite(o->mm_nis) ||
        !fin(o->mm_sigma, 18) || !fin(o->mm_bias, 6) || !fin(o->mm_corr_m, 3) || !fin(o->mm_innov, 6) ||
        !fin(o->mm_pcov, 18) || !isfinite(o->pf_ess) || !fin(o->pf_spread_m, 2) ||
        !fin(o->pf_corr_m, 2) || !fin(o->pf_mean_m, 2) || !isfinite(o->pf_gzz_s2) || !isfinite(o->pf_nis) ||
        !isfinite(o->mm_integ_ratio) || !isfinite(o->pf_integ_ratio))
        FAIL("non-finite value in the 3-D output of seq %lld (status %d, health 0x%x)",
             (long long)o->seq, (int)o->status, (unsigned)o->health);
}

static void check_state(const gg_nav3d_t *nav)
{
    gg_real_t r[3], v[3];
    if (!nav->started) return;
    if (gg_mech_get(&nav->mech, r, v) == GG_OK && (!gg_finite3(r) || !gg_finite3(v)))
        FAIL("non-finite position/velocity in the 3-D state");
    for (int j = 0; j < 3; ++j) {
        if (!isfinite(nav->f_b[j]) || !isfinite(nav->w_k[j])) FAIL("non-finite f_b / w in the 3-D state");
        for (int k = 0; k < 3; ++k)
            if (!isfinite(nav->gamma_b[j][k]) || !isfinite(nav->gamma_e[j][k]))
                FAIL("non-finite gradient in the 3-D state");
    }
    for (int j = 0; j < 4; ++j)
        if (!isfinite(nav->q_b_i[j])) FAIL("non-finite attitude in the 3-D state");
}

/* The map storage: one tile of each kind (the whole tensor for the map UKF,
 * Gamma_DD alone, GG_GMAP_GZZ_ONLY, for the cold-atom aid) of n x n nodes from
 * (lat0, lon0) at spacing (dlat, dlon) rad, every node the point-mass gradient
 * gr = GM / r^3 in NED axes (-gr, -gr, 2 gr), accepted within h_range of
 * height 0. Built on the first call; a later call returns the same storage. */
static struct {
    gg_gmap_tile_t tile, tile_gzz;
    gg_gmap_t map, map_gzz;
    gg_hal_map_t hm;
    gg_hal_t hal;
    int ready;
} g_fz_storage;

static gg_status_t fz_tile_at(void *ctx, uint32_t kind, double lat, double lon, double h, const gg_gmap_t **tile)
{
    (void)ctx;
    (void)h;
    const gg_gmap_t *m = (kind == GG_GMAP_KIND_GZZ)      ? &g_fz_storage.map_gzz
                         : (kind == GG_GMAP_KIND_TENSOR) ? &g_fz_storage.map
                                                         : NULL;
    if (m == NULL) return GG_ERR_RANGE;
    const gg_gmap_tile_t *t = &m->tile;
    if (!(lat >= t->lat0_rad && lat <= t->lat0_rad + (t->nlat - 1) * t->dlat_rad &&
          lon >= t->lon0_rad && lon <= t->lon0_rad + (t->nlon - 1) * t->dlon_rad))
        return GG_ERR_RANGE;
    *tile = m;
    return GG_OK;
}

static const gg_hal_t *fz_map_hal(int n, double lat0, double lon0, double dlat, double dlon, double h_range,
                                  double gr)
{
    if (!g_fz_storage.ready) {
        gg_gmap_tile_t *t = &g_fz_storage.tile;
        memset(t, 0, sizeof *t);
        t->nlat = n;
        t->nlon = n;
        t->lat0_rad = lat0;
        t->lon0_rad = lon0;
        t->dlat_rad = dlat;
        t->dlon_rad = dlon;
        t->h_range_m = h_range;
        for (int i = 0; i < n * n; ++i) {
            t->node[i][GG_GMAP_C_NN] = -gr;
            t->node[i][GG_GMAP_C_EE] = -gr;
            t->node[i][GG_GMAP_C_DD] = 2.0 * gr;
        }
        if (gg_gmap_init(&g_fz_storage.map, t) != GG_OK) FAIL("the reference map tile is refused");
        memcpy(&g_fz_storage.tile_gzz, t, sizeof *t);
        g_fz_storage.tile_gzz.flags = GG_GMAP_GZZ_ONLY;
        for (int i = 0; i < n * n; ++i) {
            g_fz_storage.tile_gzz.node[i][GG_GMAP_C_NN] = 0.0;
            g_fz_storage.tile_gzz.node[i][GG_GMAP_C_EE] = 0.0;
        }
        if (gg_gmap_init(&g_fz_storage.map_gzz, &g_fz_storage.tile_gzz) != GG_OK)
            FAIL("the reference Gamma_zz tile is refused");
        g_fz_storage.hm.ctx = NULL;
        g_fz_storage.hm.tile_at = fz_tile_at;
        memset(&g_fz_storage.hal, 0, sizeof g_fz_storage.hal);
        g_fz_storage.hal.map = &g_fz_storage.hm;
        g_fz_storage.ready = 1;
    }
    return &g_fz_storage.hal;
}

/* A cold-atom fringe pair on the ellipse of Gamma_zz = gzz (s^-2), phase 0.3
 * rad: the two interferometers' populations for the default geometry (852.347 nm
 * Raman light, 1 m separation, T = 0.16 s: k_eff d T^2 per s^-2). */
static void fz_fringe_pair(double gzz, double s[2])
{
    const double kd = 4.0 * 3.14159265358979323846 / 852.347e-9 * 1.0 * 0.16 * 0.16;
    s[0] = 0.5 - 0.25 * cos(0.3);
    s[1] = 0.5 - 0.25 * cos(0.3 + kd * gzz);
}

#endif
