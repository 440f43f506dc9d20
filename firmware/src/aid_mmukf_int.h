/* The gradient-map aid's units shared between its source files (aid_mmukf.c:
 * configuration, start and the real-time schedule; aid_mmukf_dyn.c: the error
 * dynamics, the UKF's process model; aid_mmukf_meas.c: the measurement model and
 * the epoch's averaging window). Internal to the firmware library. */
#ifndef GGINS_AID_MMUKF_INT_H
#define GGINS_AID_MMUKF_INT_H

#include <string.h>

#include "ggins/aid_mmukf.h"

#define NXM GG_UKF_NX_MAX

static inline void mat_identity(int32_t n, double m[NXM][NXM])
{
    int32_t j;
    int32_t k;
    for (j = 0; j < NXM; ++j) {
        for (k = 0; k < NXM; ++k) {
            m[j][k] = 0.0;
        }
        if (j < n) {
            m[j][j] = 1.0;
        }
    }
}

static inline void mat_zero(double m[NXM][NXM])
{
    (void)memset(m, 0, sizeof(double) * (size_t)NXM * (size_t)NXM);
}

/* The measurement model's context: the aid whose epoch is being updated. */
typedef struct {
    const gg_aid_mm_t *a;
} aid_hctx_t;

/* Empty the epoch's averaging window. */
void aid_mm_window_reset(gg_aid_mm_t *a);

/* Accumulate one navigation step's transition and process noise (A h, Q h). */
gg_status_t aid_mm_propagate(gg_aid_mm_t *a, const gg_aid_ins_t *ins);

/* Predict through the accumulated interval, then restart the accumulation. */
gg_status_t aid_mm_predict_accumulated(gg_aid_mm_t *a);

/* UKF measurement model (ctx: aid_hctx_t): the epoch's six tensor components for error state x. */
gg_status_t aid_mm_meas_model(void *ctx, const double *x, double *z);

/* Add this step's sample to the epoch's window. */
void aid_mm_window_add(gg_aid_mm_t *a, const gg_aid_ins_t *ins);

/* The epoch's measurement and R from the window. */
void aid_mm_window_epoch(gg_aid_mm_t *a, const gg_aid_ins_t *ins);

#endif /* GGINS_AID_MMUKF_INT_H */
