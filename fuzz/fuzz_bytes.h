/* Shared by the libFuzzer harnesses that read structured inputs: a cursor
 * over the fuzzer's bytes (reads past the end give 0). */
#ifndef GGINS_FUZZ_BYTES_H
#define GGINS_FUZZ_BYTES_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct {
    const uint8_t *p;
    size_t n;
    size_t off;
} fz_cur_t;

static int fz_left(const fz_cur_t *c) { return c->off < c->n; }

static uint8_t fz_u8(fz_cur_t *c)
{
    return c->off < c->n ? c->p[c->off++] : 0u;
}

static double fz_f64(fz_cur_t *c)
{
    uint8_t b[8] = {0};
    for (int i = 0; i < 8; ++i) b[i] = fz_u8(c);
    double d;
    memcpy(&d, b, sizeof d);
    return d;
}

static int64_t fz_i64(fz_cur_t *c)
{
    uint8_t b[8] = {0};
    for (int i = 0; i < 8; ++i) b[i] = fz_u8(c);
    int64_t v;
    memcpy(&v, b, sizeof v);
    return v;
}

/* a double that is either raw bits (NaN, Inf, denormals, huge) or a small
 * multiplicative / additive change of a reference value */
static double fz_value(fz_cur_t *c, double ref)
{
    const uint8_t how = fz_u8(c);
    switch (how & 3u) {
    case 0: return fz_f64(c);
    case 1: return ref * (1.0 + (double)(int8_t)fz_u8(c) * 1e-3);
    case 2: return ref + (double)(int8_t)fz_u8(c) * 1e-9;
    default: return ref + (double)(int16_t)(fz_u8(c) | (fz_u8(c) << 8)) * 1e-12;
    }
}

#endif
