/**
 * @file fdi3d.h
 * @brief Accommodation of unusable readings of the six tri-axis
 *        accelerometers of the 3-D platform (diff3d.h layout), from the
 *        redundancy of opposite pairs.
 *
 * Sensors p and p + 3 (p = 0, 1, 2) sit at +-d_p on body axis p. On a rigid
 * body the rotation terms of a reading are linear in the offset (diff3d.h:
 * f(d) = f_c + (W - Gamma) d + O(d^2)), so each pair's mean
 *   m_p = (f(+d_p) + f(-d_p)) / 2 = f_c - (|d_p|^2 / 2) d2G/dx_p^2 + O(d^4)
 * is the centre specific force up to the field's curvature along that axis,
 * whatever the rotation: 18 readings, 9 pair means, 3 unknowns - on each
 * axis j the three pair means agree to the curvature differences
 * (~1e-13 m/s^2 at 0.5 m near the Earth).
 *
 * A reading known to be unusable (NaN/Inf, out of range, its sensor flagged
 * bad) is rebuilt from its partner and the other pairs' means on the same
 * axis, keeping the curvature difference the pairs had at the last frame
 * with all readings usable:
 *   m_p,j := mean over usable pairs q of (m_q,j + (m_p,j - m_q,j)_last),
 *   f_i,j := 2 m_p,j - f_i',j      (i' the partner of i)
 * so the rebuilt reading is right to the change of that difference since
 * (~1e-17 m/s^2 per second at 200 m/s). One unusable reading per pair and
 * axis can be rebuilt, and only while another pair on that axis is whole;
 * anything else (both readings of a pair on one axis, or every pair of an
 * axis touched) cannot, and the frame is rejected (the task then coasts).
 * Readings are hi/lo pairs as in diff2d.h.
 */
#ifndef GGINS_FDI3D_H
#define GGINS_FDI3D_H

#include <stdint.h>
#include "ggins/real.h"
#include "ggins/status.h"

/** Reading index in masks: bit (3 * sensor + axis), sensor 0..5, axis 0..2. */
#define GG_FDI3D_BIT(sensor, axis) (1u << ((3u * (uint32_t)(sensor)) + (uint32_t)(axis)))

typedef struct {
    gg_real_t mean_good[3][3]; /**< pair means m[p][j] of the last frame used (a rebuilt pair keeps
                                    the difference of its last whole frame), m/s^2 */
    int have_good;             /**< such a frame has been seen */
    int initialized;
} gg_fdi3d_t;

gg_status_t gg_fdi3d_init(gg_fdi3d_t *st);

/** Rebuild the readings of known_bad (GG_FDI3D_BIT mask; their values are
 *  ignored) in f/f_lo in place; *rebuilt = the readings rebuilt. With
 *  known_bad = 0 only the pair means are remembered. GG_ERR_SENSOR when the
 *  set cannot be accommodated (f, f_lo and the state untouched);
 *  GG_ERR_NONFINITE when a reading not marked bad is not finite. */
gg_status_t gg_fdi3d_step(gg_fdi3d_t *st, uint32_t known_bad, double f[6][3], double f_lo[6][3],
                          uint32_t *rebuilt);

#endif /* GGINS_FDI3D_H */
