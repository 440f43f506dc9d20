/*
 * Bus authentication (hal_sim/bus_auth.h).
 *
 * Independent truth: the MAC of a fixed message against values
 * computed with CPython's hashlib (its own BLAKE2 implementation), from the
 * layout documented in bus_auth.h:
 *   key = 00 01 .. 1f, channel "GGINS_FRAME", body[i] = (7 i + 3) mod 256, i < 100
 *   hashlib.blake2b(b"ggins-bus\0" + be32(11) + b"GGINS_FRAME" + be32(100) + body,
 *                   key=key, digest_size=32)
 * Then: any single flipped bit, another channel, another key or a truncation
 * fails verification; every LCM message type of the run ends with its mac
 * field (what signing in place relies on); the key pipe hands over exactly the
 * key and refuses a short or long one.
 */
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "bus_auth.h"
#include "ggins_hal_status_t.h"
#include "ggins_nav2d_config_t.h"
#include "ggins_nav3d_config_t.h"
#include "ggins_nav3d_output_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_run_control_t.h"
#include "ggins_sensor_frame_t.h"
#include "ggins_truth3d_t.h"
#include "ggins_truth_t.h"

#define BODY 100
#define N (BODY + GGINS_BUS_MAC_BYTES)

static void fixture(ggins_bus_key_t *k, uint8_t *buf)
{
    for (int i = 0; i < GGINS_BUS_KEY_BYTES; ++i) k->k[i] = (uint8_t)i;
    for (int i = 0; i < BODY; ++i) buf[i] = (uint8_t)((7 * i + 3) & 255);
    memset(buf + BODY, 0, GGINS_BUS_MAC_BYTES);
}

static void test_mac_matches_python_blake2b(void **state)
{
    (void)state;
    static const uint8_t want[32] = {0x70, 0x7b, 0x0d, 0x18, 0x92, 0x57, 0x04, 0xcb, 0x22, 0xb4, 0x91,
                                     0x9d, 0x10, 0xb1, 0xaf, 0x52, 0xee, 0xd4, 0xce, 0x8b, 0xbf, 0x01,
                                     0xaf, 0xa8, 0x46, 0xf0, 0x84, 0x73, 0xc6, 0x70, 0x80, 0x78};
    ggins_bus_key_t k;
    uint8_t buf[N];
    assert_int_equal(ggins_bus_init(), 0);
    fixture(&k, buf);
    assert_int_equal(ggins_bus_sign(&k, "GGINS_FRAME", buf, N), 0);
    assert_memory_equal(buf + BODY, want, 32);
    assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAME", buf, N), 0);
}

static void test_any_change_fails(void **state)
{
    (void)state;
    ggins_bus_key_t k, k2;
    uint8_t buf[N];
    fixture(&k, buf);
    ggins_bus_sign(&k, "GGINS_FRAME", buf, N);
    for (int i = 0; i < N; ++i)
        for (int b = 0; b < 8; ++b) { /* every single bit, body and MAC */
            buf[i] ^= (uint8_t)(1u << b);
            assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAME", buf, N), -1);
            buf[i] ^= (uint8_t)(1u << b);
        }
    assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAME", buf, N), 0);
    assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAMe", buf, N), -1);  /* another channel */
    assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAME2", buf, N), -1);
    assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAME", buf, N - 1), -1); /* truncated */
    assert_int_equal(ggins_bus_verify(&k, "GGINS_FRAME", buf, 31), -1);    /* shorter than a MAC */
    assert_int_equal(ggins_bus_sign(&k, "GGINS_FRAME", buf, 31), -1);
    k2 = k;
    k2.k[31] ^= 0x80; /* another key */
    assert_int_equal(ggins_bus_verify(&k2, "GGINS_FRAME", buf, N), -1);
    ggins_bus_key_new(&k2); /* a fresh random key differs from the fixed one and signs differently */
    assert_memory_not_equal(k2.k, k.k, GGINS_BUS_KEY_BYTES);
    assert_int_equal(ggins_bus_verify(&k2, "GGINS_FRAME", buf, N), -1);
}

/* Encode m with its mac set to a pattern; the encoding must end with it. */
#define CHECK_TAIL(type)                                                              \
    do {                                                                              \
        static type m;                                                                \
        static uint8_t enc[65536];                                                    \
        memset(&m, 0, sizeof m);                                                      \
        for (int i = 0; i < 32; ++i) m.mac[i] = (uint8_t)(0xA0 + i);                  \
        const int n = type##_encode(enc, 0, (int)sizeof enc, &m);                     \
        assert_true(n > 32);                                                          \
        assert_memory_equal(enc + n - 32, m.mac, 32);                                 \
    } while (0)

static void test_every_type_ends_with_its_mac(void **state)
{
    (void)state;
    CHECK_TAIL(ggins_sensor_frame_t);
    CHECK_TAIL(ggins_nav_output_t);
    CHECK_TAIL(ggins_nav3d_output_t);
    CHECK_TAIL(ggins_nav2d_config_t);
    CHECK_TAIL(ggins_nav3d_config_t);
    CHECK_TAIL(ggins_run_control_t);
    CHECK_TAIL(ggins_hal_status_t);
    CHECK_TAIL(ggins_truth_t);
    CHECK_TAIL(ggins_truth3d_t);
}

static int pipe_with(const uint8_t *b, size_t n)
{
    int p[2];
    if (pipe(p) != 0) return -1;
    if (write(p[1], b, n) != (ssize_t)n) return -1;
    close(p[1]);
    return p[0];
}

static void test_key_pipe(void **state)
{
    (void)state;
    ggins_bus_key_t k, got;
    const char *why = NULL;
    ggins_bus_key_new(&k);
    const int fd = ggins_bus_key_pipe(&k);
    assert_true(fd >= 0);
    assert_true(fcntl(fd, F_GETFD) & FD_CLOEXEC); /* inherited only where dup2'ed on purpose */
    assert_int_equal(ggins_bus_key_read_fd(fd, &got, &why), 0);
    assert_memory_equal(got.k, k.k, GGINS_BUS_KEY_BYTES);
    errno = 0;
    assert_int_equal(fcntl(fd, F_GETFD), -1); /* closed after reading */
    assert_int_equal(errno, EBADF);

    uint8_t b[33];
    memset(b, 7, sizeof b);
    assert_int_equal(ggins_bus_key_read_fd(pipe_with(b, 31), &got, &why), -1); /* short */
    assert_non_null(strstr(why, "short"));
    assert_int_equal(ggins_bus_key_read_fd(pipe_with(b, 33), &got, &why), -1); /* long */
    assert_non_null(strstr(why, "more than"));
    assert_int_equal(ggins_bus_key_read_fd(pipe_with(b, 32), &got, &why), 0);
    ggins_bus_key_wipe(&got);
    for (int i = 0; i < GGINS_BUS_KEY_BYTES; ++i) assert_int_equal(got.k[i], 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mac_matches_python_blake2b),
        cmocka_unit_test(test_any_change_fails),
        cmocka_unit_test(test_every_type_ends_with_its_mac),
        cmocka_unit_test(test_key_pipe),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
