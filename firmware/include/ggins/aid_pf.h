/**
 * @file aid_pf.h
 * @brief Cold-atom partial-gradient position fixing as an aiding source of the
 *        3-D task (nav3d.h): the particle filter of pf.h (Phillips et al.,
 *        "Position fixing with partial gravity gradient measurements from cold
 *        atom interferometers", sections II-V) fed with the task's own INS
 *        solution and the fringe pairs of the cold-atom vertical gradiometer
 *        in the sensor frame (frame.h, ca_*), scoring each pair against the
 *        Gamma_zz of the onboard map tiles the HAL's map storage provides
 *        (hal.h, gmap.h component DD; the tiles must hold the total gradient).
 *
 * No mechanization or geometry of its own: the task propagates the navigation
 * state; the aid reads its position, height and NED velocity (geo.h, quat.h)
 * at the step a shot arrives, and the filter's particles are corrections to
 * that solution (pf.h: position dN, dE; with the Rao-Blackwellised model a
 * Kalman mean of the horizontal velocity, tilt, gyro-bias and
 * accelerometer-error states each).
 *
 * Closed loop on the horizontal position, and (feedback = GG_AID_PF_FB_POS_VEL)
 * the horizontal velocity. After each shot the smoothed correction c (paper eqs.
 * 9-10) is added to the task's position along north and east (the inertial
 * velocity by omega_ie x dr, so the Earth-relative velocity is unchanged; with
 * gravity dead reckoning the gravitation by Gamma dr, as the map aid does) and,
 * with POS_VEL, gain x the particles' mean velocity correction to its
 * Earth-relative velocity; every particle (RBPF: its linear mean; P unchanged)
 * and c move by minus what was applied (gg_pf_shift): the filter's error model
 * is linear, so this is the open-loop filter exactly, with the INS kept at the
 * estimate. Why closed, and why these states:
 *  - closed: the candidates are INS + r with the radii and the map page at
 *    the INS position; an open-loop INS drifts by kilometres (4.6 km after
 *    3 h in Phillips' flight) and the map page around it loses the candidates
 *    near the truth (the failure of the first standalone version,
 *    docs/cold-atom-pf.md). Fed back, the INS stays at the estimate, the tile
 *    the storage returns for the INS position covers the cloud, and the
 *    linearised error model sees errors of the cloud's size, not of the drift.
 *    The other aids (barometer, map UKF) then work about the same corrected
 *    solution.
 *  - position and velocity: resetting the position alone removes the Schuler
 *    loop's restoring term from the INS (its velocity error then grows with
 *    the tilt and the accelerometer error instead of oscillating: 3.9 m/s mean
 *    on Phillips' route against 0.6 m/s unaided, docs/cold-atom-pf.md); with
 *    the velocity fed back as well the loop is closed on both states the
 *    Schuler oscillation exchanges. Not the tilt, gyro-bias and accelerometer
 *    states: a pair measures Gamma_zz at the horizontal position only, those
 *    are inferred weakly through two integrations, and the attitude is what
 *    the map UKF (which owns attitude corrections with its own covariance)
 *    corrects; the vertical is the barometer's.
 *
 * Real-time schedule: a shot is split over navigation steps so that no step
 * does more than one bounded unit of work:
 *   idle -> (shot in the frame) begin: validation, INS solution, the work
 *   shared by all particles (RBPF F, Q, gain) -> predict and weigh chunk
 *   particles per step -> end: end_chunk particle passes per step
 *   (gg_pf_step_end_chunk) -> closed-loop correction -> idle.
 * With 500 particles, chunk 50 and end_chunk 250 a shot takes 1 + 10 + <= 16
 * steps, well inside the 100 steps of a 1 Hz shot at 100 Hz. A shot that
 * arrives while one is in progress waits (one is held, with the INS solution
 * of its arrival step, moved with every correction applied meanwhile); a
 * further one is dropped (counted, GG_HEALTH_PF_SHOT_INVALID).
 *
 * Feedback only from a weighed shot. A failed shot, a shot without a tile and a
 * degenerate one (every candidate off its ellipse) move nothing: the filter
 * predicts its cloud and the correction waits for the next weighed shot (the
 * smoothed mean of an unweighed cloud is the sampling noise of the prediction).
 * Integrity (aid_integ.h): each weighed shot enters its statistic (pf.h nis)
 * as a scaled chi-square, nis / GG_AID_PF_INTEG_SCALE with GG_AID_PF_INTEG_DOF
 * degrees of freedom (below), a degenerate one GG_INTEG_STAT_FAIL; SUSPECT feeds GG_INTEG_DEWEIGHT_FB of
 * the correction (the filter keeps the rest), ISOLATED feeds none (the task
 * flies on gravity dead reckoning) while the filter goes on weighing.
 *
 * Information (pf.h info, the share of the free-inertial position variance the map
 * has removed, RBPF): a filter whose cloud is as wide as dead reckoning has learnt
 * nothing from the map, and its mean is the sampling noise of the cloud; fed back,
 * that noise moves the INS and can only make it worse. With info_min > 0 the aid
 * feeds a weighed shot's correction only while the filter is informative: it
 * becomes so when info >= info_min and stops being so when info < info_min / 2 (a
 * hysteresis against the cloud's sampling noise); meanwhile the correction is
 * withheld (counted, GG_AID_PF_H_UNINFORMATIVE), the smoothed correction goes on
 * accumulating, and the task flies on gravity dead reckoning. A filter that is
 * never informative never feeds: the aided solution is the unaided one, and the
 * host reports the aid as not helping. The models RW and INS carry no free-inertial
 * covariance (info = -1): the gate stays open.
 *
 * Bad input never reaches the filter: a shot with a non-finite or
 * out-of-range pair is used as a failed shot (predicted, not weighed) and
 * flagged GG_HEALTH_PF_SHOT_INVALID; a shot without a covering tile likewise,
 * flagged GG_HEALTH_PF_FAIL.
 */
#ifndef GGINS_AID_PF_H
#define GGINS_AID_PF_H

#include <stdint.h>

#include "ggins/aid_integ.h"
#include "ggins/frame.h"
#include "ggins/gmap.h"
#include "ggins/hal.h"
#include "ggins/pf.h"
#include "ggins/status.h"

/** Aid health (gg_aid_pf_t.health, mapped onto GG_HEALTH_PF_* by the task). */
#define GG_AID_PF_H_SHOT_INVALID 0x01u /**< the shot's pair was NaN/Inf or out of range */
#define GG_AID_PF_H_DROPPED 0x02u      /**< a shot was dropped (one already waiting) */
#define GG_AID_PF_H_NO_MAP 0x04u       /**< no tile covers the shot's position at its height: predicted only */
#define GG_AID_PF_H_DEGENERATE 0x08u   /**< every candidate off the map: weights reset */
#define GG_AID_PF_H_FAIL 0x10u         /**< an operation of the filter was rejected */
/** The weighed shot's statistic (pf.h nis) is not chi^2(1): measured on healthy
 *  flights, mean 1.09, variance 3.99, median 0.33 over 11369 shots (Phillips'
 *  route, dz = 2 m) and mean 1.06, variance 4.22, median 0.32 over 659 shots
 *  (45 N route, EGM96, dz = 1 m), against 1, 2 and 0.45 for chi^2(1): a
 *  posterior-weighted distance of a pair to a cloud of ellipses mixes shots
 *  where the cloud is narrower than the likelihood (chi^2(1)) and where it is
 *  wider (smaller, as the weights select the ellipses near the pair), with a
 *  heavier tail. The monitor takes it as c chi^2(nu) matched in mean and variance
 *  (Satterthwaite, "An approximate distribution of estimates of variance
 *  components", Biometrics Bulletin 2, 1946): c = var / (2 mean), nu =
 *  2 mean^2 / var, from the pooled figures (mean 1.09, variance 4.0). As chi^2(1)
 *  its windows of 8 shots left their band 3 times an hour on Phillips' route. */
#define GG_AID_PF_INTEG_SCALE 1.83
#define GG_AID_PF_INTEG_DOF 0.6

#define GG_AID_PF_H_SUSPECT 0x20u      /**< integrity monitor (aid_integ.h): SUSPECT, feedback halved */
#define GG_AID_PF_H_ISOLATED 0x40u     /**< integrity monitor: ISOLATED, no correction fed */
#define GG_AID_PF_H_UNINFORMATIVE 0x80u /**< the weighed shot's correction withheld: the filter has not
                                             learnt enough from the map (info below the gate, above) */

/** What the closed loop feeds back (gg_aid_pf_config_t.feedback). */
#define GG_AID_PF_FB_POS 0     /**< the horizontal position */
#define GG_AID_PF_FB_POS_VEL 1 /**< the horizontal position and velocity */

/** Schedule phases. */
#define GG_AID_PF_PH_IDLE 0
#define GG_AID_PF_PH_PREDICT 1
#define GG_AID_PF_PH_END 2

typedef struct {
    int32_t enable;      /**< 1: aid on (the rest is validated only then) */
    int32_t chunk;       /**< particles predicted and weighed per navigation step, 1..GG_PF_MAX */
    int32_t end_chunk;   /**< particle passes of the shot's end per navigation step, 1..8 GG_PF_MAX */
    int32_t feedback;    /**< GG_AID_PF_FB_POS or GG_AID_PF_FB_POS_VEL */
    gg_pf_config_t pf;   /**< the filter (pf.h); pf.map is set by the aid (the HAL's map storage),
                              pf.dt is the shot period */
    gg_integ_config_t integ; /**< integrity monitor on the weighed shots' statistic (pf.h nis, scaled chi-square, above) */
    double info_min;     /**< feed corrections only while pf.h info >= info_min (released below info_min / 2);
                              [0, 1), 0: always feed (above) */
} gg_aid_pf_config_t;

/** The task's INS solution at a step, and the shot in its frame. */
typedef struct {
    double lat_rad;      /**< geodetic latitude, longitude, height (WGS-84) */
    double lon_rad;
    double h_m;
    double vn_mps;       /**< Earth-relative velocity north, east, m/s */
    double ve_mps;
    int32_t shot_present; /**< 1: the frame carries a new shot (ca_status != ABSENT, new ca_utime) */
    int32_t shot_ok;     /**< 1: a pair (GG_SENSOR_OK), 0: a failed shot */
    double s[2];         /**< the pair */
    int32_t stale;       /**< 1: the solution is not at the frame's time (frame not used): a shot is
                              dropped (counted, GG_AID_PF_H_DROPPED) */
} gg_aid_pf_in_t;

/** A horizontal correction to the task's state: position (m) and Earth-relative
 *  velocity (m/s, 0 with GG_AID_PF_FB_POS), north and east. */
typedef struct {
    int32_t valid;
    double dn_m;
    double de_m;
    double dvn_mps;
    double dve_mps;
} gg_aid_pf_corr_t;

typedef struct {
    gg_aid_pf_config_t cfg;
    gg_pf_t pf;
    const gg_gmap_t *tile;     /**< tile of the shot in progress (re-read each step) */
    int32_t phase;             /**< GG_AID_PF_PH_* */
    int32_t have_map;          /**< the shot in progress has a tile */
    gg_pf_input_t shot;        /**< the shot in progress */
    gg_pf_input_t held;        /**< a shot waiting for the filter */
    int32_t held_valid;
    gg_pf_output_t last;       /**< output of the last shot */
    uint32_t health;           /**< GG_AID_PF_H_* of this step */
    uint32_t n_shots;          /**< shots seen */
    uint32_t n_updates;        /**< shots weighed (a pair on the map) */
    uint32_t n_failed;         /**< failed or invalid shots (predicted only) */
    uint32_t n_invalid;        /**< shots with a NaN/Inf or out-of-range pair */
    uint32_t n_dropped;        /**< shots dropped (the filter busy with one waiting) */
    uint32_t n_no_map;         /**< shots without a covering tile */
    uint32_t n_map_miss;       /**< shots with some candidates off the tile */
    uint32_t n_degenerate;     /**< shots whose weights were reset */
    uint32_t n_resampled;
    uint32_t n_corrections;    /**< corrections fed back */
    double corr_total_m[2];    /**< sum of the corrections fed back, north, east, m */
    gg_integ_t integ;          /**< integrity monitor (aid_integ.h) */
    uint32_t n_isolated;       /**< weighed shots whose correction was not fed (ISOLATED) */
    uint32_t n_uninformative;  /**< weighed shots whose correction was withheld (info below the gate) */
    int32_t informative;       /**< 1: the information gate is open (always 1 with info_min = 0) */
    int32_t initialized;
} gg_aid_pf_t;

/** Validate cfg and start the filter (pf.h gg_pf_init; its map ops are the
 *  aid's). cfg->enable = 0 leaves the aid off (GG_OK, initialized = 0).
 *  GG_ERR_CONFIG on a bad value. */
gg_status_t gg_aid_pf_init(gg_aid_pf_t *a, const gg_aid_pf_config_t *cfg);

/** One navigation step of the aid: take the shot of this step (if any), then
 *  do the schedule's next unit of work. map may be NULL (no map storage:
 *  shots are predicted only, NO_MAP). *corr is filled (valid = 1) at the end
 *  of a weighed shot that the integrity monitor lets through (halved while
 *  SUSPECT): the task must add it to its position and then call
 *  gg_aid_pf_applied. A shot predicted only (failed, off the map) and a shot
 *  while ISOLATED feed nothing. a->health holds this step's GG_AID_PF_H_* bits.
 *  GG_ERR_NONFINITE / GG_ERR_RANGE on a bad INS solution (aid untouched). */
gg_status_t gg_aid_pf_step(gg_aid_pf_t *a, const gg_aid_pf_in_t *in, const gg_hal_map_t *map,
                           gg_aid_pf_corr_t *corr);

/** The task applied *corr (applied = 1) or could not (0): the particles move
 *  with it (gg_pf_shift) or, not applied, stay as they are. */
gg_status_t gg_aid_pf_applied(gg_aid_pf_t *a, const gg_aid_pf_corr_t *corr, int32_t applied);

#endif /* GGINS_AID_PF_H */
