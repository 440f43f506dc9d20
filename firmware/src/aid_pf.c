/* Cold-atom particle filter as an aiding source of the 3-D task: the shot's
 * schedule over navigation steps, the map page from the HAL's storage, the
 * closed-loop hand-over (aid_pf.h). */
#include "ggins/aid_pf.h"

#include <math.h>
#include <stddef.h>

#include "ggins/geo.h"
#include "ggins/ggmath.h"
#include "ggins/limits.h"

/* Map ops without a tile: every candidate is off the map. */
static gg_status_t aid_pf_no_map(const void *ctx, double lat_rad, double lon_rad, double h_m, double *gzz)
{
    (void)ctx;
    (void)lat_rad;
    (void)lon_rad;
    (void)h_m;
    (void)gzz;
    return GG_ERR_RANGE;
}

/* The map ops of the shot in progress: the storage's tile at the shot's INS
 * position (re-read each step: a tile pointer is valid until the storage's next call). */
static int32_t aid_pf_page(gg_aid_pf_t *a, const gg_hal_map_t *map)
{
    gg_pf_map_t ops;
    const gg_gmap_t *tile = NULL;
    int32_t ok = 0;
    ops.gzz = aid_pf_no_map;
    ops.ctx = NULL;
    if ((map != NULL) && (map->tile_at != NULL) &&
        (map->tile_at(map->ctx, GG_GMAP_KIND_GZZ, a->shot.lat, a->shot.lon, a->shot.h, &tile) == GG_OK) && (tile != NULL) &&
        (fabs(a->shot.h - tile->tile.h0_m) <= tile->tile.h_range_m) && ((tile->tile.flags & GG_GMAP_ANOMALY) == 0U) && (gg_pf_map_from_gmap(tile, &ops) == GG_OK)) {
        ok = 1;
    } else {
        ops.gzz = aid_pf_no_map;
        ops.ctx = NULL;
        tile = NULL;
    }
    a->tile = tile;
    if (gg_pf_set_map(&a->pf, &ops) != GG_OK) {
        ok = 0; /* not reached: the ops have a function */
    }
    return ok;
}

gg_status_t gg_aid_pf_init(gg_aid_pf_t *a, const gg_aid_pf_config_t *cfg)
{
    gg_pf_config_t pc;
    gg_status_t st;
    if ((a == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    a->initialized = 0;
    if (cfg->enable == 0) {
        return GG_OK;
    }
    if ((cfg->enable != 1) || (cfg->chunk < 1) || (cfg->chunk > GG_PF_MAX) || (cfg->end_chunk < 1) ||
        (cfg->end_chunk > (8 * GG_PF_MAX)) ||
        ((cfg->feedback != GG_AID_PF_FB_POS) && (cfg->feedback != GG_AID_PF_FB_POS_VEL)) ||
        !GG_ISFINITE(cfg->info_min) || (cfg->info_min < 0.0) || (cfg->info_min >= 1.0)) {
        return GG_ERR_CONFIG;
    }
    if (gg_integ_init(&a->integ, &cfg->integ, GG_AID_PF_INTEG_DOF) != GG_OK) {
        return GG_ERR_CONFIG;
    }
    a->n_isolated = 0U;
    a->n_uninformative = 0U;
    a->informative = 1; /* the gate opens on the first informative shot (aid_pf_feed) */
    if (cfg->info_min > 0.0) {
        a->informative = 0;
    }
    pc = cfg->pf;
    pc.map.gzz = aid_pf_no_map;
    pc.map.ctx = NULL;
    st = gg_pf_init(&a->pf, &pc);
    if (st != GG_OK) {
        return GG_ERR_CONFIG;
    }
    a->cfg = *cfg;
    a->cfg.pf.map = pc.map;
    a->tile = NULL;
    a->phase = GG_AID_PF_PH_IDLE;
    a->have_map = 0;
    a->held_valid = 0;
    a->health = 0U;
    a->n_shots = 0U;
    a->n_updates = 0U;
    a->n_failed = 0U;
    a->n_invalid = 0U;
    a->n_dropped = 0U;
    a->n_no_map = 0U;
    a->n_map_miss = 0U;
    a->n_degenerate = 0U;
    a->n_resampled = 0U;
    a->n_corrections = 0U;
    a->corr_total_m[0] = 0.0;
    a->corr_total_m[1] = 0.0;
    a->last.corr[0] = 0.0;
    a->last.corr[1] = 0.0;
    for (size_t k = 0U; k < (size_t)GG_PF_NX; ++k) {
        a->last.mean[k] = 0.0;
    }
    a->last.spread[0] = 0.0;
    a->last.spread[1] = 0.0;
    a->last.ess = 0.0;
    a->last.info = 0.0;
    a->last.spread_fi[0] = 0.0;
    a->last.spread_fi[1] = 0.0;
    a->last.gzz_mean = 0.0;
    a->last.health = 0U;
    a->initialized = 1;
    return GG_OK;
}

static int aid_pf_ins_ok(const gg_aid_pf_in_t *in)
{
    return (in->lat_rad <= GG_LIM_PF_LAT_MAX_RAD) && (in->lat_rad >= -GG_LIM_PF_LAT_MAX_RAD) &&
           (in->lon_rad <= GG_LIM_PF_LON_MAX_RAD) && (in->lon_rad >= -GG_LIM_PF_LON_MAX_RAD) &&
           (in->h_m >= GG_LIM_PF_H_MIN_M) && (in->h_m <= GG_LIM_PF_H_MAX_M) &&
           (in->vn_mps <= GG_LIM_PF_V_MAX_MPS) && (in->vn_mps >= -GG_LIM_PF_V_MAX_MPS) &&
           (in->ve_mps <= GG_LIM_PF_V_MAX_MPS) && (in->ve_mps >= -GG_LIM_PF_V_MAX_MPS);
}

/* The shot of this step into the holding slot (validated: a bad pair is a failed shot). */
static void aid_pf_take_shot(gg_aid_pf_t *a, const gg_aid_pf_in_t *in)
{
    gg_pf_input_t s;
    s.lat = in->lat_rad;
    s.lon = in->lon_rad;
    s.h = in->h_m;
    s.vn = in->vn_mps;
    s.ve = in->ve_mps;
    if (in->shot_ok != 0) {
        s.shot_ok = 1;
    } else {
        s.shot_ok = 0;
    }
    s.s0 = 0.0;
    s.s1 = 0.0;
    a->n_shots++;
    if (s.shot_ok != 0) {
        const double s0 = in->s[0];
        const double s1 = in->s[1];
        if (!GG_ISFINITE(s0) || !GG_ISFINITE(s1) || (s0 > GG_LIM_PF_S_MAX) || (s0 < -GG_LIM_PF_S_MAX) ||
            (s1 > GG_LIM_PF_S_MAX) || (s1 < -GG_LIM_PF_S_MAX)) {
            s.shot_ok = 0;
            a->health |= GG_AID_PF_H_SHOT_INVALID;
            a->n_invalid++;
        } else {
            s.s0 = s0;
            s.s1 = s1;
        }
    }
    if (a->held_valid != 0) {
        a->health |= GG_AID_PF_H_DROPPED;
        a->n_dropped++;
    } else {
        a->held = s;
        a->held_valid = 1;
    }
}

/* Begin the held shot: its tile, the filter's shared work. */
static gg_status_t aid_pf_begin(gg_aid_pf_t *a, const gg_hal_map_t *map)
{
    gg_status_t st;
    a->shot = a->held;
    a->held_valid = 0;
    a->have_map = aid_pf_page(a, map);
    if (a->have_map == 0) {
        a->health |= GG_AID_PF_H_NO_MAP;
        a->n_no_map++;
        a->shot.shot_ok = 0; /* nothing to score the pair against: predicted only */
    }
    if (a->shot.shot_ok == 0) {
        a->n_failed++;
    }
    st = gg_pf_step_begin(&a->pf, &a->shot);
    if (st == GG_OK) {
        a->phase = GG_AID_PF_PH_PREDICT;
    }
    return st;
}

/* The end of a shot: its test (aid_integ.h) and the correction it feeds (aid_pf.h). */
static void aid_pf_feed(gg_aid_pf_t *a, const gg_pf_output_t *o, gg_aid_pf_corr_t *corr)
{
    double f = 1.0;
    if ((o->health & GG_PF_H_SKIPPED) != 0U) {
        return; /* predicted only: nothing measured, nothing fed */
    }
    if ((o->health & GG_PF_H_DEGENERATE) != 0U) {
        (void)gg_integ_test(&a->integ, GG_INTEG_STAT_FAIL); /* initialized with the aid: GG_OK */
        return;
    }
    (void)gg_integ_test(&a->integ, o->nis / GG_AID_PF_INTEG_SCALE);
    if ((a->cfg.info_min > 0.0) && (o->info >= -0.5)) { /* the information gate (aid_pf.h) */
        if (o->info >= a->cfg.info_min) {
            a->informative = 1;
        } else if (o->info < (0.5 * a->cfg.info_min)) {
            a->informative = 0;
        } else {
            /* inside the hysteresis: as before */
        }
    } else {
        a->informative = 1;
    }
    if (a->integ.state == GG_INTEG_ISOLATED) {
        a->n_isolated++;
        return;
    }
    if (a->informative == 0) {
        a->n_uninformative++;
        a->health |= GG_AID_PF_H_UNINFORMATIVE;
        return;
    }
    if (a->integ.state == GG_INTEG_SUSPECT) {
        f = GG_INTEG_DEWEIGHT_FB;
    }
    corr->valid = 1;
    corr->dn_m = f * o->corr[0];
    corr->de_m = f * o->corr[1];
    if (a->cfg.feedback == GG_AID_PF_FB_POS_VEL) {
        /* the velocity's smoothed correction, reset to 0 by every feedback:
         * gain x the particles' mean (paper eqs. 9-10 applied to the velocity) */
        corr->dvn_mps = f * a->cfg.pf.gain * o->mean[2];
        corr->dve_mps = f * a->cfg.pf.gain * o->mean[3];
    }
}

/* The monitor's health bits of this step. */
static void aid_pf_integ_health(gg_aid_pf_t *a)
{
    if (a->integ.state == GG_INTEG_SUSPECT) {
        a->health |= GG_AID_PF_H_SUSPECT;
    } else if (a->integ.state == GG_INTEG_ISOLATED) {
        a->health |= GG_AID_PF_H_ISOLATED;
    } else {
        /* OK */
    }
}

gg_status_t gg_aid_pf_step(gg_aid_pf_t *a, const gg_aid_pf_in_t *in, const gg_hal_map_t *map,
                           gg_aid_pf_corr_t *corr)
{
    gg_status_t st = GG_OK;
    int done = 0;
    if ((a == NULL) || (in == NULL) || (corr == NULL)) {
        return GG_ERR_NULL;
    }
    corr->valid = 0;
    corr->dn_m = 0.0;
    corr->de_m = 0.0;
    corr->dvn_mps = 0.0;
    corr->dve_mps = 0.0;
    if (a->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(in->lat_rad) || !GG_ISFINITE(in->lon_rad) || !GG_ISFINITE(in->h_m) ||
        !GG_ISFINITE(in->vn_mps) || !GG_ISFINITE(in->ve_mps)) {
        return GG_ERR_NONFINITE;
    }
    if (aid_pf_ins_ok(in) == 0) {
        return GG_ERR_RANGE;
    }
    a->health = 0U;
    if ((in->shot_present != 0) && (in->stale != 0)) {
        a->n_shots++;
        a->health |= GG_AID_PF_H_DROPPED;
        a->n_dropped++;
    } else if (in->shot_present != 0) {
        aid_pf_take_shot(a, in);
    } else {
        /* no shot this step */
    }
    if (a->phase == GG_AID_PF_PH_IDLE) {
        if (a->held_valid != 0) {
            st = aid_pf_begin(a, map);
        }
    } else if (a->phase == GG_AID_PF_PH_PREDICT) {
        if (a->have_map != 0) {
            (void)aid_pf_page(a, map); /* lost tile: its candidates are off the map (MAP_MISS) */
        }
        st = gg_pf_step_chunk(&a->pf, a->cfg.chunk, &done);
        if ((st == GG_OK) && (done != 0)) {
            a->phase = GG_AID_PF_PH_END;
        }
    } else {
        gg_pf_output_t o;
        st = gg_pf_step_end_chunk(&a->pf, a->cfg.end_chunk, &o, &done);
        if ((st == GG_OK) && (done != 0)) {
            a->last = o;
            a->phase = GG_AID_PF_PH_IDLE;
            if ((o.health & GG_PF_H_SKIPPED) == 0U) {
                a->n_updates++;
            }
            if ((o.health & GG_PF_H_MAP_MISS) != 0U) {
                a->n_map_miss++;
            }
            if ((o.health & GG_PF_H_DEGENERATE) != 0U) {
                a->n_degenerate++;
                a->health |= GG_AID_PF_H_DEGENERATE;
            }
            if ((o.health & GG_PF_H_RESAMPLED) != 0U) {
                a->n_resampled++;
            }
            aid_pf_feed(a, &o, corr);
        }
    }
    if (st != GG_OK) {
        /* an operation refused (not reached with validated input): the shot is abandoned */
        a->health |= GG_AID_PF_H_FAIL;
        if (a->phase != GG_AID_PF_PH_IDLE) {
            a->phase = GG_AID_PF_PH_IDLE;
            a->pf.shot_open = 0;
        }
        corr->valid = 0;
    }
    aid_pf_integ_health(a);
    return GG_OK;
}

gg_status_t gg_aid_pf_applied(gg_aid_pf_t *a, const gg_aid_pf_corr_t *corr, int32_t applied)
{
    gg_status_t st = GG_OK;
    if ((a == NULL) || (corr == NULL)) {
        return GG_ERR_NULL;
    }
    if (a->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if ((corr->valid != 0) && (applied != 0)) {
        st = gg_pf_shift(&a->pf, corr->dn_m, corr->de_m, corr->dvn_mps, corr->dve_mps);
        if (st == GG_OK) {
            a->n_corrections++;
            a->corr_total_m[0] += corr->dn_m;
            a->corr_total_m[1] += corr->de_m;
            if (a->held_valid != 0) {
                /* the waiting shot's INS position moves with the state */
                double sl = 0.0;
                double cl = 1.0;
                double rm = 0.0;
                double rn = 0.0;
                st = gg_sincos_d(a->held.lat, &sl, &cl);
                if (st == GG_OK) {
                    gg_geo_radii(sl, &rm, &rn);
                    a->held.lat += corr->dn_m / (rm + a->held.h);
                    a->held.lon += corr->de_m / ((rn + a->held.h) * cl);
                }
            }
        }
    }
    if (st != GG_OK) {
        a->health |= GG_AID_PF_H_FAIL;
    }
    return st;
}
