/**
 * @file pf.h
 * @brief Bootstrap particle filter for position fixing from single pairs of a
 *        cold-atom vertical gradiometer (Phillips et al., "Position fixing with
 *        partial gravity gradient measurements from cold atom interferometers",
 *        section IV).
 *
 * Particles are candidate horizontal corrections to the (open-loop) INS solution,
 * in metres in the local NED frame at the INS position, with a velocity and a
 * specific-force correction each: x = (dN, dE, dvN, dvE, daN, daE). The corrected
 * position is INS + corr, corr the smoothed mean of the particles.
 *
 * Per gradiometer shot (gg_pf_step, every dt seconds):
 *  1. predict, model GG_PF_MODEL_RW: dN += dvN dt + q_pos w, dvN += q_vel w
 *     (w ~ N(0,1)), same for E; da unused (the paper's kinematic propagation plus
 *     process noise, section IV);
 *     model GG_PF_MODEL_INS: the correction (= minus the INS error) follows the
 *     horizontal INS error dynamics (Schuler loop with Coriolis, psi-angle form,
 *     level flight; da = g psi + accelerometer error, a random walk driven by
 *     the gyro noise): per axis, semi-implicit Euler,
 *       dv += (-w_s^2 d + da - 2 Omega sinL k x dv) dt + q_vel w
 *       d  += dv dt + q_pos w,    da += q_acc w
 *     with w_s^2 = g0 / sqrt(R_M R_N) (+h) and 2 Omega sinL from the INS latitude
 *     ((-2 Omega x dv)_N = -2 Omega sinL dvE, (...)_E = +2 Omega sinL dvN);
 *     model GG_PF_MODEL_RBPF: Rao-Blackwellised (marginalised) particle filter
 *     (Schoen, Gustafsson & Nordlund, IEEE Trans. Signal Process. 53(7), 2005):
 *     the particles carry only the position correction r = (dN, dE); the ten
 *     linear states l = (dvN, dvE, aN, aE, aD, jN, jE, jD, bN, bE) are Gaussian
 *     given the particle's position history, with a per-particle mean (x[i][2..11])
 *     and one covariance P shared by all particles (the model does not depend on
 *     the particle). The model is the psi-angle INS error model of the truth
 *     (level flight, f = (0, 0, -g)) in tilt-as-specific-force units:
 *       a = g (psi_E, -psi_N, psi_D) (tilt), j = g (eps_E, -eps_N, eps_D) (gyro
 *       bias), b = horizontal accelerometer error (bias + non-orthogonality x g):
 *       d'  = dv
 *       dv' = -w_s^2 d + a + b - 2 Omega sinL k x dv        (+ accelerometer noise)
 *       aN' =  wD aE + wN aD + jN,  aE' = -wD aN + wE aD + jE,
 *       aD' = -wN aN - wE aE + jD                           (+ gyro noise x g)
 *       j' = 0, b' = 0 (+ optional random walks)
 *     (from psi' = -w_in x psi + eps with w_in = Omega + rho = (Omega cosL + vE/(R_N+h),
 *     -vN/(R_M+h), -Omega sinL - vE tanL/(R_N+h)), the INS velocity in the input).
 *     Discretised exactly per shot: F = exp(A dt) and Q = int_0^dt e^(As) Qc e^(A^T s) ds
 *     by their Taylor series (12 terms; A dt is nilpotent up to the small Earth-rate,
 *     Schuler and Coriolis couplings). Prediction per particle: the joint Gaussian
 *     prediction of (r, l) given r_k, conditioned on the drawn r_k+1 (derived here;
 *     the construction of Schoen et al. with position and linear-state noise
 *     correlated through F): with S_rr = F_rl P F_rl^T + Q_rr, S_lr = F_ll P F_rl^T + Q_lr,
 *     S_ll = F_ll P F_ll^T + Q_ll, K = S_lr S_rr^-1:
 *       e = chol(S_rr) z,  r <- F_rr r + F_rl m + e,  m <- F_lr r + F_ll m + K e,
 *       P <- S_ll - K S_lr^T;
 *     the measurement depends on r only, so the weights are those of step 3;
 *  2. failed shot: no re-weighting (section V C) - go to 5;
 *  3. re-weight: for each particle, the candidate position INS + (dN, dE) gives
 *     Gamma_zz from the map (ops table gg_pf_map_t), the candidate ellipse
 *     dphi_i = k_eff Gamma_zz dz T^2 (paper eq. 2), and the minimum distance d_i
 *     of the measured pair (s0, s1) to that ellipse
 *       s0 = c0 - A cos(theta), s1 = c1 - A cos(theta + dphi_i), A = eta / 2
 *     (paper eq. 1 with the calibrated centre c and contrast eta);
 *       w_i <- w_i exp(-d_i^2 / (2 sigma^2))                       (paper eq. 6)
 *     then normalised. Candidates off the map get weight 0 (health MAP_MISS). If
 *     every weight is 0 (or the sum is not finite) the weights are reset to
 *     uniform and DEGENERATE is flagged (no NaN can reach the state);
 *  4. N_eff = 1 / sum w_i^2; systematic resampling when N_eff < ess_frac N
 *     (paper: N_eff < N/2); with reg_bw > 0 the resampled particles are
 *     regularised by a Gaussian kernel with the shrinkage of Liu & West (2001),
 *       x_i <- a x_i + (1 - a) m + h L z_i,  a = sqrt(1 - h^2),
 *     m, L L^T the weighted mean and covariance before resampling (Cholesky,
 *     dimensions without spread skipped), h = reg_bw (4 / ((d + 2) N))^(1/(d+4))
 *     (Silverman's Gaussian-kernel bandwidth, d state dimensions): the cloud's
 *     mean and covariance are kept in expectation while duplicated particles
 *     are spread out again (sample impoverishment). RBPF: the kernel acts on the
 *     position (d = 2) and each particle's linear mean follows its position shift
 *     along the cloud's regression of m on r (m += C_mr C_rr^-1 dr);
 *  5. mean x_bar = sum w_i x_i (paper eq. 7); corr <- corr + gain (x_bar - corr)
 *     (the fixed-gain smoothing of paper eqs. 9-10).
 *
 * What the map has taught the filter (RBPF): beside the cloud the filter carries the
 * covariance its own model gives the INS error with no measurement at all, the
 * free-inertial P_fi (12 x 12, from the initial spreads, P_fi <- F P_fi F^T + Q every
 * shot, the F and Q of step 1). The output's info = 1 - (var_N + var_E) / (P_fi,NN +
 * P_fi,EE), var the cloud's weighted position variance after the shot: the share of the
 * free-inertial position variance that the measurements removed (0: the map taught
 * nothing, the cloud is as wide as dead reckoning; near 1: a sharp fix). Corrections
 * fed back shift the cloud but not its spread, so the ratio stays that of the filter's
 * knowledge against dead reckoning. Models RW and INS: info = -1 (not modelled).
 *
 * Distance to the ellipse without trigonometry of theta: with u = (c0 - s0)/A,
 * v = (c1 - s1)/A, the rotation p = (u + v)/sqrt2, q = (u - v)/sqrt2 maps the
 * ellipse to the axis-aligned one with semi-axes sqrt2 |cos(dphi/2)|,
 * sqrt2 |sin(dphi/2)|; the distance to it is found by the trig-free iteration
 * of the evolute (4 iterations, only sqrt), times A.
 *
 * Random numbers: the firmware's generator (ggrand.h: xoshiro256** seeded by
 * splitmix64, normals by Marsaglia's polar method, no libm).
 * Deterministic: the same seed and inputs give bit-identical results.
 * No heap: GG_PF_MAX particles held in the state (compile-time, limits.h, default 500).
 * Units SI, angles rad, lat/lon geodetic WGS-84, h metres above the ellipsoid.
 */
#ifndef GGINS_PF_H
#define GGINS_PF_H

#include <stdint.h>

#include "ggins/ggrand.h"
#include "ggins/gmap.h"
#include "ggins/limits.h"
#include "ggins/status.h"

/* GG_PF_MAX (particles, overridable) and the input ranges: limits.h */
/** State per particle: dN, dE, dvN, dvE, daN, daE (models RW, INS: the first 4 / 6);
 *  RBPF: dN, dE and the mean of the 10 linear states (dvN, dvE, aN, aE, aD, jN, jE, jD, bN, bE). */
#define GG_PF_NX 12
#define GG_PF_NL 10 /**< linear states of the RBPF */
#if GG_PF_NL != (GG_PF_NX - 2)
#error "the RBPF samples the two position states; the rest are its linear states"
#endif

#define GG_PF_MODEL_RW 0   /**< random-walk velocity, no specific-force state */
#define GG_PF_MODEL_INS 1  /**< horizontal INS error dynamics (Schuler, Coriolis) */
#define GG_PF_MODEL_RBPF 2 /**< Rao-Blackwellised: particles for position, Kalman for the rest */

/** Map ops: Gamma_zz = dG_D/dD (s^-2, NED, ~ +3.1e-6) at a geodetic position.
 *  Returns GG_OK or an error (e.g. GG_ERR_RANGE off the map). */
typedef struct {
    gg_status_t (*gzz)(const void *ctx, double lat_rad, double lon_rad, double h_m, double *gzz);
    const void *ctx;
} gg_pf_map_t;

typedef struct {
    int n;                /**< particles, 1..GG_PF_MAX */
    uint64_t seed;
    double k_eff;         /**< rad/m */
    double T;             /**< s */
    double dz;            /**< m, vertical separation */
    double contrast;      /**< eta, (0, 1] */
    double c0;        /**< calibrated ellipse centre (1/2 + bias), signal units */
    double c1;
    double sigma;         /**< likelihood standard deviation, signal units (paper 0.003..0.010) */
    double sigma0_pos;    /**< initial spread of the position corrections, m */
    double sigma0_vel;    /**< initial spread of the velocity corrections, m/s */
    double q_pos;         /**< process noise per step on dN, dE, m */
    double q_vel;         /**< process noise per step on dvN, dvE, m/s */
    int model;            /**< GG_PF_MODEL_RW (0) or GG_PF_MODEL_INS */
    double sigma0_acc;    /**< initial spread of daN, daE, m/s^2 (MODEL_INS); of the tilts aN, aE, aD (RBPF) */
    double q_acc;         /**< process noise per step on daN, daE, m/s^2 (MODEL_INS); on aN, aE, aD (RBPF) */
    double sigma0_jerk;   /**< RBPF: initial spread of jN, jE, jD (g x gyro bias), m/s^3 */
    double q_jerk;        /**< RBPF: random walk per step on j, m/s^3 */
    double sigma0_bias;   /**< RBPF: initial spread of bN, bE (accelerometer error), m/s^2 */
    double q_bias;        /**< RBPF: random walk per step on b, m/s^2 */
    double reg_bw;        /**< regularisation bandwidth, multiple of Silverman's (0: off) */
    double dt;            /**< s between shots */
    double gain;          /**< smoothing gain, (0, 1] */
    double ess_frac;      /**< resample when N_eff < ess_frac N (0.5) */
    gg_pf_map_t map;
} gg_pf_config_t;

typedef struct {
    double lat;   /**< INS solution (rad, rad, m; h from the altimeter) */
    double lon;
    double h;
    int shot_ok;          /**< 0: failed shot, no update */
    double s0;        /**< the pair (signal units), used when shot_ok */
    double s1;
    double vn;            /**< INS velocity north, east (m/s; RBPF transport rate), |v| <= 1000 */
    double ve;
} gg_pf_input_t;

#define GG_PF_H_SKIPPED 0x1u    /**< failed shot: predicted only */
#define GG_PF_H_RESAMPLED 0x2u
#define GG_PF_H_DEGENERATE 0x4u /**< all weights 0: reset to uniform */
#define GG_PF_H_MAP_MISS 0x8u   /**< some candidates were off the map */

typedef struct {
    double corr[2];       /**< smoothed correction (dN, dE), m: corrected = INS + corr */
    double mean[GG_PF_NX]; /**< particle mean (dN, dE, dvN, dvE, daN, daE; RBPF: all 12) */
    double spread[2];     /**< weighted standard deviation of the particles' dN, dE, m (the cloud's spread) */
    double ess;           /**< effective sample size after the update */
    double gzz_mean;      /**< weighted mean of the candidates' Gamma_zz (s^-2; 0 when skipped) */
    double info;          /**< share of the free-inertial position variance removed (see above),
                               <= 1; -1 for the models RW and INS */
    double spread_fi[2];  /**< the free-inertial standard deviation of dN, dE, m (RBPF; 0 otherwise) */
    double nis;           /**< consistency statistic of a weighed shot: the posterior-weighted
                               squared distance of the pair to the candidates' ellipses,
                               sum_i w_i d_i^2 / sigma^2 (1 dof, mean 1 for a consistent filter:
                               aid_integ.h); -1 when not weighed (skipped or degenerate) */
    uint32_t health;      /**< GG_PF_H_* of this step */
} gg_pf_output_t;

/** Regularisation kernel of a shot: weighted mean, covariance (lower triangle)
 *  and its lower Cholesky factor of the cloud before resampling. */
typedef struct {
    double m[GG_PF_NX];
    double cv[GG_PF_NX][GG_PF_NX];
    double el[GG_PF_NX][GG_PF_NX];
} gg_pf_kernel_t;

typedef struct {
    double x[GG_PF_MAX][GG_PF_NX];
    double w[GG_PF_MAX];
    double ll[GG_PF_MAX];        /**< scratch: log-likelihood */
    double xs[GG_PF_MAX][GG_PF_NX]; /**< scratch: process noise, resampling */
    double reg_h;                /**< kernel bandwidth h (from reg_bw at init) */
    double P[GG_PF_NL][GG_PF_NL]; /**< RBPF: covariance of the linear states (all particles) */
    double rb_F[GG_PF_NX][GG_PF_NX]; /**< RBPF scratch: transition of the step */
    double rb_Q[GG_PF_NX][GG_PF_NX]; /**< RBPF scratch: process noise covariance of the step */
    double rb_T[GG_PF_NX][GG_PF_NX]; /**< RBPF scratch */
    double rb_K[GG_PF_NL][2];    /**< RBPF gain of the shot in progress, K = S_lr S_rr^-1 */
    double rb_L[3];              /**< RBPF Cholesky factor of S_rr (l00, l10, l11) */
    double P_fi[GG_PF_NX][GG_PF_NX]; /**< RBPF: free-inertial covariance of the whole state (see above) */
    /* the shot in progress (gg_pf_step_begin / _chunk / _end) */
    gg_pf_input_t sh_in;
    double sh_rm;                /**< meridian radius + h */
    double sh_rn;                /**< (prime vertical radius + h) cos(lat) */
    double sh_ws2;
    double sh_fcor;
    double sh_llmax;
    int sh_have;
    int sh_next;                 /**< next particle to predict and weigh */
    /* the end of the shot in progress (gg_pf_step_end_chunk) */
    int sh_stage;                /**< end stage (-1: not begun) */
    int sh_i;                    /**< next particle of the stage */
    int sh_degen;                /**< all weights 0: reset to uniform */
    int sh_ri;                   /**< resampling: current ancestor */
    double sh_sw;                /**< sum of the weights */
    double sh_sw2;               /**< sum of the squared normalised weights */
    double sh_gzz;               /**< weighted Gamma_zz of the candidates */
    double sh_q;                 /**< posterior-weighted d^2 / sigma^2 of the candidates */
    double sh_ess;
    double sh_u0;                /**< resampling: the one uniform */
    double sh_cum;               /**< resampling: cumulative weight */
    double sh_mean[GG_PF_NX];
    double sh_m2[2];             /**< weighted second moments of dN, dE */
    gg_pf_kernel_t kn;
    uint32_t sh_health;
    int shot_open;
    gg_pf_config_t cfg;
    gg_rng_t rng;
    double corr[2];
    uint32_t n_steps;
    uint32_t n_updates;
    uint32_t n_skipped;
    uint32_t n_resampled;
    uint32_t n_degenerate;
    int initialized;
} gg_pf_t;

/** Map ops backed by the onboard gradient map (gmap.h): Gamma_zz = the tile's
 *  GG_GMAP_C_DD component at (lat, lon, h) (height continued linearly beyond
 *  the tile's band, GG_GMAP_H_EXTRAPOLATE); GG_ERR_RANGE off the tile.
 *  The tile must outlive the filter (map->ctx points to it). */
gg_status_t gg_pf_map_from_gmap(const gg_gmap_t *gm, gg_pf_map_t *map);

/** Validate cfg (GG_ERR_CONFIG), seed, draw the particles around zero correction. */
gg_status_t gg_pf_init(gg_pf_t *st, const gg_pf_config_t *cfg);

/** One shot. GG_ERR_NONFINITE / GG_ERR_RANGE on bad input: state untouched.
 *  = gg_pf_step_begin + gg_pf_step_chunk(all particles) + gg_pf_step_end. */
gg_status_t gg_pf_step(gg_pf_t *st, const gg_pf_input_t *in, gg_pf_output_t *out);

/** The same shot split for a real-time loop (e.g. 50 particles per 10 ms navigation step):
 *  begin validates the input (state untouched on error) and does the work shared by all
 *  particles (RBPF: F, Q, gain, P); each chunk predicts and weighs the next max_particles
 *  particles (*done = 1 after the last); end normalises the weights, resamples and outputs.
 *  The generator draws in particle order, so any chunking gives results bit-identical to
 *  gg_pf_step. Out of order calls: GG_ERR_SEQUENCE (a begun shot must be ended). */
gg_status_t gg_pf_step_begin(gg_pf_t *st, const gg_pf_input_t *in);
gg_status_t gg_pf_step_chunk(gg_pf_t *st, int max_particles, int *done);
gg_status_t gg_pf_step_end(gg_pf_t *st, gg_pf_output_t *out);

/** The end of the shot split the same way: each call does at most max_particles
 *  particle passes of the end's stages (weigh, normalise, kernel mean and
 *  covariance, systematic resampling into the scratch and back, regularisation,
 *  mean: at most eight passes of N); *done = 1 and *out filled after the last.
 *  Bit-identical to gg_pf_step_end for any split. GG_ERR_SEQUENCE before the last
 *  chunk of the shot, GG_ERR_RANGE for max_particles < 1. */
gg_status_t gg_pf_step_end_chunk(gg_pf_t *st, int max_particles, gg_pf_output_t *out, int *done);

/** Closed loop: the correction (dn_m, de_m), m north and east, was added to the
 *  INS position and (dvn_mps, dve_mps), m/s, to its velocity; the particles'
 *  position and velocity (RBPF: the linear means of dvN, dvE; P unchanged) and
 *  the smoothed correction move by minus it (the INS error model is linear, so
 *  this is exact). GG_ERR_SEQUENCE while a shot is open, GG_ERR_NONFINITE
 *  (state untouched). */
gg_status_t gg_pf_shift(gg_pf_t *st, double dn_m, double de_m, double dvn_mps, double dve_mps);

/** Replace the map ops (a map paged between shots or chunks; map->gzz != NULL). */
gg_status_t gg_pf_set_map(gg_pf_t *st, const gg_pf_map_t *map);

/* Building blocks, exposed for tests. */
/** RBPF model of one step: F = exp(A dt), Q = int e^(As) Qc e^(A^T s) ds for the state
 *  (dN, dE, dvN, dvE, aN, aE, aD, jN, jE, jD, bN, bE) at (lat, h) with INS velocity (vn, ve);
 *  Qc = diag(q_pos^2, q_pos^2, q_vel^2, q_vel^2, q_acc^2 x3, q_jerk^2 x3, q_bias^2 x2) / dt.
 *  tmp: 12 x 12 scratch. */
gg_status_t gg_pf_rb_model(const gg_pf_config_t *cfg, double lat, double h, double vn, double ve,
                           double F[GG_PF_NX][GG_PF_NX], double Q[GG_PF_NX][GG_PF_NX],
                           double tmp[GG_PF_NX][GG_PF_NX]);
/** Minimum distance of (s0, s1) to the ellipse s0 = c0 - A cos t, s1 = c1 - A cos(t + dphi). */
gg_status_t gg_pf_ellipse_distance(double s0, double s1, double c0, double c1, double amp, double dphi,
                                   double *d);

#endif /* GGINS_PF_H */
