/**
 * @file limits.h
 * @brief Every fixed limit of the firmware's modules in one place: the sizes
 *        of their fixed arrays (no heap) and the ranges their inputs are
 *        validated against. Checked at compile time where a relation between
 *        them must hold (#error, as NASA cFE's platform configuration does).
 *
 * A build may override the array sizes marked "overridable" on the compiler
 * command line (-DGG_PF_MAX=1000); the checks below then reject an
 * inconsistent choice before any code is compiled.
 */
#ifndef GGINS_LIMITS_H
#define GGINS_LIMITS_H

/* ---- elementary functions (ggmath.h) ---- */
/** Largest |x| gg_sincos and gg_sincos_d accept, rad (the four-part
 *  reduction of pi/2 is exact for |k| <= 2^20). */
#define GG_MATH_ARG_MAX 1.0e6L

/* ---- geometry (geo.h) ---- */
/** No geodetic conversion within this distance of the Earth's centre, m. */
#define GG_GEO_R_MIN_M 1.0e5L
/** |geodetic latitude| a map tile or a filter state may reach, rad (89 deg:
 *  the local-level frame's east axis is undefined at the pole). */
#define GG_LIM_LAT_MAX_RAD 1.5533430342749532

/* ---- both tasks (navtask.h, nav2d.h, nav3d.h) ---- */
/** Longest frozen-reading window (acc_frozen_frames), frames: 10 min at 100 Hz. */
#define GG_LIM_FROZEN_FRAMES_MAX 60000
/** Configuration and frame ranges (beyond them the task's init returns GG_ERR_RANGE, a frame is
 *  flagged out of range): a vehicle within the Earth's neighbourhood. */
#define GG_LIM_R_MIN_M 3.0e6L       /**< |r0|, r_ref_m lower bound, m (half an Earth radius) */
#define GG_LIM_R_MAX_M 1.0e8L       /**< |r0|, r_ref_m upper bound, m */
#define GG_LIM_V_MAX_MPS 2.0e4L     /**< |v0|, m/s (above escape speed) */
#define GG_LIM_G_MAX_MPS2 100.0L    /**< |g0|, m/s^2 */
#define GG_LIM_BASE_MIN_M 1.0e-3L   /**< half-baselines, m */
#define GG_LIM_BASE_MAX_M 100.0L
#define GG_LIM_DT_MAX_US 10000000   /**< step, microseconds (10 s) */
#define GG_LIM_F_MAX_MPS2 1.0e4     /**< accelerometer range f_max, m/s^2 */

/* ---- 3-D task (nav3d.h) ---- */
/** Gyro range: |w| above it is out of range, rad/s (~573 deg/s). */
#define GG_LIM_W_MAX_RPS 10.0
/** Configured Earth rate, rad/s (about 14 times the Earth's). */
#define GG_LIM_OMEGA_IE_MAX_RPS 1.0e-3L
/** Parity flag threshold asym_max, s^-2. */
#define GG_LIM_ASYM_MAX 1.0
/** |differenced gradient component| of a frame, s^-2 (1e5 E; the Earth's is ~3e-6): beyond it
 *  the readings are no gradient, the frame is rejected (held, such a gradient would make the
 *  gravity dead reckoning diverge at e^(sqrt|Gamma| t)). */
#define GG_LIM_GAMMA_MAX_S2 1.0e-4L

/* ---- gravity model (gmodel.h): array sizes ---- */
#define GG_GMODEL_MAX_DEGREE 8   /**< zonal degree */
#define GG_GMODEL_MAX_PM 32      /**< programmed point-mass anomalies */
#define GG_GMODEL_GRID_MAX 1024  /**< anomaly grid nodes (n_th * n_rho); 16 KiB of doubles */

/* ---- map tiles (gmap.h) ---- */
#define GG_GMAP_MAX_NODES 2500   /**< nodes of one tile (nlat * nlon) */

/* ---- unscented Kalman filter core (ukf.h): array sizes ---- */
#define GG_UKF_NX_MAX 18         /**< state dimension (the map aid: 12 + 6 bias states) */
#define GG_UKF_NZ_MAX 6          /**< measurement dimension */

/* ---- gradient-map aid of the 3-D task (aid_mmukf.h) ---- */
#define GG_MM_MAX_PASSES 40        /**< progressive update passes */
#define GG_LIM_MM_GAMMA_MAX_S2 1.0e-4 /**< |measured gradient component|, s^-2 (1e5 E) */
#define GG_LIM_MM_OFFDIAG_MAX 10.0 /**< offdiag_ratio */
/** Navigation steps one aid call may propagate (a bridge plus a catch-up). */
#define GG_LIM_AID_MM_STEPS_MAX 128
/** Navigation steps between two measurement epochs (1000 s at 100 Hz). */
#define GG_LIM_AID_MM_UPDATE_STEPS_MAX 100000
/** Gyro noise and bias one-sigma the aid accepts, rad/s (~57 deg/s: beyond any navigation gyro). */
#define GG_LIM_AID_MM_SIGMA_W_MAX_RPS 1.0
#define GG_LIM_AID_MM_SIGMA_BARO_MAX_M 1000.0 /**< barometer noise per sample the map aid accepts, m */
/** map aid (aid_mmukf.h): largest initial one-sigma of the accelerometer bias state, m/s^2 */
#define GG_LIM_AID_MM_ACC_BIAS_MAX_MPS2 1.0
/* Bias estimates the task subtracts from its readings (nav3d_aid.c): a
 * correction is applied only if every axis of the resulting estimate stays
 * inside GG_AID_MM_BIAS_SIGMAS times its initial one-sigma and inside the
 * absolute bound below. The gyro bound keeps the rotation terms a wrong
 * estimate leaves in the differenced gradient (|b|^2 per component, Gao et
 * al. eqs. 24-27; 3 b^2 = 3e-6 s^-2) below a tenth of the gradient range GG_LIM_GAMMA_MAX_S2, so no
 * estimate can make every later frame fail the differencing's range check;
 * the accelerometer bound lies far beyond any navigation accelerometer. */
#define GG_AID_MM_BIAS_SIGMAS 10.0
#define GG_LIM_AID_MM_BIAS_W_EST_MAX_RPS 1.0e-3   /**< |gyro bias estimate| per axis, rad/s (206 deg/h) */
#define GG_LIM_AID_MM_BIAS_F_EST_MAX_MPS2 0.1     /**< |accelerometer bias estimate| per axis, m/s^2 */

/* ---- particle filter (pf.h) ---- */
#ifndef GG_PF_MAX
#define GG_PF_MAX 500              /**< particles (overridable) */
#endif
#define GG_LIM_PF_LAT_MAX_RAD 1.55 /**< |INS latitude|, rad */
#define GG_LIM_PF_LON_MAX_RAD 7.0  /**< |INS longitude|, rad (unwrapped) */
#define GG_LIM_PF_H_MIN_M (-1.0e4) /**< INS height, m */
#define GG_LIM_PF_H_MAX_M 1.0e5
#define GG_LIM_PF_V_MAX_MPS 1.0e3  /**< |INS velocity| per axis, m/s */
#define GG_LIM_PF_S_MAX 10.0       /**< |fringe signal| of a shot (normalised populations) */
/* The filter's configuration: each bound lies orders of magnitude beyond any
 * physical setting and keeps the particle cloud's squares far inside the
 * double range (a spread of 1e6 m squares to 1e12 m^2). The regularisation
 * bandwidth is bounded by its kernel (pf.c: h < 1). */
#define GG_LIM_PF_K_EFF_MAX 1.0e9         /**< effective wave number, rad/m (Rb 780 nm: 1.6e7) */
#define GG_LIM_PF_T_MAX_S 10.0            /**< pulse separation, s */
#define GG_LIM_PF_DZ_MAX_M 1.0e3          /**< vertical separation of the interferometers, m */
#define GG_LIM_PF_DT_MAX_S 3600.0         /**< time between shots, s */
#define GG_LIM_PF_POS_SIGMA_MAX_M 1.0e6   /**< initial spread and process noise of the position, m */
#define GG_LIM_PF_VEL_SIGMA_MAX_MPS 1.0e3 /**< the same of the velocity, m/s */
#define GG_LIM_PF_ACC_SIGMA_MAX_MPS2 1.0e2 /**< the same of accelerations, tilts and biases, m/s^2 */
#define GG_LIM_PF_JERK_SIGMA_MAX_MPS3 10.0 /**< the same of g x gyro bias, m/s^3 */

/* ---- compile-time checks ---- */
#if (GG_PF_MAX < 1) || (GG_PF_MAX > 100000)
#error "GG_PF_MAX must be in 1..100000 (the state holds 4 arrays of GG_PF_MAX x 12 doubles)"
#endif
#if GG_UKF_NZ_MAX < 6
#error "GG_UKF_NZ_MAX must hold the six tensor components of the map-matching update"
#endif
#if (GG_MM_MAX_PASSES < 1) || (GG_GMAP_MAX_NODES < 16) || (GG_GMODEL_GRID_MAX < 4)
#error "a module limit is below the smallest size its validation accepts"
#endif

#endif /* GGINS_LIMITS_H */
