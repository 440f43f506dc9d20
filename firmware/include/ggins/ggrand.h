/**
 * @file ggrand.h
 * @brief The firmware's seeded random generator: xoshiro256** (Blackman &
 *        Vigna 2018) seeded by four splitmix64 outputs of the 64-bit seed;
 *        uniform doubles from the top 53 bits, standard normals by
 *        Marsaglia's polar method (logarithm of ggmath.h, no libm).
 *
 * The state is the caller's (no hidden global): a filter holds its own
 * generator, and the same seed draws the same sequence on every target
 * (integer arithmetic; the normals use only +, *, / and gg_log_d, gg_sqrt_d).
 * The polar method accepts a pair with probability pi/4; 64 tries fail with
 * p < 1e-42 (GG_ERR_RANGE then).
 */
#ifndef GGINS_GGRAND_H
#define GGINS_GGRAND_H

#include <stdint.h>

#include "ggins/status.h"

typedef struct {
    uint64_t s[4];
} gg_rng_t;

/** Seed the generator (any 64-bit value). */
gg_status_t gg_rng_seed(gg_rng_t *r, uint64_t seed);
/** Next 64-bit output. */
gg_status_t gg_rng_u64(gg_rng_t *r, uint64_t *v);
/** Uniform in [0, 1), 53 bits. */
gg_status_t gg_rng_uniform(gg_rng_t *r, double *u);
/** Standard normal N(0, 1). */
gg_status_t gg_rng_normal(gg_rng_t *r, double *z);

#endif /* GGINS_GGRAND_H */
