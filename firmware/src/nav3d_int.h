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

#endif /* GGINS_NAV3D_INT_H */
