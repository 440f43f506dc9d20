/*
 * Conversions between the LCM messages (lcmtypes/) and the firmware's HAL
 * structs (firmware/include/ggins/frame.h, nav2d.h). One implementation,
 * shared by hal_sim (host-in-the-loop), `ggins replay` (the same frames
 * through the firmware again, bit for bit) and the fuzz harnesses (raw
 * bytes -> decode -> these conversions -> gg_nav2d_step), so that all three
 * feed the firmware exactly the same values.
 */
#ifndef GGINS_HAL_LCM_H
#define GGINS_HAL_LCM_H

#ifdef __cplusplus
extern "C" { /* the firmware headers are plain C */
#endif
#include "ggins/frame.h"
#include "ggins/nav2d.h"
#ifdef __cplusplus
}
#endif
#include "ggins_nav2d_config_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_sensor_frame_t.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Sensor frame message -> firmware frame (every field copied as is). */
void ggins_frame_from_lcm(const ggins_sensor_frame_t *m, gg_frame_t *f);

/** Configuration message -> firmware configuration (long doubles from hi + lo
 *  pairs). Fields the message does not carry are zero (gg_nav2d_config_t
 *  defaults). */
void ggins_config_from_lcm(const ggins_nav2d_config_t *m, gg_nav2d_config_t *c);

/** Firmware output -> navigation output message (republished = 0). */
void ggins_output_to_lcm(const gg_nav_output_t *o, int64_t run_id, ggins_nav_output_t *m);

#ifdef __cplusplus
}
#endif

#endif /* GGINS_HAL_LCM_H */
