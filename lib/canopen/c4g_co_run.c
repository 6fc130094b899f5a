/* SPDX-License-Identifier: MIT */
/* CANopen master at run time (step 7): SYNC and TxPDOs, RxPDOs into the process image,
   heartbeat consumer and node guarding, node loss, EMCY history. */
#include "c4gopen_canopen.h"
#include "c4g_co_internal.h"

void c4g_co_start_node(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    n->boot = (uint8_t)C4G_CO_BOOT_RUNNING;
    n->last_seen_ns = now_ns;
    n->next_ns = now_ns;
    n->started_ns = now_ns;
    n->op_seen = 0U;
    /* the first guard reply sets the toggle: a node the recovery did not reset goes on
       with its own */
    n->toggle = 2U;
}

/* A running node is no longer there, or no longer operational (cause NMT_STATE, the
   state it reported in value): it stops running, and is polled for recovery if its flag
   says so. */
static void node_gone(c4g_co_master_t *m, uint8_t slot, uint8_t cause, uint32_t value,
                      uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    const bool recovery = (m->cfg.node[slot].flags & C4G_CO_F_RECOVERY) != 0U;
    uint8_t kind = (uint8_t)C4G_CO_EV_NODE_LOST;
    if (cause == (uint8_t)C4G_CO_CAUSE_NMT_STATE) {
        kind = (uint8_t)C4G_CO_EV_NODE_STATE;
    }
    n->boot = recovery ? (uint8_t)C4G_CO_BOOT_LOST : (uint8_t)C4G_CO_BOOT_FAILED;
    n->fail_step = (uint8_t)C4G_CO_STEP_NONE;
    n->fail_cause = cause;
    n->fail_value = value;
    n->fail_index = 0U;
    n->fail_sub = 0U;
    n->losses++;
    n->next_ns = now_ns + C4G_CO_RECOVERY_POLL_NS;
    c4g_co_push_event(m, kind, slot, now_ns);
}

void c4g_co_node_lost(c4g_co_master_t *m, uint8_t slot, uint8_t cause, uint64_t now_ns)
{
    node_gone(m, slot, cause, 0U, now_ns);
}

/* How long after NMT Start a STOPPED or PRE-OPERATIONAL report may still be one the node
   sent before it took the Start (a frame already queued): one consumer time for a
   heartbeat, one guard period for lifeguarding, none without a watchdog. A report after
   the node was seen OPERATIONAL is never such a frame. */
static uint64_t start_grace_ns(const c4g_co_node_cfg_t *nc)
{
    uint64_t g = 0U;
    if (nc->watchdog == (uint8_t)C4G_CO_WD_HEARTBEAT) {
        g = 1000000U * (uint64_t)nc->consumer_ms;
    } else if (nc->watchdog == (uint8_t)C4G_CO_WD_LIFEGUARD) {
        g = 1000000U * (uint64_t)nc->guard_ms;
    } else {
        /* no watchdog: no grace */
    }
    return g;
}

/* The NMT state of a running node: OPERATIONAL, or it left (the PDOs would go to a node
   that ignores them, and its TPDOs no longer come). */
static void running_state(c4g_co_master_t *m, uint8_t slot, uint8_t state, uint64_t t_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    if (state == C4G_CO_STATE_OPERATIONAL) {
        n->op_seen = 1U;
    } else if ((state == C4G_CO_STATE_STOPPED) || (state == C4G_CO_STATE_PREOP)) {
        const bool late = (t_ns >= n->started_ns) &&
                          ((t_ns - n->started_ns) >= start_grace_ns(&m->cfg.node[slot]));
        if ((n->op_seen != 0U) || late) {
            node_gone(m, slot, (uint8_t)C4G_CO_CAUSE_NMT_STATE, state, t_ns);
        }
    } else {
        /* c4g_co_ec_decode accepts no other state */
    }
}

static void rx_ec(c4g_co_master_t *m, const c4g_co_frame_t *f, uint8_t slot)
{
    c4g_co_node_t *n = &m->node[slot];
    uint8_t node = 0U;
    uint8_t state = 0U;
    uint8_t toggle = 0U;
    const c4g_status_t st = c4g_co_ec_decode(f, &node, &state, &toggle);
    const bool lg = m->cfg.node[slot].watchdog == (uint8_t)C4G_CO_WD_LIFEGUARD;
    const uint8_t want = lg ? n->toggle : 0U;
    if (st == C4G_ERR_LENGTH) {
        m->count.bad_dlc++;
    } else if (st != C4G_OK) {
        m->count.bad_value++;
    } else if (state == C4G_CO_STATE_BOOTUP) {
        n->nmt = C4G_CO_STATE_PREOP; /* a node enters pre-operational after boot-up */
        if (n->boot == (uint8_t)C4G_CO_BOOT_RUNNING) {
            c4g_co_node_lost(m, slot, (uint8_t)C4G_CO_CAUSE_BOOTUP, f->t_ns);
        }
    } else if ((toggle != want) && (want <= 1U)) {
        m->count.bad_toggle++;
    } else {
        n->nmt = state;
        n->last_seen_ns = f->t_ns;
        if (lg) {
            n->toggle = (uint8_t)(toggle ^ 1U);
        }
        if (n->boot == (uint8_t)C4G_CO_BOOT_RUNNING) {
            running_state(m, slot, state, f->t_ns);
        }
    }
}

static void rx_emcy(c4g_co_master_t *m, const c4g_co_frame_t *f, uint8_t slot)
{
    c4g_co_node_t *n = &m->node[slot];
    uint8_t node = 0U;
    c4g_co_emcy_t e;
    if (c4g_co_emcy_decode(f, &node, &e) != C4G_OK) {
        m->count.bad_dlc++;
    } else {
        c4g_co_event_t ev;
        n->emcy[n->emcy_head] = e;
        n->emcy_head = (uint8_t)((n->emcy_head + 1U) % C4G_CO_EMCY_DEPTH);
        if (n->emcy_n < C4G_CO_EMCY_DEPTH) {
            n->emcy_n++;
        }
        (void)memset(&ev, 0, sizeof ev);
        ev.t_ns = f->t_ns;
        ev.kind = (uint8_t)C4G_CO_EV_EMCY;
        ev.node = node;
        ev.value = e.code;
        c4g_co_push_ev(m, &ev);
    }
}

static void rx_pdo(c4g_co_master_t *m, const c4g_co_frame_t *f, uint8_t slot, uint8_t pdo)
{
    c4g_co_node_t *n = &m->node[slot];
    const c4g_co_pdo_map_t *map = &m->cfg.node[slot].rx[pdo];
    if ((n->boot != (uint8_t)C4G_CO_BOOT_RUNNING) || (map->n == 0U)) {
        m->count.unknown++;
    } else if (c4g_co_pdo_unpack(map, f, n->rx_val[pdo]) != C4G_OK) {
        m->count.bad_dlc++;
    } else {
        n->rx_pdos++;
    }
}

void c4g_co_run_rx(c4g_co_master_t *m, const c4g_co_frame_t *f, c4g_co_kind_t kind,
                   uint8_t slot, uint8_t pdo)
{
    if ((kind == C4G_CO_K_NMT) || (kind == C4G_CO_K_SYNC) || (kind == C4G_CO_K_RPDO) ||
        (kind == C4G_CO_K_SDO_RX)) {
        m->count.foreign++;
    } else if (slot == C4G_CO_NO_SLOT) {
        m->count.unknown++; /* TIME and unknown identifiers have no node either */
    } else if (f->rtr != 0U) {
        m->count.rtr++;
    } else if (kind == C4G_CO_K_NMT_EC) {
        rx_ec(m, f, slot);
    } else if (kind == C4G_CO_K_EMCY) {
        rx_emcy(m, f, slot);
    } else if (kind == C4G_CO_K_SDO_TX) {
        c4g_co_sdo_answer(m, f);
    } else {
        rx_pdo(m, f, slot, pdo); /* the one kind left with a node: TPDO */
    }
}

/* Step 7: the mapped TxPDOs of every running node, then SYNC. */
static void sync_cycle(c4g_co_master_t *m, uint64_t now_ns)
{
    uint32_t i;
    uint32_t p;
    c4g_co_frame_t f;
    for (i = 0U; i < m->cfg.n_nodes; i++) {
        const c4g_co_node_cfg_t *nc = &m->cfg.node[i];
        for (p = 0U; p < C4G_CO_MAX_PDO; p++) {
            if ((m->node[i].boot == (uint8_t)C4G_CO_BOOT_RUNNING) && (nc->tx[p].n > 0U)) {
                const uint16_t cob = (uint16_t)(C4G_CO_COB_RPDO1 + (0x100U * p) + nc->node_id);
                (void)c4g_co_pdo_pack(&nc->tx[p], cob, m->node[i].tx_val[p], &f);
                c4g_co_push_tx(m, &f);
            }
        }
    }
    (void)c4g_co_sync_encode(&f);
    c4g_co_push_tx(m, &f);
    m->count.syncs++;
    m->next_sync_ns += m->cfg.sync_period_ns;
    if (m->next_sync_ns <= now_ns) {
        m->next_sync_ns = now_ns + m->cfg.sync_period_ns; /* late: no burst of SYNCs */
    }
}

static void supervise(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    const c4g_co_node_cfg_t *nc = &m->cfg.node[slot];
    const uint64_t quiet = now_ns - n->last_seen_ns;
    if (nc->watchdog == (uint8_t)C4G_CO_WD_HEARTBEAT) {
        if (quiet > (1000000U * (uint64_t)nc->consumer_ms)) {
            c4g_co_node_lost(m, slot, (uint8_t)C4G_CO_CAUSE_HEARTBEAT, now_ns);
        }
    } else if (nc->watchdog == (uint8_t)C4G_CO_WD_LIFEGUARD) {
        const uint64_t guard = 1000000U * (uint64_t)nc->guard_ms;
        if (quiet > (guard * nc->life_factor)) {
            c4g_co_node_lost(m, slot, (uint8_t)C4G_CO_CAUSE_GUARD, now_ns);
        } else if (now_ns >= n->next_ns) {
            c4g_co_frame_t f;
            (void)c4g_co_guard_request(&f, nc->node_id);
            c4g_co_push_tx(m, &f);
            n->next_ns = now_ns + guard;
        } else {
            /* next guard request not due */
        }
    } else {
        /* without a watchdog the master cannot tell whether the node is there */
    }
}

void c4g_co_run_poll(c4g_co_master_t *m, uint64_t now_ns)
{
    uint32_t i;
    if (now_ns >= m->next_sync_ns) {
        sync_cycle(m, now_ns);
    }
    for (i = 0U; i < m->cfg.n_nodes; i++) {
        if ((m->node[i].boot == (uint8_t)C4G_CO_BOOT_RUNNING) && (now_ns >= m->node[i].last_seen_ns)) {
            supervise(m, (uint8_t)i, now_ns);
        }
    }
}

/* Entry of a mapped object: PDO p and entry e in the node's rx (from_node) or tx maps. */
static c4g_status_t find_entry(const c4g_co_node_cfg_t *nc, bool from_node, uint16_t index,
                               uint8_t sub, uint32_t *p_out, uint32_t *e_out)
{
    c4g_status_t st = C4G_ERR_ARG;
    const uint32_t key = ((uint32_t)index << 8U) | sub;
    uint32_t p;
    uint32_t e;
    for (p = 0U; (p < C4G_CO_MAX_PDO) && (st != C4G_OK); p++) {
        const c4g_co_pdo_map_t *map = from_node ? &nc->rx[p] : &nc->tx[p];
        for (e = 0U; (e < map->n) && (st != C4G_OK); e++) {
            if ((map->entry[e] >> 8U) == key) {
                *p_out = p;
                *e_out = e;
                st = C4G_OK;
            }
        }
    }
    return st;
}

c4g_status_t c4g_co_master_get(const c4g_co_master_t *m, uint8_t node_id, bool from_node,
                               uint16_t index, uint8_t sub, uint32_t *value)
{
    uint8_t slot = 0U;
    c4g_status_t st = c4g_co_master_slot(m, node_id, &slot);
    uint32_t p = 0U;
    uint32_t e = 0U;
    if (value == NULL) {
        st = C4G_ERR_NULL;
    } else if (st == C4G_OK) {
        st = find_entry(&m->cfg.node[slot], from_node, index, sub, &p, &e);
        if (st == C4G_OK) {
            *value = from_node ? m->node[slot].rx_val[p][e] : m->node[slot].tx_val[p][e];
        }
    } else {
        /* st from the slot lookup */
    }
    return st;
}

c4g_status_t c4g_co_master_set(c4g_co_master_t *m, uint8_t node_id, uint16_t index,
                               uint8_t sub, uint32_t value)
{
    uint8_t slot = 0U;
    c4g_status_t st = c4g_co_master_slot(m, node_id, &slot);
    uint32_t p = 0U;
    uint32_t e = 0U;
    if (st == C4G_OK) {
        st = find_entry(&m->cfg.node[slot], false, index, sub, &p, &e);
        if (st == C4G_OK) {
            m->node[slot].tx_val[p][e] = value;
        }
    }
    return st;
}
