/* The map-matching UKF's units shared between its source files (mmukf.c:
 * the filter; mmukf_nav.c: mechanization and error-state algebra).
 * Internal to the firmware library. */
#ifndef GGINS_MMUKF_INT_H
#define GGINS_MMUKF_INT_H

#include "ggins/mmukf.h"

/* 1 when every field is finite and lat, h within the filter's limits. */
int mm_nav_ok(const gg_mm_nav_t *x);

/* a = b (+) d, b already validated (gg_mm_apply checks it). */
gg_status_t mm_apply(const gg_mm_nav_t *b, const double *d, gg_mm_nav_t *a);

#endif /* GGINS_MMUKF_INT_H */
