/* libFuzzer harness: LCM decode -> HAL conversion -> firmware step.
 *
 * The input is raw bytes as they would arrive on the GGINS_FRAME channel, cut
 * into payloads of the encoded size of one sensor_frame_t (the last one may
 * be short: a truncated payload). Each payload goes through
 * ggins_sensor_frame_t_decode -> ggins_frame_from_lcm (hal_sim's conversion)
 * -> gg_nav2d_step of one navigation task initialised with the
 * welker-perfect configuration (parity checks on). Invariants, checked after
 * every step (abort = a finding):
 *  - no crash, no sanitizer report (the build has ASan + UBSan);
 *  - a rejected frame leaves the navigation state byte for byte untouched;
 *  - after an accepted frame no NaN/Inf anywhere in the state or the output,
 *    and never in an output at all.
 * Seeds: scripts/fuzz writes consecutive valid frames of the flight
 * (fuzz_seeds), so mutations start from frames the firmware accepts. */
#include <stdint.h>

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static gg_nav2d_t nav, saved;
    gg_nav2d_config_t cfg;
    ggins_sensor_frame_t probe;
    memset(&probe, 0, sizeof probe);
    const size_t rec = (size_t)ggins_sensor_frame_t_encoded_size(&probe);
    fuzz_config(&cfg);
    if (gg_nav2d_init(&nav, &cfg) != GG_OK) FUZZ_FAIL("the reference configuration was refused");
    for (size_t off = 0; off < size; off += rec) {
        const size_t n = size - off < rec ? size - off : rec;
        ggins_sensor_frame_t m;
        if (ggins_sensor_frame_t_decode(data + off, 0, (int)n, &m) < 0) continue; /* hal_sim counts and drops it */
        gg_frame_t f;
        gg_nav_output_t out;
        ggins_frame_from_lcm(&m, &f);
        ggins_sensor_frame_t_decode_cleanup(&m);
        memcpy(&saved, &nav, sizeof nav);
        const gg_status_t st = gg_nav2d_step(&nav, &f, NULL, &out);
        if (st != GG_OK) {
            /* a rejected frame's readings never reach the state: the state is
             * byte-identical, apart from the stream follower (which moves on
             * with a consistently sequenced frame) and, during an outage
             * longer than the bridge, the coasting on the held inputs */
            static gg_nav2d_t cmp;
            memcpy(&cmp, &nav, sizeof nav);
            memcpy(&cmp.seq, &saved.seq, sizeof saved.seq);
            if (!(out.health & GG_HEALTH_COAST) && memcmp(&saved, &cmp, sizeof cmp) != 0)
                FUZZ_FAIL("frame seq %lld rejected (status %d) but the navigation state changed", (long long)f.seq, (int)st);
            if (!(out.health & GG_HEALTH_FRAME_REJECTED)) FUZZ_FAIL("rejected frame not flagged FRAME_REJECTED");
            if (out.health & GG_HEALTH_COAST) fuzz_check_state(&nav);
        } else {
            fuzz_check_state(&nav);
        }
        fuzz_check_output(&out);
    }
    return 0;
}
