/**
 * @file aid_integ.h
 * @brief Integrity monitor of an aiding source of the 3-D task: each aid
 *        (aid_mmukf.h, aid_pf.h) tests its own consistency after every
 *        measurement and this monitor decides, from a moving window of those
 *        tests, whether the aid may keep feeding corrections into the state.
 *
 * The habit of PX4's EKF2 (innovation test ratios, per-source fault flags),
 * sized for this task. One test statistic per measurement (epoch of the map
 * UKF, weighed shot of the particle filter), each a normalised squared
 * innovation that a consistent aid draws from chi-square with `dof` degrees
 * of freedom:
 *   - map UKF: the epoch's NIS, nu^T S^-1 nu with S = H P H^T + R (6 dof);
 *   - particle filter: the posterior-weighted squared distance of the measured
 *     fringe pair to the particles' ellipses, sum_i w_i d_i^2 / sigma^2, whose
 *     mean is ~1 but whose tail is heavier than chi^2(1)'s: taken as a scaled
 *     chi-square (aid_pf.h, GG_AID_PF_INTEG_SCALE / _DOF, measured).
 * A measurement the aid could not use for want of consistency (a gated epoch,
 * every particle off the ellipse: degenerate weights) enters with its own
 * statistic (the gated NIS) or, without one, with GG_INTEG_STAT_FAIL.
 *
 * Window test. S_n = sum of the last n statistics (n = window, fewer at the
 * start), against the upper quantile of chi^2(dof n) at the standard-normal
 * z (Wilson & Hilferty, "The distribution of chi-square", PNAS 17, 1931):
 *   q(k, z) = k (1 - 2/(9k) + z sqrt(2/(9k)))^3,   test ratio tau = S_n / q(dof n, z).
 * tau <= 1: the window is inside its band; tau > 1: outside.
 *
 * States (a ladder, one rung per test):
 *   OK        corrections fed whole;
 *   SUSPECT   a window outside its band: flagged in the health word, the
 *             aid de-weights (UKF: R x GG_INTEG_DEWEIGHT_R; particle filter:
 *             the correction fed x GG_INTEG_DEWEIGHT_FB, the rest kept by the filter);
 *   ISOLATED  isolate_after windows in a row outside the band while SUSPECT:
 *             the aid feeds no correction, the task navigates on gravity dead
 *             reckoning alone (its safe core) while the aid keeps testing;
 *   recovery  recover_after windows in a row inside the band step the state
 *             down one rung (ISOLATED -> SUSPECT -> OK).
 * False alarms: a healthy aid's window leaves its band with probability at
 * most 1 - Phi(z) per test (z = 4.265: 1e-5; Wilson-Hilferty overstates the
 * far-tail quantile slightly, the exact tail at the band being 0.66 (k = 6)
 * to 0.99 (k = 384) of the nominal, tests/unit/test_aid_integ.c), so a 10 h flight of 1800 map epochs
 * or 36000 shots at 1 Hz expects 0.018 or 0.36 SUSPECT entries of one
 * window (consecutive windows share n - 1 statistics, so they are not
 * independent trials: these are upper bounds on the expected entries).
 *
 * No heap, fixed window (GG_INTEG_WINDOW_MAX), every loop bounded by it.
 */
#ifndef GGINS_AID_INTEG_H
#define GGINS_AID_INTEG_H

#include <stdint.h>

#include "ggins/status.h"

#define GG_INTEG_WINDOW_MAX 64

#define GG_INTEG_OK 0
#define GG_INTEG_SUSPECT 1
#define GG_INTEG_ISOLATED 2

/** Defaults (a configuration value of 0 selects them). */
#define GG_INTEG_WINDOW_DEFAULT 8
#define GG_INTEG_Z_DEFAULT 4.265
#define GG_INTEG_ISOLATE_AFTER_DEFAULT 3
#define GG_INTEG_RECOVER_AFTER_DEFAULT 8
/** Statistic of a measurement refused without one (per degree of freedom). */
#define GG_INTEG_STAT_FAIL 25.0
/** De-weighting while SUSPECT: the UKF's R times this; the particle filter's
 *  fed correction times GG_INTEG_DEWEIGHT_FB. */
#define GG_INTEG_DEWEIGHT_R 4.0
#define GG_INTEG_DEWEIGHT_FB 0.5
/** Largest statistic entered (a NaN, a negative or a larger value is entered as this):
 *  keeps the window sum finite whatever an aid reports. */
#define GG_INTEG_STAT_MAX 1.0e12

typedef struct {
    int32_t enable;        /**< 1: on (the default in the scenarios), 0: off (always OK) */
    int32_t window;        /**< statistics in the window, 1..GG_INTEG_WINDOW_MAX (0: default) */
    double z;              /**< band's standard-normal quantile, [1, 10] (0: default) */
    int32_t isolate_after; /**< windows outside the band while SUSPECT before ISOLATED, 1..1000 (0: default) */
    int32_t recover_after; /**< windows inside the band per rung of recovery, 1..1000 (0: default) */
} gg_integ_config_t;

typedef struct {
    gg_integ_config_t cfg;       /**< with the defaults filled in */
    double dof;                  /**< degrees of freedom of one statistic */
    double ring[GG_INTEG_WINDOW_MAX];
    int32_t n;                   /**< statistics in the ring (<= window) */
    int32_t head;                /**< next slot */
    double band[GG_INTEG_WINDOW_MAX]; /**< q(dof (i + 1), z): the band of a window of i + 1 statistics */
    int32_t state;               /**< GG_INTEG_* */
    int32_t run_out;             /**< consecutive windows outside the band */
    int32_t run_in;              /**< consecutive windows inside the band */
    double ratio;                /**< test ratio of the last window */
    double last_stat;            /**< the last statistic entered */
    uint32_t n_tests;            /**< statistics entered */
    uint32_t n_outside;          /**< windows outside the band */
    uint32_t n_suspect;          /**< entries into SUSPECT (from OK) */
    uint32_t n_isolated;         /**< entries into ISOLATED */
    int32_t initialized;
} gg_integ_t;

/** Validate cfg (0 fields take the defaults) and start in OK with an empty
 *  window; dof of one statistic in (0, 100]. GG_ERR_CONFIG on a bad value. */
gg_status_t gg_integ_init(gg_integ_t *m, const gg_integ_config_t *cfg, double dof);

/** Enter one test statistic (>= 0; NaN, negative or beyond GG_INTEG_STAT_MAX entered
 *  as GG_INTEG_STAT_MAX) and step the ladder. Off (enable = 0): counted, state OK. */
gg_status_t gg_integ_test(gg_integ_t *m, double stat);

#endif /* GGINS_AID_INTEG_H */
