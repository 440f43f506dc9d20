#include "truth2d.h"

#include <math.h>
#include <string.h>

void t_point_mass_g(const long double r[3], long double g[3])
{
    const long double n = sqrtl(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const long double k = T_GM / (n * n * n);
    for (int j = 0; j < 3; ++j) g[j] = -k * r[j];
}

void t_point_mass_gamma(const long double r[3], long double gamma[3][3])
{
    const long double n = sqrtl(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const long double k = T_GM / (n * n * n);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            gamma[j][i] = k * (3.0L * r[j] * r[i] / (n * n) - (i == j ? 1.0L : 0.0L));
}

void t_flight(const t_flight_t *fl, long double t, long double r[3], long double v[3],
              long double a[3])
{
    const long double rho = T_RE + fl->h;
    const long double lat = fl->lat0 + fl->v * t / rho;
    const long double c = cosl(lat), s = sinl(lat);
    r[0] = rho * c; r[1] = 0.0L; r[2] = rho * s;
    v[0] = -fl->v * s; v[1] = 0.0L; v[2] = fl->v * c;
    const long double w2 = fl->v * fl->v / rho;
    a[0] = -w2 * c; a[1] = 0.0L; a[2] = -w2 * s;
}

void t_sensor_forces(const long double r[3], const long double acc[3], long double a_m,
                     long double b_m, long double f[4][3])
{
    const long double off[4][3] = {{a_m, 0, 0}, {0, 0, b_m}, {-a_m, 0, 0}, {0, 0, -b_m}};
    for (int i = 0; i < 4; ++i) {
        long double p[3], g[3];
        for (int j = 0; j < 3; ++j) p[j] = r[j] + off[i][j];
        t_point_mass_g(p, g);
        for (int j = 0; j < 3; ++j) f[i][j] = acc[j] - g[j];
    }
}

void t_make_frame(const t_flight_t *fl, int64_t k, int64_t dt_us, int64_t t0_us,
                  const long double bias[3], int64_t baro_every, gg_frame_t *fr)
{
    long double r[3], v[3], a[3], f[4][3];
    memset(fr, 0, sizeof *fr);
    t_flight(fl, (long double)k * (long double)dt_us * 1e-6L, r, v, a);
    t_sensor_forces(r, a, 0.5L, 0.5L, f);
    fr->utime = t0_us + k * dt_us;
    fr->seq = k;
    fr->n_acc = 4;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 3; ++j) {
            const long double x = f[i][j] + (bias != NULL ? bias[j] : 0.0L);
            fr->f[i][j] = (double)x;
            fr->f_lo[i][j] = (double)(x - (long double)fr->f[i][j]);
        }
        fr->acc_status[i] = GG_SENSOR_OK;
    }
    for (int i = 4; i < GG_MAX_ACC; ++i) fr->acc_status[i] = GG_SENSOR_ABSENT;
    fr->gyro_status = GG_SENSOR_ABSENT;
    fr->baro_status = GG_SENSOR_ABSENT;
    if (baro_every > 0 && k % baro_every == 0) {
        fr->baro_alt_m = (double)(sqrtl(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) - T_RE);
        fr->baro_utime = fr->utime;
        fr->baro_status = GG_SENSOR_OK;
    }
}
