/* Seeded random generator (see ggrand.h). */
#include "ggins/ggrand.h"

#include <stddef.h>

#include "ggins/ggmath.h"

gg_status_t gg_rng_seed(gg_rng_t *r, uint64_t seed)
{
    uint64_t z = seed;
    int i;
    if (r == NULL) {
        return GG_ERR_NULL;
    }
    for (i = 0; i < 4; ++i) { /* splitmix64 */
        uint64_t t;
        z += 0x9E3779B97F4A7C15ull;
        t = z;
        t = (t ^ (t >> 30)) * 0xBF58476D1CE4E5B9ull;
        t = (t ^ (t >> 27)) * 0x94D049BB133111EBull;
        r->s[i] = t ^ (t >> 31);
    }
    return GG_OK;
}

static uint64_t rotl64(uint64_t x, uint32_t k)
{
    const uint32_t rk = 64u - k;
    return (x << k) | (x >> rk);
}

gg_status_t gg_rng_u64(gg_rng_t *r, uint64_t *v)
{
    uint64_t t;
    if ((r == NULL) || (v == NULL)) {
        return GG_ERR_NULL;
    }
    *v = rotl64(r->s[1] * 5u, 7u) * 9u; /* xoshiro256** */
    t = r->s[1] << 17;
    r->s[2] ^= r->s[0];
    r->s[3] ^= r->s[1];
    r->s[1] ^= r->s[2];
    r->s[0] ^= r->s[3];
    r->s[2] ^= t;
    r->s[3] = rotl64(r->s[3], 45u);
    return GG_OK;
}

gg_status_t gg_rng_uniform(gg_rng_t *r, double *u)
{
    uint64_t v = 0;
    gg_status_t s;
    if (u == NULL) {
        return GG_ERR_NULL;
    }
    s = gg_rng_u64(r, &v);
    if (s != GG_OK) {
        return s;
    }
    *u = (double)(v >> 11) * (1.0 / 9007199254740992.0);
    return GG_OK;
}

gg_status_t gg_rng_normal(gg_rng_t *r, double *z)
{
    int k;
    if ((r == NULL) || (z == NULL)) {
        return GG_ERR_NULL;
    }
    /* Marsaglia polar method; acceptance pi/4, so 64 tries fail with p < 1e-42 */
    for (k = 0; k < 64; ++k) {
        double u = 0.0;
        double v = 0.0;
        double q;
        double lq = 0.0;
        gg_status_t s = gg_rng_uniform(r, &u);
        if (s == GG_OK) {
            s = gg_rng_uniform(r, &v);
        }
        if (s != GG_OK) {
            return s;
        }
        u = (2.0 * u) - 1.0;
        v = (2.0 * v) - 1.0;
        q = (u * u) + (v * v);
        if ((q > 0.0) && (q < 1.0)) {
            s = gg_log_d(q, &lq);
            if (s != GG_OK) {
                return s;
            }
            *z = u * gg_sqrt_d(-2.0 * lq / q);
            return GG_OK;
        }
    }
    return GG_ERR_RANGE;
}
