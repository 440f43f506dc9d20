/*
 * hal_sim: the firmware's HAL (gg_hal_t, firmware/include/ggins/hal.h)
 * implemented over LCM for host-in-the-loop runs.
 *
 * It receives the navigation configuration (GGINS_CONFIG) and sensor frames
 * (GGINS_FRAME) from the run tool, steps the firmware with
 * gg_nav2d_task_cycle once per frame, in seq order, and publishes each
 * navigation output (GGINS_NAV). Its own state and transport counters go out
 * on GGINS_HAL. It is a thin adapter: validation and fault handling of the
 * sensor data belong to the firmware.
 *
 * Transport: frames come alone (GGINS_FRAME, sensor_frame_t) or several per
 * message (GGINS_FRAMES, frame_batch_t: batched lockstep); they are put back
 * in seq order through a reorder window and each is stepped once. The
 * outputs of batched frames leave as batches (GGINS_NAVS nav_output_batch_t,
 * GGINS_NAV3DS nav3d_output_batch_t): one per message handled, or when
 * OUT_BATCH are ready; the outputs of frames that came alone leave alone
 * (GGINS_NAV, GGINS_NAV3D).
 * A frame that arrives again after it was used is a duplicate: its cached
 * output (the last WINDOW are kept) is published again (the sender may have
 * lost it) and the firmware is not stepped twice. A gap (a later frame
 * arrived first) is answered at once with a negative acknowledgement
 * (GGINS_NAK, resend_request_t: the missing seqs as ranges), repeated while a
 * frame stays missing, every --gap-timeout-ms doubled per request (up to 64
 * times: a busy sender is not a lost frame); after --max-resend requests
 * for the same frame it is declared lost and skipped (the firmware then sees
 * the seq gap and flags it). Frames that reach the firmware as
 * retransmissions (resent > 0) are counted as recovered.
 *
 * Redundancy after a loss: a sender that knows of a loss re-carries each
 * batch's frames in its next batch (resent = -1, a copy, not a request); while
 * it does, the negative acknowledgement of a gap waits until the next batch of
 * copies has come without the frame. A copy of a frame already used is not
 * answered. After a request for lost outputs (run_control_t OUTPUT_COPIES on
 * P+CONTROL: answered from the output ring) or a frame resent for a used seq,
 * each output batch re-carries the previous batch's outputs (republished = -1)
 * for --output-redundancy-steps steps. Counted in hal_status_t.
 *
 * Cycle counter: CLOCK_MONOTONIC in ns truncated to uint32 (the firmware
 * takes differences modulo 2^32), cycles_per_second = 1e9.
 *
 * Authentication: every message carries a MAC (bus_auth.h) under the run's
 * secret key, which hal_sim reads from an inherited pipe (--key-fd N; the run
 * tool writes the key into it and closes it). A message of this run whose MAC
 * does not verify is counted per channel (auth_failed_*) and dropped. A
 * second authenticated frame for a seq already taken (buffered or used) is
 * compared by content with the copy kept (encodings with the transport fields and
 * the MAC zeroed, compared only when a second copy comes): the same
 * content is a duplicate, different content a conflict (frames_conflict:
 * counted, dropped, never flown, and never answered with the output of the
 * first). The same for a second configuration (config_conflict).
 *
 * 3-D mode: a configuration on GGINS_CONFIG3D (nav3d_config_t)
 * instead of GGINS_CONFIG selects the 3-D task: gg_nav3d_init, then
 * gg_nav3d_task_cycle per frame, outputs (nav3d_output_t) on GGINS_NAV3D
 * through the HAL's write_output3d. Frames, control, status, transport and
 * duplicate handling are the same as in 2-D.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <getopt.h>
#include <lcm/lcm.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include "bus_auth.h"
#include "ggins/hal.h"
#include "ggins/nav2d.h"
#include "hal_lcm.h"
#include "hal_lcm3d.h"
#include "hal_map.h"
#include "ggins/nav3d.h"
#include "ggins_hal_status_t.h"
#include "ggins_nav2d_config_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_run_control_t.h"
#include "ggins_sensor_frame_t.h"
#include "ggins_frame_batch_t.h"
#include "ggins_nav_output_batch_t.h"
#include "ggins_nav3d_output_batch_t.h"
#include "ggins_resend_request_t.h"

_Static_assert(GG_MOD_COUNT <= 8, "ggins_nav_output_t.cycles holds 8 modules");

#define WINDOW 8192 /* reorder window, frames (power of two); > the runners' largest window */
#define MAX_MSG 4096
#define OUT_BATCH 64   /* first publications per output batch at most */
#define OB_CAP (2 * OUT_BATCH + 8) /* an output batch: its outputs, conflicts, answers, copies of the previous */
#define BATCH_BUF 262144 /* encoded output batch */
#define RED_SPAN 8192  /* steps of redundancy after a loss (outputs re-carried in the next batch) */
#define COPY_ATTEMPT 1000u /* fault-injection transmission index of a redundant output copy */
#define NAK_RANGES 128 /* ranges per negative acknowledgement */

typedef struct {
    int valid;
    int resent;    /* the copy held is a retransmission */
    int requested; /* hal_sim asked for it */
    int batched;   /* it came in a frame batch: its output goes into an output batch */
    int from_copy; /* the copy held is a redundant copy (resent < 0): the first transmission was lost */
    int64_t gap_batch; /* copy-carrying batches received when its gap was seen (its NAK waits for the next) */
    int64_t req_seq;  /* seq the request state below belongs to (-1 none) */
    int req_count;    /* requests sent for req_seq */
    double req_time;  /* when the last was sent */
    gg_frame_t frame;
    int64_t taken_seq;          /* seq of the frame kept in `taken` (-1 none) */
    ggins_sensor_frame_t taken; /* the authenticated message taken for that seq */
} slot_t;

typedef struct {
    /* options */
    const char *url;     /* inbound: configuration, control, frames */
    const char *url_out; /* outbound: outputs, status, requests (NULL: same as url) */
    char ch_frame[96], ch_nav[96], ch_config[96], ch_control[96], ch_request[96], ch_hal[96];
    char ch_nav3d[96], ch_config3d[96];
    char ch_frames[96], ch_navs[96], ch_nav3ds[96], ch_nak[96];
    int64_t run_id;
    int gap_timeout_ms;
    int max_resend;
    double idle_timeout_s;
    int quiet;
    double drop_output_prob; /* fault injection */
    double conflict_output_prob; /* fault injection: a second, different, signed output for a seq */
    uint64_t inject_seed;
    int key_fd;
    ggins_bus_key_t key;

    lcm_t *lcm;     /* inbound (subscribed) */
    lcm_t *lcm_out; /* outbound (publish only; == lcm in single-URL mode) */
    gg_nav2d_t nav;
    gg_nav3d_t nav3d;
    int mode3d; /* 1: configured by GGINS_CONFIG3D (3-D task) */
    gg_hal_t hal;

    int32_t state;
    int32_t init_status;
    int64_t config_seq;
    ggins_nav2d_config_t config2d; /* the configuration message applied (2-D or 3-D) */
    ggins_nav3d_config_t config3d;
    int stop;

    /* reorder window */
    slot_t slots[WINDOW];
    int64_t next;      /* next seq for the firmware */
    int64_t highest;   /* highest seq seen */
    int64_t gap_seq;   /* seq currently missing (-1 none) */

    /* recent outputs, for duplicates (the sender may have lost our answer) */
    ggins_nav_output_t last_out;
    int have_last_out;
    ggins_nav_output_t out_ring[WINDOW];
    uint8_t out_valid[WINDOW];
    ggins_nav3d_output_t out3_ring[WINDOW]; /* 3-D mode */

    /* output batch under construction (answers to batched frames) */
    ggins_nav_output_t ob2[OB_CAP];
    ggins_nav3d_output_t ob3[OB_CAP];
    int ob_n;
    /* redundancy after a loss: the seqs first published in the batch under
     * construction (cur) and in the previous one (prev, re-carried in the next
     * batch while next < out_red_until) */
    int64_t cur_seqs[OUT_BATCH + 8], prev_seqs[OUT_BATCH + 8];
    int cur_n, prev_n;
    int64_t out_red_until;
    int64_t out_red_span; /* --output-redundancy-steps */
    int64_t batches_rx;      /* frame batches received */
    int64_t last_copy_batch; /* the last that carried redundant copies (-1 none) */
    int64_t copy_batches_rx; /* frame batches received that carried redundant copies */
    int cur_batched;  /* the frame being stepped came in a batch */
    int64_t out_batch_seq, nak_seq;
    uint8_t bbuf[BATCH_BUF];

    ggins_hal_status_t st;
    int64_t status_seq, request_seq;
    double last_rx_wall;
    double last_status_wall;
    uint8_t buf[MAX_MSG];
    uint8_t tmp[2][32768]; /* re-encodings for content comparisons (a 2-D configuration is ~18 KB) */
} hal_sim_t;

static volatile sig_atomic_t g_signal = 0;

/* Fault injection: a uniform deviate in [0, 1) that is a pure function of its inputs. */
static uint64_t mix64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

static int inject_drop(const hal_sim_t *h, int64_t seq, uint64_t attempt);
static int64_t wall_us(void);
static int inject_conflict(const hal_sim_t *h, int64_t seq);

/* Sign the n encoded bytes in h->buf for the channel and publish them. */
static int publish_signed(hal_sim_t *h, const char *channel, int n)
{
    if (n < 0 || ggins_bus_sign(&h->key, channel, h->buf, (size_t)n) != 0) return -1;
    return lcm_publish(h->lcm_out, channel, h->buf, (unsigned)n) == 0 ? 0 : -1;
}

/* The output batch under construction goes out (one signed message on
 * P+NAVS or P+NAV3DS); nothing when it is empty. */
static int flush_outputs(hal_sim_t *h)
{
    /* after a loss, the previous batch's outputs are re-carried (republished
     * = -1): a lost one usually reaches the sender without a request */
    if (h->next < h->out_red_until) {
        for (int i = 0; i < h->prev_n && h->ob_n < OB_CAP; ++i) {
            const int64_t q = h->prev_seqs[i];
            const int64_t r = q & (WINDOW - 1);
            if (!h->out_valid[r]) continue;
            if (h->mode3d ? h->out3_ring[r].seq != q : h->out_ring[r].seq != q) continue;
            if (inject_drop(h, q, COPY_ATTEMPT)) {
                h->st.output_copies_dropped_injected++;
                continue;
            }
            if (h->mode3d) {
                h->ob3[h->ob_n] = h->out3_ring[r];
                h->ob3[h->ob_n].republished = -1;
                memset(h->ob3[h->ob_n].mac, 0, sizeof h->ob3[h->ob_n].mac);
            } else {
                h->ob2[h->ob_n] = h->out_ring[r];
                h->ob2[h->ob_n].republished = -1;
                memset(h->ob2[h->ob_n].mac, 0, sizeof h->ob2[h->ob_n].mac);
            }
            h->ob_n++;
            h->st.output_copies_sent++;
        }
    }
    memcpy(h->prev_seqs, h->cur_seqs, sizeof h->prev_seqs[0] * (size_t)h->cur_n);
    h->prev_n = h->cur_n;
    h->cur_n = 0;
    if (h->ob_n == 0) return 0;
    int n;
    const char *ch;
    if (h->mode3d) {
        ggins_nav3d_output_batch_t b;
        memset(&b, 0, sizeof b);
        b.utime = wall_us();
        b.seq = h->out_batch_seq++;
        b.run_id = h->run_id;
        b.n = h->ob_n;
        b.outputs = h->ob3;
        n = ggins_nav3d_output_batch_t_encode(h->bbuf, 0, BATCH_BUF, &b);
        ch = h->ch_nav3ds;
    } else {
        ggins_nav_output_batch_t b;
        memset(&b, 0, sizeof b);
        b.utime = wall_us();
        b.seq = h->out_batch_seq++;
        b.run_id = h->run_id;
        b.n = h->ob_n;
        b.outputs = h->ob2;
        n = ggins_nav_output_batch_t_encode(h->bbuf, 0, BATCH_BUF, &b);
        ch = h->ch_navs;
    }
    h->ob_n = 0;
    if (n < 0 || ggins_bus_sign(&h->key, ch, h->bbuf, (size_t)n) != 0) return -1;
    return lcm_publish(h->lcm_out, ch, h->bbuf, (unsigned)n) == 0 ? 0 : -1;
}

/* One output to its receiver: alone on P+NAV3D, or (batched) into the output
 * batch. Fault injection (a dropped output, a second different one) applies
 * to each output either way. */
static int publish_output3d(hal_sim_t *h, const ggins_nav3d_output_t *m, uint64_t attempt, int batched)
{
    if (batched && attempt == 0) h->cur_seqs[h->cur_n++] = m->seq; /* re-carried after a loss, dropped or not */
    if (inject_drop(h, m->seq, attempt)) {
        h->st.outputs_dropped_injected++;
        return batched && h->cur_n >= OUT_BATCH ? flush_outputs(h) : 0;
    }
    const int conflict = attempt == 0 && inject_conflict(h, m->seq); /* a sender contradicting itself */
    ggins_nav3d_output_t other = *m;
    other.r_e[0] += 1e-3;
    if (conflict) h->st.outputs_conflict_injected++;
    if (batched) {
        h->ob3[h->ob_n] = *m;
        memset(h->ob3[h->ob_n].mac, 0, sizeof h->ob3[h->ob_n].mac);
        h->ob_n++;
        if (conflict) {
            h->ob3[h->ob_n] = other;
            memset(h->ob3[h->ob_n].mac, 0, sizeof other.mac);
            h->ob_n++;
        }
        return h->ob_n >= OUT_BATCH || h->cur_n >= OUT_BATCH ? flush_outputs(h) : 0;
    }
    if (publish_signed(h, h->ch_nav3d, ggins_nav3d_output_t_encode(h->buf, 0, MAX_MSG, m)) != 0) return -1;
    if (conflict) return publish_signed(h, h->ch_nav3d, ggins_nav3d_output_t_encode(h->buf, 0, MAX_MSG, &other));
    return 0;
}

static int publish_output(hal_sim_t *h, const ggins_nav_output_t *m, uint64_t attempt, int batched)
{
    if (batched && attempt == 0) h->cur_seqs[h->cur_n++] = m->seq; /* re-carried after a loss, dropped or not */
    if (inject_drop(h, m->seq, attempt)) {
        h->st.outputs_dropped_injected++;
        return batched && h->cur_n >= OUT_BATCH ? flush_outputs(h) : 0;
    }
    const int conflict = attempt == 0 && inject_conflict(h, m->seq); /* a sender contradicting itself */
    ggins_nav_output_t other = *m;
    other.r_i[0] += 1e-3;
    if (conflict) h->st.outputs_conflict_injected++;
    if (batched) {
        h->ob2[h->ob_n] = *m;
        memset(h->ob2[h->ob_n].mac, 0, sizeof h->ob2[h->ob_n].mac);
        h->ob_n++;
        if (conflict) {
            h->ob2[h->ob_n] = other;
            memset(h->ob2[h->ob_n].mac, 0, sizeof other.mac);
            h->ob_n++;
        }
        return h->ob_n >= OUT_BATCH || h->cur_n >= OUT_BATCH ? flush_outputs(h) : 0;
    }
    if (publish_signed(h, h->ch_nav, ggins_nav_output_t_encode(h->buf, 0, MAX_MSG, m)) != 0) return -1;
    if (conflict) return publish_signed(h, h->ch_nav, ggins_nav_output_t_encode(h->buf, 0, MAX_MSG, &other));
    return 0;
}
static void on_signal(int sig) { g_signal = sig; }

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int64_t wall_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static int inject_drop(const hal_sim_t *h, int64_t seq, uint64_t attempt)
{
    if (!(h->drop_output_prob > 0.0)) return 0;
    const uint64_t x = mix64(mix64(h->inject_seed ^ 0x6f7574ull) ^ (uint64_t)seq) ^ mix64(attempt + 1);
    return (double)(mix64(x) >> 11) * 0x1.0p-53 < h->drop_output_prob;
}

static int inject_conflict(const hal_sim_t *h, int64_t seq)
{
    if (!(h->conflict_output_prob > 0.0)) return 0;
    const uint64_t x = mix64(mix64(h->inject_seed ^ 0x636f6e66ull) ^ (uint64_t)seq);
    return (double)(mix64(x) >> 11) * 0x1.0p-53 < h->conflict_output_prob;
}

/* ---- HAL operations ---------------------------------------------------- */

static gg_status_t hal_read_frame(void *ctx, gg_frame_t *frame)
{
    hal_sim_t *h = ctx;
    slot_t *s = &h->slots[h->next & (WINDOW - 1)];
    if (!s->valid || s->frame.seq != h->next) return GG_ERR_NO_DATA;
    *frame = s->frame;
    if (s->resent) h->st.frames_recovered++; /* the copy that got through was a retransmission */
    if (s->from_copy) h->st.frames_from_copies++; /* ... or a redundant copy */
    h->cur_batched = s->batched;
    s->valid = 0;
    if (h->gap_seq == h->next) h->gap_seq = -1;
    h->next++;
    return GG_OK;
}

static gg_status_t hal_write_output(void *ctx, const gg_nav_output_t *o)
{
    hal_sim_t *h = ctx;
    ggins_nav_output_t *m = &h->last_out;
    ggins_output_to_lcm(o, h->run_id, m); /* hal_lcm.c: shared with ggins replay */
    h->have_last_out = 1;
    h->out_ring[o->seq & (WINDOW - 1)] = *m;
    h->out_valid[o->seq & (WINDOW - 1)] = 1;
    h->st.steps++;
    if (o->status != GG_OK) h->st.steps_rejected++;
    if (o->health & GG_HEALTH_DEADLINE) h->st.deadline_overruns++;
    return publish_output(h, m, 0, h->cur_batched) == 0 ? GG_OK : GG_ERR_IO;
}

static gg_status_t hal_write_output3d(void *ctx, const struct gg_nav3d_output_s *o)
{
    hal_sim_t *h = ctx;
    ggins_nav3d_output_t *m = &h->out3_ring[o->seq & (WINDOW - 1)];
    ggins_output3d_to_lcm(o, h->run_id, m); /* hal_lcm3d.c */
    h->out_valid[o->seq & (WINDOW - 1)] = 1;
    h->st.steps++;
    if (o->status != GG_OK) h->st.steps_rejected++;
    if (o->health & GG_HEALTH_DEADLINE) h->st.deadline_overruns++;
    return publish_output3d(h, m, 0, h->cur_batched) == 0 ? GG_OK : GG_ERR_IO;
}

static uint32_t hal_cycle_count(void *ctx)
{
    (void)ctx;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint32_t)((uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec);
}

/* ---- messages out -------------------------------------------------------- */

static void publish_status(hal_sim_t *h)
{
    h->st.utime = wall_us();
    h->st.seq = h->status_seq++;
    h->st.run_id = h->run_id;
    h->st.state = h->state;
    h->st.init_status = h->init_status;
    h->st.config_seq = h->config_seq;
    h->st.next_seq = h->next;
    publish_signed(h, h->ch_hal, ggins_hal_status_t_encode(h->buf, 0, MAX_MSG, &h->st));
    h->last_status_wall = now_s();
}

/* ---- messages in --------------------------------------------------------- */

/* The checks every inbound message passes, in this order: it decodes, to
 * exactly its size (else decode_errors); it is of this run (else
 * foreign_messages); its MAC verifies under the run's key (else *auth_failed).
 * 1: process it; 0: it was counted and is dropped. */
static int accept_msg(hal_sim_t *h, const lcm_recv_buf_t *rb, const char *channel, int decoded, int64_t run_id,
                      int64_t *auth_failed)
{
    if (decoded < 0 || (uint32_t)decoded != rb->data_size) {
        h->st.decode_errors++;
        return 0;
    }
    if (run_id != h->run_id) {
        h->st.foreign_messages++;
        return 0;
    }
    if (ggins_bus_verify(&h->key, channel, rb->data, rb->data_size) != 0) {
        (*auth_failed)++;
        return 0;
    }
    return 1;
}

/* Whether two authenticated messages for one seq have the same content: their
 * encodings with the transport fields (zeroed by the caller) and the MAC zeroed
 * are equal. Only called when a second copy comes. */
#define SAME_CONTENT(h, type, a, b)                                                    \
    (memset((a).mac, 0, sizeof (a).mac), memset((b).mac, 0, sizeof (b).mac),           \
     same_bytes(type##_encode((h)->tmp[0], 0, (int)sizeof (h)->tmp[0], &(a)),          \
                type##_encode((h)->tmp[1], 0, (int)sizeof (h)->tmp[1], &(b)), (h)))

static int same_bytes(int na, int nb, const hal_sim_t *h)
{
    return na > 0 && na == nb && memcmp(h->tmp[0], h->tmp[1], (size_t)na) == 0;
}

static int same_frame(hal_sim_t *h, ggins_sensor_frame_t a, ggins_sensor_frame_t b)
{
    a.resent = b.resent = 0; /* differs between transmissions of one frame */
    return SAME_CONTENT(h, ggins_sensor_frame_t, a, b);
}

static void report_conflict(hal_sim_t *h, const char *what, int64_t seq, int64_t count)
{
    if (!h->quiet && count <= 10)
        fprintf(stderr, "hal_sim: conflict: a second authenticated %s for seq %lld with different content; dropped%s\n",
                what, (long long)seq, count == 10 ? " (further conflicts counted only)" : "");
}

/* The output of step s (already stepped, kept in the ring) published again,
 * as an answer (republished counts the answers). */
static void republish(hal_sim_t *h, int64_t s, int batched)
{
    if (s < 0 || !h->out_valid[s & (WINDOW - 1)]) return;
    if (h->mode3d) {
        ggins_nav3d_output_t *o3 = &h->out3_ring[s & (WINDOW - 1)];
        if (o3->seq != s) return;
        if (o3->republished < 127) o3->republished++;
        publish_output3d(h, o3, (uint64_t)o3->republished, batched);
    } else {
        ggins_nav_output_t *o = &h->out_ring[s & (WINDOW - 1)];
        if (o->seq != s) return;
        if (o->republished < 127) o->republished++;
        publish_output(h, o, (uint64_t)o->republished, batched);
    }
    h->st.outputs_republished++;
}

/* An authenticated frame of this run (alone, or one of a batch). A redundant
 * copy (resent < 0: re-carried by the sender after a loss, unasked) fills a
 * gap like any transmission, but a copy of a frame already used is no
 * request: it is not answered. */
static void take_frame(hal_sim_t *h, ggins_sensor_frame_t m, int batched)
{
    h->st.frames_received++;
    if (h->state != GGINS_HAL_STATUS_T_CONFIGURED && h->state != GGINS_HAL_STATUS_T_RUNNING)
        return; /* not configured yet: the sender resends on timeout */
    const int64_t s = m.seq;
    const int copy = m.resent < 0;
    if (copy) h->st.frame_copies_received++;
    if (s < h->next) {
        const slot_t *used = s >= 0 ? &h->slots[s & (WINDOW - 1)] : NULL;
        if (used && used->taken_seq == s && !same_frame(h, used->taken, m)) {
            report_conflict(h, "frame", s, ++h->st.frames_conflict);
            return;
        }
        if (copy) return;
        h->st.frames_duplicate++;
        /* the sender probably lost our answer; a retransmission says the link loses:
         * the outputs are re-carried for a while */
        if (m.resent > 0) h->out_red_until = h->next + h->out_red_span;
        republish(h, s, batched);
        return;
    }
    if (s >= h->next + WINDOW) { /* too far ahead to hold; the sender will resend */
        h->st.frames_out_of_order++;
        return;
    }
    slot_t *sl = &h->slots[s & (WINDOW - 1)];
    if (sl->valid && sl->frame.seq == s) {
        if (sl->taken_seq == s && !same_frame(h, sl->taken, m))
            report_conflict(h, "frame", s, ++h->st.frames_conflict);
        else if (!copy)
            h->st.frames_duplicate++;
        return;
    }
    if (s > h->next) h->st.frames_out_of_order++;
    const int requested = (sl->req_seq == s);
    memset(sl, 0, sizeof *sl);
    ggins_frame_from_lcm(&m, &sl->frame); /* hal_lcm.c: shared with ggins replay */
    sl->valid = 1;
    sl->batched = batched;
    sl->req_seq = -1;
    sl->resent = m.resent > 0;
    sl->from_copy = copy;
    sl->requested = requested;
    sl->taken_seq = s;
    sl->taken = m;
    if (s > h->highest) h->highest = s;
}

static void on_frame(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    hal_sim_t *h = user;
    ggins_sensor_frame_t m;
    h->last_rx_wall = now_s();
    const int dec = ggins_sensor_frame_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m);
    if (!accept_msg(h, rbuf, channel, dec, dec >= 0 ? m.run_id : -1, &h->st.auth_failed_frame)) return;
    take_frame(h, m, 0);
}

/* A batch of frames: checked as one message (decode, run, MAC), then each
 * frame as if it had come alone, in the batch's order; an inner frame of
 * another run is foreign. */
static void on_frame_batch(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    hal_sim_t *h = user;
    ggins_frame_batch_t b;
    h->last_rx_wall = now_s();
    const int dec = ggins_frame_batch_t_decode(rbuf->data, 0, (int)rbuf->data_size, &b);
    if (accept_msg(h, rbuf, channel, dec, dec >= 0 ? b.run_id : -1, &h->st.auth_failed_frame)) {
        h->batches_rx++;
        for (int i = 0; i < b.n; ++i)
            if (b.frames[i].resent < 0) {
                h->last_copy_batch = h->batches_rx;
                h->copy_batches_rx++;
                break;
            }
        for (int i = 0; i < b.n; ++i) {
            if (b.frames[i].run_id != h->run_id) {
                h->st.foreign_messages++;
                continue;
            }
            take_frame(h, b.frames[i], 1);
        }
    }
    if (dec >= 0) ggins_frame_batch_t_decode_cleanup(&b);
}

static void on_config(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    hal_sim_t *h = user;
    ggins_nav2d_config_t m;
    h->last_rx_wall = now_s();
    const int dec = ggins_nav2d_config_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m);
    if (!accept_msg(h, rbuf, channel, dec, dec >= 0 ? m.run_id : -1, &h->st.auth_failed_config)) return;
    if (h->state != GGINS_HAL_STATUS_T_IDLE) {
        /* Already configured: a repeat of the same configuration (our status was lost)
         * is answered with the status again; a new one is refused; a different one
         * with the seq of the one applied is a conflict. */
        if (m.seq == h->config_seq && (h->mode3d || !SAME_CONTENT(h, ggins_nav2d_config_t, m, h->config2d)))
            report_conflict(h, "configuration", m.seq, ++h->st.config_conflict);
        publish_status(h);
        return;
    }
    h->config2d = m;
    gg_nav2d_config_t c;
    /* message -> firmware configuration: hal_lcm.c (shared with ggins replay;
     * add new configuration fields there) */
    ggins_config_from_lcm(&m, &c);
    gg_status_t rc = gg_nav2d_init(&h->nav, &c);
    h->init_status = (int32_t)rc;
    h->config_seq = m.seq;
    if (rc == GG_OK) {
        h->state = GGINS_HAL_STATUS_T_CONFIGURED;
    } else if (!h->quiet) {
        fprintf(stderr, "hal_sim: gg_nav2d_init refused the configuration (status %d)\n", (int)rc);
    }
    publish_status(h);
}

static void on_config3d(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    hal_sim_t *h = user;
    ggins_nav3d_config_t m;
    h->last_rx_wall = now_s();
    const int dec = ggins_nav3d_config_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m);
    if (!accept_msg(h, rbuf, channel, dec, dec >= 0 ? m.run_id : -1, &h->st.auth_failed_config)) return;
    if (h->state != GGINS_HAL_STATUS_T_IDLE) { /* as on_config: repeat answered, new one refused, conflict counted */
        if (m.seq == h->config_seq && (!h->mode3d || !SAME_CONTENT(h, ggins_nav3d_config_t, m, h->config3d)))
            report_conflict(h, "configuration", m.seq, ++h->st.config_conflict);
        publish_status(h);
        return;
    }
    h->config3d = m;
    gg_nav3d_config_t c;
    ggins_config3d_from_lcm(&m, &c); /* hal_lcm3d.c */
    gg_status_t rc = gg_nav3d_init(&h->nav3d, &c);
    h->init_status = (int32_t)rc;
    h->config_seq = m.seq;
    if (rc == GG_OK) {
        h->state = GGINS_HAL_STATUS_T_CONFIGURED;
        h->mode3d = 1;
    } else if (!h->quiet) {
        fprintf(stderr, "hal_sim: gg_nav3d_init refused the configuration (status %d)\n", (int)rc);
    }
    publish_status(h);
}

static void on_control(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    hal_sim_t *h = user;
    ggins_run_control_t m;
    h->last_rx_wall = now_s();
    const int dec = ggins_run_control_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m);
    if (!accept_msg(h, rbuf, channel, dec, dec >= 0 ? m.run_id : -1, &h->st.auth_failed_control)) return;
    if (m.command == GGINS_RUN_CONTROL_T_START) {
        if (h->state == GGINS_HAL_STATUS_T_CONFIGURED) h->state = GGINS_HAL_STATUS_T_RUNNING;
        publish_status(h);
    } else if (m.command == GGINS_RUN_CONTROL_T_STOP) {
        h->state = GGINS_HAL_STATUS_T_STOPPED;
        h->stop = 1;
        publish_status(h);
    } else if (m.command == GGINS_RUN_CONTROL_T_OUTPUT_COPIES) {
        /* outputs lost on the way: published again, and the following ones
         * re-carried for a while (the link loses) */
        h->st.output_copy_requests++;
        h->out_red_until = h->next + h->out_red_span;
        const int64_t count = m.n_steps < 0 ? 0 : (m.n_steps > WINDOW ? WINDOW : m.n_steps);
        for (int64_t s = m.resend_seq; s < m.resend_seq + count && s < h->next; ++s)
            if (s >= 0 && s + WINDOW > h->next) republish(h, s, 1);
    }
}

/* ---- gap handling -------------------------------------------------------- */

/* Negative acknowledgement: every frame between next and the highest seq
 * seen that is not here is asked for at once (one P+NAK message of ranges),
 * and again while it stays missing (backoff()); after
 * --max-resend requests the frame at next is declared lost and skipped. */
static void send_nak(hal_sim_t *h, const int64_t *first, const int32_t *count, int n)
{
    ggins_resend_request_t r;
    memset(&r, 0, sizeof r);
    r.utime = wall_us();
    r.seq = h->nak_seq++;
    r.run_id = h->run_id;
    r.next_seq = h->next;
    r.n = n;
    r.first = (int64_t *)first;
    r.count = (int32_t *)count;
    publish_signed(h, h->ch_nak, ggins_resend_request_t_encode(h->buf, 0, MAX_MSG, &r));
}

/* The wait before the next request for a frame asked for n times: the
 * interval doubled per request up to 64 times (2 ms .. 128 ms; 50 requests
 * take ~6 s), so that a sender descheduled for a while on a busy machine is
 * not mistaken for a lost frame. */
static double backoff(double interval, int n)
{
    int e = n - 1;
    if (e < 0) e = 0;
    if (e > 6) e = 6;
    return interval * (double)(1 << e);
}

static void handle_gaps(hal_sim_t *h)
{
    if (h->highest < h->next) { /* nothing ahead: no gap */
        h->gap_seq = -1;
        return;
    }
    const double t = now_s();
    const double interval = 1e-3 * h->gap_timeout_ms;
    {
        slot_t *sn = &h->slots[h->next & (WINDOW - 1)];
        if (sn->req_seq == h->next && sn->req_count >= h->max_resend && t - sn->req_time >= backoff(interval, sn->req_count)) {
            h->st.frames_lost++; /* give up on it */
            if (!h->quiet) fprintf(stderr, "hal_sim: frame %lld lost after %d resend requests\n",
                                   (long long)h->next, sn->req_count);
            sn->valid = 0;
            sn->req_seq = -1;
            h->next++;
            h->gap_seq = -1;
            return;
        }
    }
    h->gap_seq = h->next;
    /* the sender re-carries each frame in its next batch (redundancy after a
     * loss): a gap is asked for only when that copy did not come either */
    const int sender_redundant = h->last_copy_batch >= 0 && h->batches_rx - h->last_copy_batch <= 8;
    int64_t first[NAK_RANGES];
    int32_t count[NAK_RANGES];
    int n = 0;
    for (int64_t s = h->next; s < h->highest && s < h->next + WINDOW; ++s) {
        slot_t *sl = &h->slots[s & (WINDOW - 1)];
        if (sl->valid && sl->frame.seq == s) continue;
        if (sl->req_seq != s) {
            sl->req_seq = s;
            sl->req_count = 0;
            if (sender_redundant) { /* its copy comes with the next batch of copies: no request yet */
                sl->gap_batch = h->copy_batches_rx;
                sl->req_time = t;
                h->st.naks_deferred++;
                continue;
            }
        } else if (sl->req_count == 0 && h->copy_batches_rx > sl->gap_batch) {
            /* the next batch of copies came without it: lost twice, asked for */
        } else if (t - sl->req_time < backoff(interval, sl->req_count)) {
            continue; /* asked for recently (or its copy is still on the way) */
        }
        sl->req_count++;
        sl->req_time = t;
        sl->requested = 1;
        h->st.resend_requests++;
        if (n > 0 && first[n - 1] + count[n - 1] == s) {
            count[n - 1]++;
        } else {
            if (n == NAK_RANGES) {
                send_nak(h, first, count, n);
                n = 0;
            }
            first[n] = s;
            count[n] = 1;
            n++;
        }
    }
    if (n > 0) send_nak(h, first, count, n);
}

/* ---- main ------------------------------------------------------------------ */

static void usage(FILE *out)
{
    fprintf(out,
            "usage: hal_sim --run-id N --key-fd FD [options]\n\n"
            "The ggins firmware's HAL over LCM: receives the configuration and sensor\n"
            "frames of one run, steps the firmware (gg_nav2d_task_cycle) once per frame in\n"
            "seq order, publishes every navigation output. Normally started by `ggins run`.\n"
            "A configuration on P+CONFIG3D instead of P+CONFIG selects the 3-D task\n"
            "(gg_nav3d_task_cycle, outputs on P+NAV3D; started by `ggins run3d`).\n\n"
            "options:\n"
            "  --lcm-url URL          LCM URL hal_sim listens on (default: LCM_DEFAULT_URL or LCM's default)\n"
            "  --lcm-url-out URL      LCM URL for what hal_sim publishes (default: the same); a second\n"
            "                         URL spares each process receiving its own traffic\n"
            "  --prefix P             channel prefix (default GGINS_): P+FRAME, P+FRAMES, P+NAV, P+NAVS,\n"
            "                         P+CONFIG, P+CONTROL, P+NAK, P+HAL, P+CONFIG3D, P+NAV3D, P+NAV3DS\n"
            "  --run-id N             run nonce; messages with another run_id are ignored (required)\n"
            "  --key-fd FD            read the run's 32-byte secret key from this inherited descriptor\n"
            "                         (a pipe the run tool wrote and closed), then close it (required).\n"
            "                         Every message is authenticated with it (keyed BLAKE2b-256, libsodium):\n"
            "                         ours carry its MAC, theirs are dropped and counted when theirs fails\n"
            "  --gap-timeout-ms MS    a missing frame is asked for at once (P+NAK), again every MS ms (default 20)\n"
            "  --max-resend N         requests per missing frame before it is declared lost (default 50)\n"
            "  --idle-timeout-s S     exit (status 3) after S s without a message (default 60)\n"
            "  --drop-output-prob P   fault injection: do not send an output with probability P\n"
            "  --conflict-output-prob P  fault injection: after an output, a second, different, signed\n"
            "                         output for the same seq with probability P (a conflict)\n"
            "  --inject-seed N        seed of the fault injection (default 1)\n"
            "  --output-redundancy-steps N  after a lost output (a request for it), re-carry each output\n"
            "                         batch's outputs in the next one for N steps (default 8192; 0: never)\n"
            "  --map FILE             a gradient map tile (gmap format) for the computer's map storage,\n"
            "                         read by the 3-D task's map aid; repeat for more tiles (up to 256)\n"
            "  --quiet                no diagnostics on stderr\n"
            "  --help                 this text\n\n"
            "exit status: 0 after STOP, 1 bad usage, no key or LCM failure, 3 idle timeout, 4 signal\n");
}

int main(int argc, char **argv)
{
    static hal_sim_t h; /* large (reorder window): static storage */
    const char *prefix = "GGINS_";
    h.url = NULL;
    h.run_id = -1;
    h.gap_timeout_ms = 20;
    h.max_resend = 50;
    h.out_red_span = RED_SPAN;
    h.idle_timeout_s = 60.0;
    static const struct option opts[] = {
        {"lcm-url", required_argument, 0, 'u'}, {"lcm-url-out", required_argument, 0, 'o'},
        {"prefix", required_argument, 0, 'p'},
        {"run-id", required_argument, 0, 'r'}, {"gap-timeout-ms", required_argument, 0, 'g'},
        {"max-resend", required_argument, 0, 'm'}, {"idle-timeout-s", required_argument, 0, 'i'},
        {"quiet", no_argument, 0, 'q'}, {"help", no_argument, 0, 'h'},
        {"drop-output-prob", required_argument, 0, 'd'}, {"inject-seed", required_argument, 0, 's'},
        {"key-fd", required_argument, 0, 'k'}, {"conflict-output-prob", required_argument, 0, 'c'},
        {"map", required_argument, 0, 'M'}, {"output-redundancy-steps", required_argument, 0, 'R'}, {0, 0, 0, 0}};
    static hal_map_store_t maps; /* the computer's map storage (hal_map.c) */
    hal_map_init(&maps);
    int c;
    h.inject_seed = 1;
    h.key_fd = -1;
    while ((c = getopt_long(argc, argv, "u:o:p:r:g:m:i:qhd:s:k:c:M:R:", opts, NULL)) != -1) {
        char *end = NULL;
        switch (c) {
        case 'u': h.url = optarg; break;
        case 'o': h.url_out = optarg; break;
        case 'p': prefix = optarg; break;
        case 'r': h.run_id = strtoll(optarg, &end, 0); if (*end) goto bad; break;
        case 'g': h.gap_timeout_ms = (int)strtol(optarg, &end, 0); if (*end || h.gap_timeout_ms <= 0) goto bad; break;
        case 'm': h.max_resend = (int)strtol(optarg, &end, 0); if (*end || h.max_resend < 0) goto bad; break;
        case 'i': h.idle_timeout_s = strtod(optarg, &end); if (*end || !(h.idle_timeout_s > 0)) goto bad; break;
        case 'q': h.quiet = 1; break;
        case 'd': h.drop_output_prob = strtod(optarg, &end); if (*end || !(h.drop_output_prob >= 0.0 && h.drop_output_prob < 1.0)) goto bad; break;
        case 's': h.inject_seed = strtoull(optarg, &end, 0); if (*end) goto bad; break;
        case 'c': h.conflict_output_prob = strtod(optarg, &end); if (*end || !(h.conflict_output_prob >= 0.0 && h.conflict_output_prob < 1.0)) goto bad; break;
        case 'R': h.out_red_span = strtoll(optarg, &end, 0); if (*end || h.out_red_span < 0) goto bad; break;
        case 'k': h.key_fd = (int)strtol(optarg, &end, 0); if (*end || h.key_fd < 0) goto bad; break;
        case 'M': {
            char err[512];
            if (hal_map_load(&maps, optarg, err, sizeof err) != 0) {
                fprintf(stderr, "hal_sim: --map %s\n", err);
                return 1;
            }
            break;
        }
        case 'h': usage(stdout); return 0;
        default: usage(stderr); return 1;
        }
        continue;
    bad:
        fprintf(stderr, "hal_sim: bad value '%s' for option -%c\n", optarg, c);
        return 1;
    }
    if (optind != argc || h.run_id < 0) {
        fprintf(stderr, "hal_sim: --run-id N (N >= 0) is required and no positional arguments are taken\n");
        usage(stderr);
        return 1;
    }
    /* The key: no core dump, no ptrace or /proc/<pid>/fd|mem access by other
     * processes of the same user (the process is not dumpable) */
    prctl(PR_SET_DUMPABLE, 0);
    if (h.key_fd < 0) {
        fprintf(stderr, "hal_sim: --key-fd FD is required (the run's key; ggins run and ggins run3d pass it)\n");
        return 1;
    }
    {
        const char *why = "";
        if (ggins_bus_init() != 0) {
            fprintf(stderr, "hal_sim: libsodium cannot be initialised\n");
            return 1;
        }
        if (ggins_bus_key_read_fd(h.key_fd, &h.key, &why) != 0) {
            fprintf(stderr, "hal_sim: cannot read the key from descriptor %d: %s\n", h.key_fd, why);
            return 1;
        }
    }
    for (int i = 0; i < WINDOW; ++i) {
        h.slots[i].taken_seq = -1;
        h.slots[i].req_seq = -1;
        h.slots[i].gap_batch = -1;
    }
    h.last_copy_batch = -1;
    if (strlen(prefix) > 80) {
        fprintf(stderr, "hal_sim: prefix too long\n");
        return 1;
    }
    snprintf(h.ch_frame, sizeof h.ch_frame, "%sFRAME", prefix);
    snprintf(h.ch_nav, sizeof h.ch_nav, "%sNAV", prefix);
    snprintf(h.ch_config, sizeof h.ch_config, "%sCONFIG", prefix);
    snprintf(h.ch_control, sizeof h.ch_control, "%sCONTROL", prefix);
    snprintf(h.ch_request, sizeof h.ch_request, "%sREQUEST", prefix);
    snprintf(h.ch_hal, sizeof h.ch_hal, "%sHAL", prefix);
    snprintf(h.ch_nav3d, sizeof h.ch_nav3d, "%sNAV3D", prefix);
    snprintf(h.ch_config3d, sizeof h.ch_config3d, "%sCONFIG3D", prefix);
    snprintf(h.ch_frames, sizeof h.ch_frames, "%sFRAMES", prefix);
    snprintf(h.ch_navs, sizeof h.ch_navs, "%sNAVS", prefix);
    snprintf(h.ch_nav3ds, sizeof h.ch_nav3ds, "%sNAV3DS", prefix);
    snprintf(h.ch_nak, sizeof h.ch_nak, "%sNAK", prefix);

    prctl(PR_SET_PDEATHSIG, SIGTERM); /* do not outlive the run tool */
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);

    h.lcm = lcm_create(h.url);
    if (!h.lcm) {
        fprintf(stderr, "hal_sim: cannot create LCM (url %s); is multicast on loopback enabled?\n"
                        "  fix (as root): ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo\n",
                h.url ? h.url : "(default)");
        return 1;
    }
    h.lcm_out = h.lcm;
    if (h.url_out && (!h.url || strcmp(h.url_out, h.url) != 0)) {
        h.lcm_out = lcm_create(h.url_out);
        if (!h.lcm_out) {
            fprintf(stderr, "hal_sim: cannot create LCM (url %s)\n", h.url_out);
            lcm_destroy(h.lcm);
            return 1;
        }
    }
    lcm_subscription_t *sf = lcm_subscribe(h.lcm, h.ch_frame, on_frame, &h);
    lcm_subscription_set_queue_capacity(sf, 100000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(h.lcm, h.ch_frames, on_frame_batch, &h), 100000);
    /* room for a burst of forged messages, so that it cannot push the genuine ones out of the queue */
    lcm_subscription_set_queue_capacity(lcm_subscribe(h.lcm, h.ch_config, on_config, &h), 10000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(h.lcm, h.ch_config3d, on_config3d, &h), 10000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(h.lcm, h.ch_control, on_control, &h), 10000);

    h.hal.ctx = &h;
    h.hal.read_frame = hal_read_frame;
    h.hal.write_output = hal_write_output;
    h.hal.cycle_count = hal_cycle_count;
    h.hal.write_output3d = hal_write_output3d;
    h.hal.map = maps.n_tiles > 0 ? &maps.ops : NULL;
    h.hal.cycles_per_second = 1000000000u;
    h.state = GGINS_HAL_STATUS_T_IDLE;
    h.init_status = -1;
    h.config_seq = -1;
    h.next = 0;
    h.highest = -1;
    h.gap_seq = -1;
    h.last_rx_wall = now_s();
    publish_status(&h);

    int rc = 0;
    while (!h.stop) {
        if (g_signal) { rc = 4; break; }
        const int wait_ms = (h.state == GGINS_HAL_STATUS_T_IDLE) ? 50 : h.gap_timeout_ms;
        int r = lcm_handle_timeout(h.lcm, wait_ms);
        if (r < 0) {
            if (errno == EINTR) continue;
            fprintf(stderr, "hal_sim: lcm_handle_timeout failed\n");
            rc = 1;
            break;
        }
        /* step the firmware for every frame that is ready, in seq order */
        if (h.state == GGINS_HAL_STATUS_T_CONFIGURED || h.state == GGINS_HAL_STATUS_T_RUNNING) {
            for (;;) {
                const slot_t *s = &h.slots[h.next & (WINDOW - 1)];
                if (!s->valid || s->frame.seq != h.next) break;
                if (h.mode3d) {
                    gg_nav3d_task_cycle(&h.nav3d, &h.hal);
                } else {
                    gg_nav2d_task_cycle(&h.nav, &h.hal);
                }
            }
            handle_gaps(&h);
            if (flush_outputs(&h) != 0 && !h.quiet) fprintf(stderr, "hal_sim: publishing an output batch failed\n");
        }
        const double t = now_s();
        if (h.state == GGINS_HAL_STATUS_T_IDLE ? t - h.last_status_wall > 0.05 : t - h.last_status_wall > 1.0)
            publish_status(&h);
        if (t - h.last_rx_wall > h.idle_timeout_s) {
            if (!h.quiet) fprintf(stderr, "hal_sim: no message for %.0f s, exiting\n", h.idle_timeout_s);
            rc = 3;
            break;
        }
    }
    if (h.stop) {
        /* linger briefly: answer a repeated STOP (our status may have been lost) */
        const double t_end = now_s() + 0.2;
        while (now_s() < t_end && !g_signal) lcm_handle_timeout(h.lcm, 50);
    }
    if (h.lcm_out != h.lcm) lcm_destroy(h.lcm_out);
    lcm_destroy(h.lcm);
    ggins_bus_key_wipe(&h.key);
    return rc;
}
