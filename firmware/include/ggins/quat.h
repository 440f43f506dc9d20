/**
 * @file quat.h
 * @brief Quaternion and 3x3 matrix algebra of the firmware, in gg_real_t.
 *
 * Conventions (docs/design.md): quaternions are scalar first, q = (w, x, y, z);
 * a unit quaternion q_a_b rotates vectors of frame a into frame b,
 * v_b = q_a_b (x) (0, v_a) (x) q_a_b*, and its direction-cosine matrix
 * C_a_b = gg_quat_to_dcm(q_a_b) does the same (v_b = C_a_b v_a). Products
 * compose left to right as the frames do: q_a_c = q_b_c (x) q_a_b.
 * Rotation vectors th (rad): q = Exp(th) = (cos |th|/2, sin(|th|/2) th/|th|).
 * R3(theta) = [[c, -s, 0], [s, c, 0], [0, 0, 1]] is the rotation about z
 * (the Earth's rotation between ECEF and ECI, nav3d.h).
 * Matrices are row-major gg_real_t m[3][3]; functions taking a matrix that
 * they only read take a non-const pointer, since C11 does not convert
 * gg_real_t (*)[3] to const gg_real_t (*)[3] implicitly (gg_mat3_t wraps a
 * matrix whose const rows a caller can pass).
 *
 * Header-only (static inline): the navigation step calls these in its
 * inner loops, where a call per product would cost more than the product.
 * Every operation is written once here; the order of the floating-point
 * operations is part of the definition (results are bit-reproducible).
 */
#ifndef GGINS_QUAT_H
#define GGINS_QUAT_H

#include <stddef.h>

#include "ggins/ggmath.h"
#include "ggins/real.h"
#include "ggins/status.h"

/** Smallest |q|^2 gg_quat_normalize accepts (a drifted unit quaternion is
 *  within 1e-6 of 1; below 0.5 the attitude is lost, not drifted). */
#define GG_QUAT_NORM2_MIN 0.5L

/** A 3x3 matrix in a struct: a pointer to a const one yields const rows. */
typedef struct {
    gg_real_t m[3][3];
} gg_mat3_t;

/** a . b */
static inline gg_real_t gg_vec3_dot(const gg_real_t a[3], const gg_real_t b[3])
{
    return (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2]);
}

/** o = p (x) q (o may alias p or q). */
static inline void gg_quat_mul(const gg_real_t p[4], const gg_real_t q[4], gg_real_t o[4])
{
    const gg_real_t w = (p[0] * q[0]) - (p[1] * q[1]) - (p[2] * q[2]) - (p[3] * q[3]);
    const gg_real_t x = (p[0] * q[1]) + (p[1] * q[0]) + (p[2] * q[3]) - (p[3] * q[2]);
    const gg_real_t y = (p[0] * q[2]) - (p[1] * q[3]) + (p[2] * q[0]) + (p[3] * q[1]);
    const gg_real_t z = (p[0] * q[3]) + (p[1] * q[2]) - (p[2] * q[1]) + (p[3] * q[0]);
    o[0] = w;
    o[1] = x;
    o[2] = y;
    o[3] = z;
}

/** o = q* (the inverse of a unit quaternion). */
static inline void gg_quat_conj(const gg_real_t q[4], gg_real_t o[4])
{
    o[0] = q[0];
    o[1] = -q[1];
    o[2] = -q[2];
    o[3] = -q[3];
}

/** Direction-cosine matrix of a unit quaternion: C_a_b of q_a_b. */
static inline void gg_quat_to_dcm(const gg_real_t q[4], gg_real_t c[3][3])
{
    const gg_real_t w = q[0];
    const gg_real_t x = q[1];
    const gg_real_t y = q[2];
    const gg_real_t z = q[3];
    c[0][0] = 1.0L - (2.0L * ((y * y) + (z * z)));
    c[0][1] = 2.0L * ((x * y) - (w * z));
    c[0][2] = 2.0L * ((x * z) + (w * y));
    c[1][0] = 2.0L * ((x * y) + (w * z));
    c[1][1] = 1.0L - (2.0L * ((x * x) + (z * z)));
    c[1][2] = 2.0L * ((y * z) - (w * x));
    c[2][0] = 2.0L * ((x * z) - (w * y));
    c[2][1] = 2.0L * ((y * z) + (w * x));
    c[2][2] = 1.0L - (2.0L * ((x * x) + (y * y)));
}

/** q <- q / |q|. GG_ERR_RANGE (q untouched) when |q|^2 is not finite or
 *  below GG_QUAT_NORM2_MIN. */
static inline gg_status_t gg_quat_normalize(gg_real_t q[4])
{
    const gg_real_t n2 = (q[0] * q[0]) + (q[1] * q[1]) + (q[2] * q[2]) + (q[3] * q[3]);
    gg_real_t inv;
    size_t j;
    if (!GG_ISFINITE(n2) || !(n2 > GG_QUAT_NORM2_MIN)) {
        return GG_ERR_RANGE;
    }
    inv = 1.0L / sqrtl(n2);
    for (j = 0U; j < 4U; ++j) {
        q[j] *= inv;
    }
    return GG_OK;
}

/** q = Exp(th) for a rotation vector th (rad); below |th| = 1e-8 the
 *  second-order series (error ~|th|^4/384, below rounding). */
static inline gg_status_t gg_quat_from_rotvec(const gg_real_t th[3], gg_real_t q[4])
{
    const gg_real_t a2 = gg_vec3_dot(th, th);
    gg_real_t a;
    gg_real_t s;
    gg_real_t c;
    gg_status_t st;
    if (a2 < 1.0e-16L) {
        const gg_real_t k = 0.5L * (1.0L - (a2 / 24.0L));
        q[0] = 1.0L - (a2 / 8.0L);
        q[1] = k * th[0];
        q[2] = k * th[1];
        q[3] = k * th[2];
        return GG_OK;
    }
    a = sqrtl(a2);
    st = gg_sincos(0.5L * a, &s, &c);
    if (st == GG_OK) {
        q[0] = c;
        q[1] = (s * th[0]) / a;
        q[2] = (s * th[1]) / a;
        q[3] = (s * th[2]) / a;
    }
    return st;
}

/** th = Log(q) for a unit quaternion (the shorter rotation: q and -q give
 *  the same th, |th| <= pi); below |v| = 1e-9 the first-order series. */
static inline gg_status_t gg_quat_to_rotvec(const gg_real_t qin[4], gg_real_t th[3])
{
    const gg_real_t sg = (qin[0] < 0.0L) ? -1.0L : 1.0L;
    const gg_real_t v[3] = {sg * qin[1], sg * qin[2], sg * qin[3]};
    const gg_real_t w = sg * qin[0];
    const gg_real_t n = sqrtl(gg_vec3_dot(v, v));
    gg_real_t k;
    gg_status_t st = GG_OK;
    if (n < 1.0e-9L) {
        k = 2.0L / w;
    } else {
        gg_real_t ang = 0.0L;
        st = gg_atan2(n, w, &ang);
        k = (2.0L * ang) / n;
    }
    if (st == GG_OK) {
        th[0] = k * v[0];
        th[1] = k * v[1];
        th[2] = k * v[2];
    }
    return st;
}

/** y = C x */
static inline void gg_mat3_vec(gg_real_t c[3][3], const gg_real_t x[3], gg_real_t y[3])
{
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        y[j] = (c[j][0] * x[0]) + (c[j][1] * x[1]) + (c[j][2] * x[2]);
    }
}

/** y = C^T x */
static inline void gg_mat3_tvec(gg_real_t c[3][3], const gg_real_t x[3], gg_real_t y[3])
{
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        y[j] = (c[0][j] * x[0]) + (c[1][j] * x[1]) + (c[2][j] * x[2]);
    }
}

/** o = A B (o distinct from A and B) */
static inline void gg_mat3_mul(gg_real_t a[3][3], gg_real_t b[3][3], gg_real_t o[3][3])
{
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            o[j][k] = (a[j][0] * b[0][k]) + (a[j][1] * b[1][k]) + (a[j][2] * b[2][k]);
        }
    }
}

/** o = A^T (o distinct from A) */
static inline void gg_mat3_transpose(gg_real_t a[3][3], gg_real_t o[3][3])
{
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            o[j][k] = a[k][j];
        }
    }
}

/** dst = src */
static inline void gg_mat3_copy(gg_real_t src[3][3], gg_mat3_t *dst)
{
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            dst->m[j][k] = src[j][k];
        }
    }
}

/** o = C M C^T (a tensor's change of axes; o distinct from M). */
static inline void gg_mat3_similarity(gg_real_t c[3][3], const gg_real_t m[3][3], gg_real_t o[3][3])
{
    gg_real_t t[3][3];
    size_t j;
    size_t k;
    size_t l;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            t[j][k] = 0.0L;
            for (l = 0U; l < 3U; ++l) {
                t[j][k] += c[j][l] * m[l][k];
            }
        }
    }
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            o[j][k] = 0.0L;
            for (l = 0U; l < 3U; ++l) {
                o[j][k] += t[j][l] * c[k][l];
            }
        }
    }
}

/** o = R3(theta) v (sign > 0) or R3(-theta) v (sign < 0); (s, c) = sin,
 *  cos theta (o may alias v). */
static inline void gg_rot3(gg_real_t s, gg_real_t c, int sign, const gg_real_t v[3], gg_real_t o[3])
{
    const gg_real_t ss = (sign > 0) ? s : -s;
    const gg_real_t x = (c * v[0]) - (ss * v[1]);
    const gg_real_t y = (ss * v[0]) + (c * v[1]);
    o[0] = x;
    o[1] = y;
    o[2] = v[2];
}

/** m = R3(theta) (sign > 0) or R3(-theta) (sign < 0) as a matrix. */
static inline void gg_rot3_mat(gg_real_t s, gg_real_t c, int sign, gg_real_t m[3][3])
{
    const gg_real_t ss = (sign > 0) ? s : -s;
    m[0][0] = c;
    m[0][1] = -ss;
    m[0][2] = 0.0L;
    m[1][0] = ss;
    m[1][1] = c;
    m[1][2] = 0.0L;
    m[2][0] = 0.0L;
    m[2][1] = 0.0L;
    m[2][2] = 1.0L;
}

#endif /* GGINS_QUAT_H */
