/* Attitude of the 3-D task's strapdown platform: q_b_i by the classical
 * fourth-order Runge-Kutta method on q' = 1/2 q (x) (0, w) (nav3d.h). */
#include "nav3d_int.h"

#include <stddef.h>

#include "ggins/quat.h"

/* q' = 1/2 q (x) (0, w) */
static void qdot(const gg_real_t q[4], const gg_real_t w[3], gg_real_t d[4])
{
    const gg_real_t p[4] = {0.0L, w[0], w[1], w[2]};
    size_t j;
    gg_quat_mul(q, p, d);
    for (j = 0U; j < 4U; ++j) {
        d[j] *= 0.5L;
    }
}

/* Fourth-order Runge-Kutta attitude step with the rate interpolated through
 * the samples k-2 .. k+1, or by cubic Hermite with the measured angular
 * accelerations wd1 (at k+1) and nav->omega_dot_b (at k) on the first two steps (nav3d.h). */
gg_status_t n3_attitude_step(gg_nav3d_t *nav, const gg_real_t w1[3], const gg_real_t wd1[3])
{
    const gg_real_t h = nav->dt_s;
    gg_real_t wm[3];
    gg_real_t k1[4];
    gg_real_t k2[4];
    gg_real_t k3[4];
    gg_real_t k4[4];
    gg_real_t qt[4];
    gg_real_t q[4];
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        if (nav->n_w >= 3) {
            /* cubic through t_k - 2h, t_k - h, t_k, t_k + h at t_k + h/2:
             * Lagrange weights 1/16, -5/16, 15/16, 5/16 */
            wm[j] = (nav->w_km2[j] - (5.0L * nav->w_km1[j]) + (15.0L * nav->w_k[j]) +
                     (5.0L * w1[j])) * 0.0625L;
        } else {
            /* cubic Hermite at h/2: (w_k + w1)/2 + h/8 (wd_k - wd1) */
            wm[j] = (0.5L * (nav->w_k[j] + w1[j])) + ((0.125L * h) * (nav->omega_dot_b[j] - wd1[j]));
        }
    }
    qdot(nav->q_b_i, nav->w_k, k1);
    for (j = 0U; j < 4U; ++j) {
        qt[j] = nav->q_b_i[j] + (0.5L * h * k1[j]);
    }
    qdot(qt, wm, k2);
    for (j = 0U; j < 4U; ++j) {
        qt[j] = nav->q_b_i[j] + (0.5L * h * k2[j]);
    }
    qdot(qt, wm, k3);
    for (j = 0U; j < 4U; ++j) {
        qt[j] = nav->q_b_i[j] + (h * k3[j]);
    }
    qdot(qt, w1, k4);
    for (j = 0U; j < 4U; ++j) {
        q[j] = nav->q_b_i[j] + ((h / 6.0L) * (k1[j] + (2.0L * (k2[j] + k3[j])) + k4[j]));
    }
    if (gg_quat_normalize(q) != GG_OK) {
        return GG_ERR_RANGE;
    }
    for (j = 0U; j < 4U; ++j) {
        nav->q_b_i[j] = q[j];
    }
    return GG_OK;
}
