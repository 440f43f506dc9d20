/* Closed-form truth for the unit tests (independent of the firmware):
 * spherical point-mass Earth and the analytic north flight of docs/design.md,
 * in long double. Vectors are 3-D, index 0 = x (equatorial), 1 = y (0),
 * 2 = z (polar). */
#ifndef GGINS_TESTS_TRUTH2D_H
#define GGINS_TESTS_TRUTH2D_H

#include <stdint.h>

#include "ggins/frame.h"

#define T_GM 3.986004418e14L  /* m^3/s^2, WGS-84 */
#define T_RE 6378137.0L       /* m, WGS-84 semi-major axis */

/* G = -GM r/|r|^3 */
void t_point_mass_g(const long double r[3], long double g[3]);
/* Gamma = (GM/|r|^3)(3 r^ r^T - I) */
void t_point_mass_gamma(const long double r[3], long double gamma[3][3]);

typedef struct {
    long double v;     /* ground speed, m/s */
    long double h;     /* height above R_e, m */
    long double lat0;  /* start latitude, rad */
} t_flight_t;

/* r = (R+h)(cos L, 0, sin L), v = V(-sin L, 0, cos L), a = -(V^2/(R+h))(cos L, 0, sin L),
 * L = L0 + V t/(R+h). */
void t_flight(const t_flight_t *fl, long double t, long double r[3], long double v[3],
              long double a[3]);

/* Specific force of the four dual-axis accelerometers at offsets
 * 1:(+a,0) 2:(0,+b) 3:(-a,0) 4:(0,-b) (x,z) on a platform at r with
 * acceleration acc: f_i = acc - G(r + d_i), exact field at each sensor. */
void t_sensor_forces(const long double r[3], const long double acc[3], long double a_m,
                     long double b_m, long double f[4][3]);

/* One sensor frame (frame.h) of the flight at step k: time t = k dt, utime
 * t0_us + k dt_us, the four accelerometers at a = b = 0.5 m from
 * t_sensor_forces, plus bias[3] on every sensor (NULL: none), each reading
 * sent as double + sub-ulp residual; a perfect barometer (|r| - R_e) every
 * baro_every steps (0: none); the other sensors absent. */
void t_make_frame(const t_flight_t *fl, int64_t k, int64_t dt_us, int64_t t0_us,
                  const long double bias[3], int64_t baro_every, gg_frame_t *fr);

#endif
