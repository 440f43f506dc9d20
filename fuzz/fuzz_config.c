/* libFuzzer harness: the configuration message path, raw bytes as they would
 * arrive on GGINS_CONFIG -> ggins_nav2d_config_t_decode -> ggins_config_from_lcm
 * (hal_sim's conversion) -> gg_nav2d_init. A configuration the firmware accepts
 * must give a navigation task that steps a plausible frame without crashing
 * and without a NaN/Inf in its state or output; a refused one must leave
 * nothing configured (a step then reports GG_ERR_NOT_INIT). */
#include <stdint.h>

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static gg_nav2d_t nav;
    static gg_nav2d_config_t cfg;
    ggins_nav2d_config_t m;
    if (ggins_nav2d_config_t_decode(data, 0, (int)size, &m) < 0) return 0;
    ggins_config_from_lcm(&m, &cfg);
    ggins_nav2d_config_t_decode_cleanup(&m);
    const gg_status_t st = gg_nav2d_init(&nav, &cfg);
    /* two frames of a vehicle at rest at the configured position: plausible input */
    gg_frame_t f;
    gg_nav_output_t out;
    memset(&f, 0, sizeof f);
    f.n_acc = 4;
    for (int i = 4; i < GG_MAX_ACC; ++i) f.acc_status[i] = GG_SENSOR_ABSENT;
    f.gyro_status = GG_SENSOR_ABSENT;
    f.baro_status = GG_SENSOR_ABSENT;
    for (int i = 0; i < 4; ++i) f.f[i][0] = 9.8;
    for (int k = 0; k < 2; ++k) {
        f.seq = k;
        f.utime = (int64_t)k * (cfg.dt_us > 0 && cfg.dt_us < 1000000000 ? cfg.dt_us : 1);
        const gg_status_t s = gg_nav2d_step(&nav, &f, NULL, &out);
        if (st != GG_OK) {
            if (s != GG_ERR_NOT_INIT) FUZZ_FAIL("refused configuration (status %d), but a step ran (status %d)", (int)st, (int)s);
            continue;
        }
        if (s == GG_OK) fuzz_check_state(&nav);
        fuzz_check_output(&out);
    }
    return 0;
}
