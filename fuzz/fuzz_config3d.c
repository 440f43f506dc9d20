/* libFuzzer harness: the 3-D configuration message path, raw bytes as they
 * would arrive on GGINS_CONFIG3D -> ggins_nav3d_config_t_decode ->
 * ggins_config3d_from_lcm (hal_sim's conversion, hal_lcm3d.c) ->
 * gg_nav3d_init, then FRAMES frames of a platform at rest at the configured
 * position (every accelerometer reads -G0 of the configuration, gyro at
 * zero, barometer absent, a cold-atom shot (the fringe pair of the reference
 * field's Gamma_zz) on the first; seq and utime on the configured step)
 * through gg_nav3d_step, with a map storage that serves a tile of each
 * kind (tensor, Gamma_zz only) covering most of the globe, so configurations
 * with the map UKF or the particle filter on run their aids.
 * Invariants (abort = a finding): no crash or sanitizer report; a refused
 * configuration makes every step GG_ERR_NOT_INIT; an accepted one gives no
 * NaN/Inf in any output nor in the state's position, velocity, attitude,
 * gradient and specific force.
 * Seeds: scripts/fuzz writes encoded nav3d_config_t of fuzz_nav3d's reference
 * configuration (stabilized and strapdown, gradiometer and model gravity,
 * barometer, fault detection, each aid) via fuzz_seeds, so mutations start
 * from messages that decode and configurations the firmware accepts. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "ggins/gmap.h"
#include "ggins/hal.h"
#include "hal_lcm3d.h"
#include "fuzz_nav3d_checks.h"

#define FRAMES 8
#define GR 1.5386e-6 /* GM / R^3 at the equator, s^-2: the reference gradient */

/* the map storage: 4 x 4 nodes from -1.5 to 1.5 rad of latitude and -3.1 to 2.9
 * rad of longitude, the point-mass gradient at the equator at every node */
static const gg_hal_t *map_hal(void)
{
    return fz_map_hal(4, -1.5, -3.1, 1.0, 2.0, 1e5, GR);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static gg_nav3d_t nav;
    static gg_nav3d_config_t cfg;
    static ggins_nav3d_config_t m;
    const gg_hal_t *hal = map_hal();
    if (size > (size_t)INT32_MAX) return 0;
    if (ggins_nav3d_config_t_decode(data, 0, (int)size, &m) < 0) return 0; /* hal_sim counts and drops it */
    ggins_config3d_from_lcm(&m, &cfg);
    ggins_nav3d_config_t_decode_cleanup(&m);
    const gg_status_t st_init = gg_nav3d_init(&nav, &cfg);
    const int64_t dt = (cfg.dt_us > 0 && cfg.dt_us < 1000000000) ? cfg.dt_us : 1;
    for (int64_t k = 0; k < FRAMES; ++k) {
        gg_frame_t f;
        gg_nav3d_output_t out;
        memset(&f, 0, sizeof f);
        f.seq = k;
        f.utime = k * dt;
        f.n_acc = 6;
        for (int s = 0; s < 6; ++s) {
            for (int j = 0; j < 3; ++j) f.f[s][j] = -(double)cfg.g0_e[j];
            f.acc_status[s] = GG_SENSOR_OK;
        }
        f.gyro_status = GG_SENSOR_OK;
        f.baro_status = GG_SENSOR_ABSENT;
        f.ca_status = GG_SENSOR_ABSENT;
        if (k == 0) {
            fz_fringe_pair(2.0 * GR, f.ca_s);
            f.ca_utime = f.utime;
            f.ca_status = GG_SENSOR_OK;
        }
        const gg_status_t st = gg_nav3d_step(&nav, &f, hal, &out);
        if (st_init != GG_OK) {
            if (st != GG_ERR_NOT_INIT)
                FAIL("refused 3-D configuration (status %d), but a step ran (status %d)", (int)st_init, (int)st);
            continue;
        }
        check_state(&nav);
        check_output(&out);
    }
    return 0;
}
