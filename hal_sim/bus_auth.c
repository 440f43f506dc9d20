/* Message authentication on the host-in-the-loop bus: see bus_auth.h. */
#define _GNU_SOURCE
#include "bus_auth.h"

#include <errno.h>
#include <fcntl.h>
#include <sodium.h>
#include <string.h>
#include <unistd.h>

static const char kDomain[] = "ggins-bus"; /* sent with its terminating NUL */

int ggins_bus_init(void) { return sodium_init() < 0 ? -1 : 0; }

void ggins_bus_key_new(ggins_bus_key_t *key) { randombytes_buf(key->k, sizeof key->k); }

void ggins_bus_key_wipe(ggins_bus_key_t *key) { sodium_memzero(key->k, sizeof key->k); }

int ggins_bus_key_read_fd(int fd, ggins_bus_key_t *key, const char **why)
{
    size_t got = 0;
    int rc = -1;
    *why = "short read (fewer than 32 key bytes)";
    while (got < sizeof key->k) {
        const ssize_t r = read(fd, key->k + got, sizeof key->k - got);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) {
            *why = strerror(errno);
            goto out;
        }
        if (r == 0) goto out;
        got += (size_t)r;
    }
    {
        uint8_t extra;
        ssize_t r;
        do r = read(fd, &extra, 1);
        while (r < 0 && errno == EINTR);
        if (r != 0) {
            *why = r > 0 ? "more than 32 bytes on the key descriptor" : strerror(errno);
            goto out;
        }
    }
    rc = 0;
    *why = "";
out:
    close(fd);
    if (rc != 0) ggins_bus_key_wipe(key);
    return rc;
}

int ggins_bus_key_pipe(const ggins_bus_key_t *key)
{
    int p[2];
    if (pipe2(p, O_CLOEXEC) != 0) return -1;
    size_t put = 0;
    while (put < sizeof key->k) { /* 32 bytes < PIPE_BUF: one write, never blocks */
        const ssize_t w = write(p[1], key->k + put, sizeof key->k - put);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            close(p[0]);
            close(p[1]);
            return -1;
        }
        put += (size_t)w;
    }
    close(p[1]);
    return p[0];
}

static void mac_of(const ggins_bus_key_t *key, const char *channel, const uint8_t *buf, size_t body,
                   uint8_t out[GGINS_BUS_MAC_BYTES])
{
    crypto_generichash_state st;
    const size_t lc = strlen(channel);
    const uint8_t lcb[4] = {(uint8_t)(lc >> 24), (uint8_t)(lc >> 16), (uint8_t)(lc >> 8), (uint8_t)lc};
    const uint8_t lbb[4] = {(uint8_t)(body >> 24), (uint8_t)(body >> 16), (uint8_t)(body >> 8), (uint8_t)body};
    crypto_generichash_init(&st, key->k, sizeof key->k, GGINS_BUS_MAC_BYTES);
    crypto_generichash_update(&st, (const unsigned char *)kDomain, sizeof kDomain);
    crypto_generichash_update(&st, lcb, sizeof lcb);
    crypto_generichash_update(&st, (const unsigned char *)channel, lc);
    crypto_generichash_update(&st, lbb, sizeof lbb);
    crypto_generichash_update(&st, buf, body);
    crypto_generichash_final(&st, out, GGINS_BUS_MAC_BYTES);
    sodium_memzero(&st, sizeof st);
}

int ggins_bus_sign(const ggins_bus_key_t *key, const char *channel, uint8_t *buf, size_t n)
{
    if (n < GGINS_BUS_MAC_BYTES || n - GGINS_BUS_MAC_BYTES > 0xffffffffu) return -1;
    mac_of(key, channel, buf, n - GGINS_BUS_MAC_BYTES, buf + (n - GGINS_BUS_MAC_BYTES));
    return 0;
}

int ggins_bus_verify(const ggins_bus_key_t *key, const char *channel, const uint8_t *buf, size_t n)
{
    if (n < GGINS_BUS_MAC_BYTES || n - GGINS_BUS_MAC_BYTES > 0xffffffffu) return -1;
    uint8_t want[GGINS_BUS_MAC_BYTES];
    mac_of(key, channel, buf, n - GGINS_BUS_MAC_BYTES, want);
    const int ok = crypto_verify_32(want, buf + (n - GGINS_BUS_MAC_BYTES)) == 0;
    sodium_memzero(want, sizeof want);
    return ok ? 0 : -1;
}
