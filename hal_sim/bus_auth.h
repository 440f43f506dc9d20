/*
 * Message authentication on the host-in-the-loop bus (hal_sim <-> ggins run /
 * ggins run3d). One implementation, used by both sides.
 *
 * Each run has a secret key of GGINS_BUS_KEY_BYTES random bytes
 * (ggins_bus_key_new: libsodium's randombytes_buf), made by the run tool and
 * handed to hal_sim through an inherited pipe (--key-fd): never on a command
 * line, in the environment, in a file or in the LCM log.
 *
 * Every message type of the run ends with `byte mac[32]`, so in the LCM
 * encoding the last GGINS_BUS_MAC_BYTES bytes are the MAC. It is
 *
 *   BLAKE2b-256 keyed with the run's key (RFC 7693 keyed mode; libsodium
 *   crypto_generichash) of
 *     "ggins-bus" 0x00 || u32be(|channel|) || channel || u32be(n - 32) || encoded[0 .. n - 32)
 *
 * i.e. over the channel name and every byte of the encoded message (LCM type
 * fingerprint included) except the MAC field itself. Binding the channel
 * means a message of one channel cannot be replayed on another (run_control_t
 * travels on CONTROL and REQUEST). A message whose MAC does not verify comes
 * from a sender without the key: the receiver counts and drops it.
 *
 * A repeat of a message is told from a different message for the same seq (a
 * conflict) by the receiver (hal_sim.c, hil_common.hpp): their encodings with
 * the transport fields (resent / republished) and the MAC zeroed are compared.
 */
#ifndef GGINS_BUS_AUTH_H
#define GGINS_BUS_AUTH_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GGINS_BUS_KEY_BYTES 32
#define GGINS_BUS_MAC_BYTES 32

typedef struct {
    uint8_t k[GGINS_BUS_KEY_BYTES];
} ggins_bus_key_t;

/** Initialise libsodium; 0 on success, -1 if it cannot be used. */
int ggins_bus_init(void);

/** A fresh random key (libsodium randombytes_buf). */
void ggins_bus_key_new(ggins_bus_key_t *key);

/** Read exactly GGINS_BUS_KEY_BYTES from fd, then require end of file, and
 *  close fd. 0 on success, -1 (and errno-style message in *why) otherwise. */
int ggins_bus_key_read_fd(int fd, ggins_bus_key_t *key, const char **why);

/** A pipe holding the key, ready to be inherited: returns its read end (with
 *  FD_CLOEXEC set, so only a child given it explicitly, e.g. by dup2 in
 *  posix_spawn, receives it) or -1. The write end is written and closed. */
int ggins_bus_key_pipe(const ggins_bus_key_t *key);

/** Overwrite the key with zeros (sodium_memzero). */
void ggins_bus_key_wipe(ggins_bus_key_t *key);

/** Sign an encoded message in place: buf[0 .. n) is the LCM encoding, its
 *  last GGINS_BUS_MAC_BYTES bytes the mac field, which receive the MAC.
 *  0 on success, -1 if n is too short. */
int ggins_bus_sign(const ggins_bus_key_t *key, const char *channel, uint8_t *buf, size_t n);

/** Verify a received encoded message (layout as for ggins_bus_sign); constant
 *  time in the MAC comparison. 0 when the MAC is right, -1 otherwise. */
int ggins_bus_verify(const ggins_bus_key_t *key, const char *channel, const uint8_t *buf, size_t n);

#ifdef __cplusplus
}
#endif

#endif /* GGINS_BUS_AUTH_H */
