/* SPDX-License-Identifier: MIT */
/* c4g-sim fault injection on its own packets (--drop ... --entry-fault). The random
 * draws happen in a fixed order, so the same --seed gives the same faults. */
#include <string.h>

#include "app.h"

const char *const fault_names[F_COUNT] = {"drop", "delay", "duplicate", "reorder", "corrupt",
                                          "truncate"};

/* The fault generator's draws (it is seeded in app_start, so they cannot fail). */
static uint64_t draw(app_t *a)
{
    uint64_t x = 0U;
    (void)c4gsim_rng_next(&a->frng, &x);
    return x;
}

static int roll(app_t *a, enum fault f)
{
    double u = 1.0;
    if (!(a->o.fault_frac[f] > 0.0)) {
        return 0;
    }
    (void)c4gsim_rng_uniform(&a->frng, &u);
    return u < a->o.fault_frac[f];
}

static void queue_pending(app_t *a, const uint8_t *buf, size_t len, uint64_t due)
{
    int i;
    for (i = 0; i < MAX_PENDING; i++) {
        if (!a->pend[i].used) {
            a->pend[i].used = 1;
            a->pend[i].due_ns = due;
            a->pend[i].len = len;
            memcpy(a->pend[i].buf, buf, len);
            return;
        }
    }
    (void)raw_send(a, buf, len, NULL); /* queue full: send now */
}

/* 1 if this cyclic packet is the first to carry a new mode on some axis. */
static int mode_entry(app_t *a, const uint8_t *pkt, size_t len)
{
    int entry = 0;
    size_t i;
    for (i = 0; i < C4G_MAX_AXES && C4G_CYCLIC_SIZE(i + 1U) <= len; i++) {
        const int32_t m = c4g_le_i32(&pkt[C4G_HEADER_SIZE + C4G_AXIS_SIZE * i]);
        if (m != a->sent_modes[i]) {
            entry = 1;
            a->sent_modes[i] = m;
        }
    }
    return entry;
}

/* --entry-fault and --drop: 1 if the packet is lost; the entry fault may cut *len. */
static int lost(app_t *a, const uint8_t *pkt, size_t *len)
{
    if (a->cs.out.kind == C4G_PKT_CYCLIC && mode_entry(a, pkt, *len) && a->o.entry_fault != 0) {
        /* the packet that opens a mode is lost or cut: the PC must not anchor on it */
        if (a->o.entry_fault == 1) {
            a->st.fault[F_DROP]++;
            return 1;
        }
        *len = *len / 2U;
        a->st.fault[F_TRUNCATE]++;
    }
    if (roll(a, F_DROP)) {
        a->st.fault[F_DROP]++;
        return 1;
    }
    return 0;
}

/* --corrupt and --truncate. */
static void damage(app_t *a, uint8_t *buf, size_t *len)
{
    if (roll(a, F_CORRUPT)) {
        const size_t at = (size_t)(draw(a) % *len);
        buf[at] ^= (uint8_t)(1U + draw(a) % 255U);
        a->st.fault[F_CORRUPT]++;
    }
    if (roll(a, F_TRUNCATE)) {
        *len = (size_t)(draw(a) % *len);
        a->st.fault[F_TRUNCATE]++;
    }
}

/* --reorder, --delay, --duplicate, or plain: 1 if it went out now; *held_now if it waits
 * for the next packet. */
static int dispatch(app_t *a, const uint8_t *buf, size_t len, uint32_t *key, int *held_now)
{
    int now = 0;
    if (roll(a, F_REORDER) && !a->held.used) {
        a->held.used = 1;
        a->held.len = len;
        memcpy(a->held.buf, buf, len);
        a->st.fault[F_REORDER]++;
        *held_now = 1;
    } else if (roll(a, F_DELAY)) {
        queue_pending(a, buf, len, now_ns() + (uint64_t)a->o.delay_us * 1000U);
        a->st.fault[F_DELAY]++;
    } else {
        now = raw_send(a, buf, len, key);
        if (roll(a, F_DUP)) {
            (void)raw_send(a, buf, len, NULL);
            a->st.fault[F_DUP]++;
        }
    }
    return now;
}

/* Send one of our packets through fault injection. Returns 1 (and the datagram's
 * SO_TIMESTAMPING id in @p key) if it went out now, unaltered in time. */
int send_packet(app_t *a, const uint8_t *pkt, size_t len, uint32_t *key)
{
    uint8_t buf[C4G_INIT_SIZE];
    int held_now = 0;
    int now = 0;
    memcpy(buf, pkt, len);
    a->st.sent++;
    if (!lost(a, pkt, &len)) {
        damage(a, buf, &len);
        if (a->cs.out.kind == C4G_PKT_INIT && len == C4G_INIT_SIZE && a->cs.out.len == C4G_INIT_SIZE) {
            /* the PC echoes what went on the wire: a --corrupt byte is not a PC's own limit */
            memcpy(a->cs.out.raw, buf, C4G_INIT_SIZE);
        }
        now = dispatch(a, buf, len, key, &held_now);
    }
    if (a->held.used && !held_now) {
        (void)raw_send(a, a->held.buf, a->held.len, NULL);
        a->held.used = 0;
    }
    return now;
}
