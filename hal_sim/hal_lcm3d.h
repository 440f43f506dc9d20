/*
 * Conversions between the 3-D LCM messages (lcmtypes/nav3d_config_t.lcm,
 * nav3d_output_t.lcm) and the firmware's 3-D structs (nav3d.h). Used by
 * hal_sim in 3-D mode; sensor frames are the 2-D ones (hal_lcm.h).
 */
#ifndef GGINS_HAL_LCM3D_H
#define GGINS_HAL_LCM3D_H

#ifdef __cplusplus
extern "C" {
#endif
#include "ggins/nav3d.h"
#include "ggins_nav3d_config_t.h"
#include "ggins_nav3d_output_t.h"

/** Configuration message -> firmware configuration (long doubles from hi + lo
 *  pairs). Fields the message does not carry are zero. */
void ggins_config3d_from_lcm(const ggins_nav3d_config_t *m, gg_nav3d_config_t *c);

/** Firmware output -> 3-D navigation output message (republished = 0). */
void ggins_output3d_to_lcm(const gg_nav3d_output_t *o, int64_t run_id, ggins_nav3d_output_t *m);

#ifdef __cplusplus
}
#endif

#endif /* GGINS_HAL_LCM3D_H */
