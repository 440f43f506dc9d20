/* The 3-D task's units shared between its source files (nav3d.c: validation,
 * sequencing and the step; nav3d_att.c: attitude; nav3d_out.c: output).
 * Internal to the firmware library: not installed with the public headers. */
#ifndef GGINS_NAV3D_INT_H
#define GGINS_NAV3D_INT_H

#include "ggins/nav3d.h"

/* Strapdown attitude step: q_b_i from t_k to t_k + dt with the gyro rate w1
 * and the measured angular acceleration wd1 at t_k + dt (nav3d.h,
 * "Attitude"). GG_ERR_RANGE when the quaternion cannot be renormalised
 * (q_b_i untouched). */
gg_status_t n3_attitude_step(gg_nav3d_t *nav, const gg_real_t w1[3], const gg_real_t wd1[3]);

/* The step's output from the state: position (ECEF, geodetic), velocity
 * (ECEF, NED), gravitation, attitude (q_b_e, roll-pitch-yaw), gradients,
 * parity; before the first accepted frame the configured initial state with
 * GG_HEALTH_NOT_INIT. */
void n3_fill_output(const gg_nav3d_t *nav, const gg_frame_t *fr, gg_status_t status,
                    uint32_t health, gg_nav3d_output_t *out);

/* The aiding sources after a step that advanced the state (nav3d_aid.c): the
 * task's INS solution and gradient handed to the gradient-map UKF, its
 * correction applied to the state (closed loop) and its health bits added to
 * *health. n_adv: steps the state advanced since the aid last ran; z_valid: 1
 * when this frame's own readings made the gradient. *corrected = 1 when a
 * correction was applied. A failure of the aid is flagged, never an error of
 * the step. */
void n3_aid_step(gg_nav3d_t *nav, int64_t n_adv, int z_valid, const gg_hal_t *hal,
                 uint32_t *health, int32_t *corrected);

/* The aids' start with the state's first step (aid_mmukf.h, gg_aid_mm_start). */
void n3_aid_start(const gg_nav3d_t *nav, gg_aid_mm_t *aid, uint32_t *health);

/* Closed loop: an aid's correction x = true - estimate (ECI, aid_mmukf.h's
 * gg_aid_corr_t) added to the state (nav3d_aid.c). */
gg_status_t n3_aid_apply(gg_nav3d_t *nav, const gg_aid_corr_t *corr);

/* The cold-atom aid after a step (nav3d_pf.c): the frame's shot with the
 * task's solution handed to the particle filter, its horizontal correction
 * fed back; health bits added to *health, *corrected = 1 when applied.
 * used: the frame advanced the state to its own time. */
void n3_pf_step(gg_nav3d_t *nav, const gg_frame_t *fr, int used, const gg_hal_t *hal, uint32_t *health,
                int32_t *corrected);

/* The cold-atom aid's counters into the output. */
void n3_pf_output(const gg_nav3d_t *nav, gg_nav3d_output_t *out);

/* The aid's counters and one-sigma into the output. */
void n3_aid_output(const gg_nav3d_t *nav, gg_nav3d_output_t *out);

#endif /* GGINS_NAV3D_INT_H */
