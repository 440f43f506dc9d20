/**
 * @file mmukf.h
 * @brief Gravity-gradient map matching with an unscented Kalman filter
 *        (Gao, Hu, Chang, Qin & Lyu, "An Aided Navigation Method
 *        Based on Strapdown Gravity Gradiometer", Sensors 21, 829, 2021).
 *
 * The filter runs its OWN double-precision strapdown mechanization in the
 * local-level NED frame (not the firmware's ECI/ECEF nav3d mechanization):
 *   attitude  q_b_n <- Exp(-w_in^n dt) (x) q_b_n (x) Exp(w_ib^b dt)
 *             (Gao eq. 1 with w_nb = w_ib - C_n_b w_in, exact rotation per step),
 *   velocity  v' = C_b_n f + g_n - (2 w_ie^n + w_en^n) x v   (Gao eqs. 6-8 in NED),
 *   position  lat' = v_N/(R_M+h), lon' = v_E/((R_N+h) cos lat), h' = -v_D (Gao eqs. 3-5),
 * w_ie^n = W (cos lat, 0, -sin lat), w_en^n = (v_E/(R_N+h), -v_N/(R_M+h), -v_E tan lat/(R_N+h)),
 * R_M, R_N of WGS-84 (Gao eqs. 9-10), g_n = (0, 0, gamma(lat, h)) normal gravity
 * (Somigliana, NIMA TR8350.2 eq. 4-1, height by eq. 4-3). Per step of dt: the
 * specific force is rotated with the mid-step attitude, velocity by Euler,
 * position with the mean of old and new velocity.
 *
 * Filter state (15, error state about the nominal mechanization, reset to 0
 * after each update; Gao eq. 32): phi (3, rad: C_b_n = Exp(phi) C_b_n,nom),
 * dv (3, NED, m/s), dp (3, NED metres: dN = dlat (R_M+h), dE = dlon (R_N+h) cos lat,
 * dD = -dh), gyro bias (3, rad/s), accelerometer bias (3, m/s^2) (Gao eqs. 11-14:
 * random-walk biases). Sigma points (ukf.h; lambda = 0 is Gao eqs. 35-38) are
 * full navigation states nominal (+) chi_i, each propagated through the
 * mechanization with its own bias-corrected IMU samples over the update
 * interval; at the update the propagated states are differenced against the
 * central one (the nominal) to form the predicted error distribution.
 *
 * Measurement (Gao eqs. 30-31): the six independent components of the gravity
 * gradient tensor in BODY axes, z = (NN.. order of gmap.h mapped to body x, y, z:
 * xx, yy, zz, xy, xz, yz), predicted as Gamma_b = C_n_b Gamma_n(map at lat, lon, h) C_b_n.
 * The gradiometer's centrifugal term (Omega Omega of eq. 30) is removed before
 * the filter (diff3d does it with the gyro rates), so z is Gamma_b itself.
 * R = diag(sigma_meas^2 + sigma_db^2) on the diagonal components and
 * ((offdiag_ratio sigma_meas)^2 + sigma_db^2) on the off-diagonal ones (Gao:
 * ratio 1, R = (sigma_meas^2 + sigma_db^2) I). The map tile must hold the TOTAL field.
 *
 * Progressive update (max_passes > 1; not in Gao): the tensor measures tilt
 * to ~1e-6 rad through the ~4600 E normal field, so with the initial 0.5 deg
 * sigma points at +-sqrt(15) sigma the prediction is far from linear (second
 * order term ~2.6 E against 0.01 E noise) and a single UKF update can throw
 * the heading off (seen in Monte Carlo runs). The epoch's update is then split
 * into passes with R / w_k, sum w_k = 1 (identical to one update for a linear
 * model), each re-linearised about the new estimate; w_k = the smallest
 * R_kk / (predicted spread of component k) until every spread falls below its
 * R_kk, the last pass takes the rest. The NIS output is that of a single update with R at the predicted
 * state (before the passes).
 */
#ifndef GGINS_MMUKF_H
#define GGINS_MMUKF_H

#include <stdint.h>

#include "ggins/geo.h"
#include "ggins/gmap.h"
#include "ggins/status.h"
#include "ggins/ukf.h"

#define GG_MM_NX 15
#define GG_MM_NSIG ((2 * GG_MM_NX) + 1)
#if GG_MM_NX > GG_UKF_NX_MAX
#error "the map-matching error state does not fit the UKF core (GG_UKF_NX_MAX, limits.h)"
#endif
/* GG_MM_MAX_PASSES and the input ranges: limits.h */

/* health bits (output) */
#define GG_MM_H_UKF_FAIL 0x01u   /**< UKF rejected an operation (not PD / model): see ukf health */
#define GG_MM_H_GATED 0x02u      /**< last measurement failed the innovation gate */
#define GG_MM_H_OFF_MAP 0x04u    /**< a sigma point left the map tile: update skipped */
#define GG_MM_H_BAD_INPUT 0x08u  /**< non-finite or out-of-range IMU/measurement: rejected */

/** Full navigation state. */
typedef struct {
    double q[4];   /**< body to NED quaternion, scalar first */
    double v[3];   /**< Earth-relative velocity, NED, m/s */
    double lat;    /**< geodetic latitude, rad */
    double lon;    /**< longitude, rad */
    double h;      /**< height above the WGS-84 ellipsoid, m */
    double bg[3];  /**< gyro bias estimate, rad/s (subtracted from the gyro) */
    double ba[3];  /**< accelerometer bias estimate, m/s^2 */
} gg_mm_nav_t;

typedef struct {
    double dt_s;               /**< mechanization step = IMU sample interval, s (0 < dt <= 1) */
    double update_period_s;    /**< measurement update period, s (Gao Table 1: 60) */
    double sigma_meas_s2;      /**< gradiometer noise, s^-2 (Gao: 0.01 E = 1e-11) */
    double sigma_db_s2;        /**< map (database) noise, s^-2 (Gao: 0.001 E) */
    double sig0_att_rad;       /**< initial one-sigma: attitude, per axis */
    double sig0_vel_mps;       /**< velocity, per axis */
    double sig0_pos_m;         /**< position, per axis */
    double sig0_bg_rps;        /**< gyro bias */
    double sig0_ba_mps2;       /**< accelerometer bias */
    double arw_rad_rts;        /**< gyro angle random walk, rad/sqrt(s) */
    double vrw_mps_rts;        /**< accelerometer velocity random walk, m/s/sqrt(s) */
    double bg_rw;              /**< gyro bias random walk, rad/s/sqrt(s) */
    double ba_rw;              /**< accelerometer bias random walk, m/s^2/sqrt(s) */
    double lambda;             /**< UT spread (0 = Gao) */
    double gate_nis;           /**< NIS gate (chi-square, 6 dof), <= 0: none */
    double offdiag_ratio;      /**< gradiometer noise of the off-diagonal components (xy, xz, yz)
                                    relative to the diagonal ones, [0, 10]; 0 or 1: equal (Gao).
                                    Six differenced tri-axis accelerometers: 1/sqrt(2) (an
                                    off-diagonal element averages four readings, a diagonal one
                                    differences two). The database noise is the same on all six. */
    int32_t max_passes;        /**< progressive update passes, 1..GG_MM_MAX_PASSES (1 = Gao's single update) */
    int32_t vertical_hold;     /**< 1: h and v_D held at their initial values (Gao's pure-inertial run) */
    gg_mm_nav_t init;          /**< initial nominal state (the INS's initial estimate) */
} gg_mm_config_t;

typedef struct {
    gg_mm_config_t cfg;
    const gg_gmap_t *map;          /**< caller-owned tile (read through gg_gmap_eval) */
    gg_ukf_t ukf;
    gg_mm_nav_t sig[GG_MM_NSIG];   /**< propagated sigma states; sig[0] is the nominal */
    double h_hold;
    double vd_hold;
    double t_s;                    /**< time since init, s */
    double t_since_update_s;
    uint32_t health;
    uint32_t n_updates;
    uint32_t n_gated;
    uint32_t n_offmap;
    uint32_t n_fail;
    double last_nis;
    int32_t initialized;
} gg_mm_t;

typedef struct {
    double omega_b[3];   /**< gyro: inertial angular rate of the body, body axes, rad/s (mean over the step) */
    double f_b[3];       /**< accelerometer specific force, body axes, m/s^2 (mean over the step) */
} gg_mm_imu_t;

typedef struct {
    double gamma_b[6];   /**< measured gradient, body axes: xx, yy, zz, xy, xz, yz (s^-2) */
    int32_t gyro_term;   /**< 0: gamma_b is the gradient (Gao). 1: a differencing gradiometer
                              (diff3d.h) removed [w x]^2 with the gyro reading omega_b, so
                              gamma_b = Gamma_b + [w x]^2 - [W x]^2 for the true rate W =
                              omega_b - b_g - n: the prediction adds [w x]^2 - [(w - b_g) x]^2
                              with each sigma state's gyro bias b_g (the tensor then observes
                              the bias), and R the share of the rate noise n (per-axis sigma
                              sigma_omega_rps, linearised at W = w - b_g of the nominal) */
    double omega_b[3];   /**< that gyro reading (or its mean over the gradiometer's window), rad/s */
    double sigma_omega_rps; /**< white-noise sigma of omega_b per axis, rad/s (>= 0) */
} gg_mm_meas_t;

typedef struct {
    gg_mm_nav_t nav;          /**< nominal (estimated) state */
    double sigma[GG_MM_NX];   /**< one-sigma of the error state */
    double P[GG_MM_NX][GG_MM_NX];
    double t_s;
    int32_t updated;          /**< 1 if this step made a measurement update (accepted) */
    double nis;               /**< NIS of this step's update (0 if none) */
    uint32_t health;
    uint32_t n_updates;
    uint32_t n_gated;
    uint32_t n_offmap;
    uint32_t n_fail;
} gg_mm_output_t;

/** map may be NULL (pure inertial; every measurement is then refused). */
gg_status_t gg_mm_init(gg_mm_t *st, const gg_mm_config_t *cfg, const gg_gmap_t *map);

/** One mechanization step of dt with the IMU sample; meas (may be NULL) is
 *  used when update_period_s has elapsed since the last update. */
gg_status_t gg_mm_step(gg_mm_t *st, const gg_mm_imu_t *imu, const gg_mm_meas_t *meas,
                       gg_mm_output_t *out);

/** The mechanization alone (one step), for tests and truth generation:
 *  x advanced by dt with the bias-corrected samples. */
gg_status_t gg_mm_mech(gg_mm_nav_t *x, const gg_mm_imu_t *imu, double dt, int32_t vertical_hold,
                       double h_hold, double vd_hold);

/** Error of a navigation state a against a reference b in the filter's error
 *  coordinates (phi, dv, dN dE dD, dbg, dba): d = a (-) b. */
gg_status_t gg_mm_error(const gg_mm_nav_t *a, const gg_mm_nav_t *b, double d[GG_MM_NX]);

/** a = b (+) d: the error d (filter coordinates) applied to state b. */
gg_status_t gg_mm_apply(const gg_mm_nav_t *b, const double d[GG_MM_NX], gg_mm_nav_t *a);

/** Predicted body-axes gradient (xx, yy, zz, xy, xz, yz) of a state from the map. */
gg_status_t gg_mm_predict_gradient(const gg_gmap_t *map, const gg_mm_nav_t *x, double g6[6]);

/** Normal gravity at (lat, h), m/s^2 (gg_geo_normal_gravity of geo.h). */
static inline gg_status_t gg_mm_normal_gravity(double lat, double h, double *g)
{
    return gg_geo_normal_gravity(lat, h, g);
}

#endif /* GGINS_MMUKF_H */
