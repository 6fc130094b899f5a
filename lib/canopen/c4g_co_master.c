/* SPDX-License-Identifier: MIT */
/* CANopen master: configuration check and the boot-up sequence of the Robox CAN master
   (Robox CANopen master documentation, "Operazioni effettuate dal Master all'avvio della
   rete", steps 1-6), also run again for one node on recovery. */
#include "c4gopen_canopen.h"
#include "c4g_co_internal.h"

/* One configuration operation: an SDO of steps 2-5. */
typedef struct co_op {
    uint32_t value;
    uint16_t index;
    uint8_t sub;
    uint8_t size;   /* bytes to download; 0 = upload */
    uint8_t step;   /* c4g_co_step_t */
} co_op_t;

static void set_op(co_op_t *op, uint8_t step, uint16_t index, uint8_t sub, uint8_t size,
                   uint32_t value)
{
    op->step = step;
    op->index = index;
    op->sub = sub;
    op->size = size;
    op->value = value;
}

static const c4g_co_pdo_map_t *pdo_map(const c4g_co_node_cfg_t *nc, uint32_t p)
{
    return (p < C4G_CO_MAX_PDO) ? &nc->rx[p] : &nc->tx[p - C4G_CO_MAX_PDO];
}

/* COB-ID of PDO p (0..3: the node's TPDOs, 4..7: its RPDOs). */
static uint32_t pdo_cob(const c4g_co_node_cfg_t *nc, uint32_t p)
{
    const uint32_t k = p % C4G_CO_MAX_PDO;
    uint32_t base = C4G_CO_COB_RPDO1;
    if (p < C4G_CO_MAX_PDO) {
        base = C4G_CO_COB_TPDO1;
    }
    return base + (0x100U * k) + nc->node_id;
}

/* Step 5 for one PDO, operation j: COB-ID disabled, mapping count 0, the entries, the
   count, the transmission type, COB-ID enabled. */
static void pdo_op(const c4g_co_node_cfg_t *nc, uint32_t p, uint32_t j, co_op_t *op)
{
    const c4g_co_pdo_map_t *map = pdo_map(nc, p);
    const uint32_t k = p % C4G_CO_MAX_PDO;
    const uint16_t comm = (uint16_t)(((p < C4G_CO_MAX_PDO) ? 0x1800U : 0x1400U) + k);
    const uint16_t mapi = (uint16_t)(comm + 0x200U);
    const uint32_t n = map->n;
    const uint8_t st = (uint8_t)C4G_CO_STEP_PDO;
    if (j == 0U) {
        set_op(op, st, comm, 1U, 4U, pdo_cob(nc, p) | 0x80000000UL);
    } else if (j == 1U) {
        set_op(op, st, mapi, 0U, 1U, 0U);
    } else if (j < (n + 2U)) {
        set_op(op, st, mapi, (uint8_t)(j - 1U), 4U, map->entry[j - 2U]);
    } else if (j == (n + 2U)) {
        set_op(op, st, mapi, 0U, 1U, n);
    } else if (j == (n + 3U)) {
        set_op(op, st, comm, 2U, 1U, map->trans);
    } else {
        set_op(op, st, comm, 1U, 4U, pdo_cob(nc, p));
    }
}

static bool pdo_op_at(const c4g_co_node_cfg_t *nc, uint32_t k, co_op_t *op)
{
    bool found = false;
    uint32_t rest = k;
    uint32_t p;
    for (p = 0U; (p < (2U * C4G_CO_MAX_PDO)) && !found; p++) {
        const uint32_t n = pdo_map(nc, p)->n;
        if (n > 0U) {
            if (rest < (n + 5U)) {
                pdo_op(nc, p, rest, op);
                found = true;
            } else {
                rest -= n + 5U;
            }
        }
    }
    return found;
}

static uint32_t wd_ops(const c4g_co_node_cfg_t *nc)
{
    uint32_t n = 0U;
    if (nc->watchdog == (uint8_t)C4G_CO_WD_HEARTBEAT) {
        n = 1U;
    } else if (nc->watchdog == (uint8_t)C4G_CO_WD_LIFEGUARD) {
        n = 3U;
    } else {
        n = 0U;
    }
    return n;
}

/* Step 4, operation i: heartbeat 0x1017; lifeguard 0x100C, 0x100D, 0x1017 = 0, or with
   bit 30 of the device type 0x1017 = 0 first (the Robox documentation's note on RTE 34.30.2). */
static void wd_op(const c4g_co_node_cfg_t *nc, uint32_t i, co_op_t *op)
{
    const uint8_t st = (uint8_t)C4G_CO_STEP_WATCHDOG;
    uint32_t j = i;
    if ((nc->device_type & C4G_CO_DEVTYPE_LG_REVERSE) != 0U) {
        j = (i + 2U) % 3U;
    }
    if (nc->watchdog == (uint8_t)C4G_CO_WD_HEARTBEAT) {
        set_op(op, st, C4G_CO_OBJ_HEARTBEAT, 0U, 2U, nc->heartbeat_ms);
    } else if (j == 0U) {
        set_op(op, st, C4G_CO_OBJ_GUARD_TIME, 0U, 2U, nc->guard_ms);
    } else if (j == 1U) {
        set_op(op, st, C4G_CO_OBJ_LIFE_FACTOR, 0U, 1U, nc->life_factor);
    } else {
        set_op(op, st, C4G_CO_OBJ_HEARTBEAT, 0U, 2U, 0U);
    }
}

/* Operation k of steps 2-5; false past the last one. */
static bool op_at(const c4g_co_node_cfg_t *nc, uint32_t k, co_op_t *op)
{
    bool found = true;
    const uint32_t w = wd_ops(nc);
    if (k == 0U) {
        set_op(op, (uint8_t)C4G_CO_STEP_DEVTYPE, C4G_CO_OBJ_DEVICE_TYPE, 0U, 0U, 0U);
    } else if (k == 1U) {
        set_op(op, (uint8_t)C4G_CO_STEP_CYCLE, C4G_CO_OBJ_CYCLE_PERIOD, 0U, 4U,
               nc->cycle_period_us);
    } else if (k < (2U + w)) {
        wd_op(nc, k - 2U, op);
    } else {
        found = pdo_op_at(nc, k - 2U - w, op);
    }
    return found;
}

/* ---- queues */

void c4g_co_push_tx(c4g_co_master_t *m, const c4g_co_frame_t *f)
{
    if (m->txq_n >= C4G_CO_TXQ_LEN) {
        m->count.txq_full++;
    } else {
        const uint32_t i = ((uint32_t)m->txq_head + m->txq_n) % C4G_CO_TXQ_LEN;
        m->txq[i] = *f;
        m->txq_n++;
    }
}

void c4g_co_push_ev(c4g_co_master_t *m, const c4g_co_event_t *e)
{
    if (m->evq_n >= C4G_CO_EVQ_LEN) {
        m->count.evq_full++;
    } else {
        const uint32_t i = ((uint32_t)m->evq_head + m->evq_n) % C4G_CO_EVQ_LEN;
        m->evq[i] = *e;
        m->evq_n++;
    }
}

void c4g_co_push_event(c4g_co_master_t *m, uint8_t kind, uint8_t slot, uint64_t t_ns)
{
    const c4g_co_node_t *n = &m->node[slot];
    c4g_co_event_t e;
    (void)memset(&e, 0, sizeof e);
    e.t_ns = t_ns;
    e.kind = kind;
    e.node = m->cfg.node[slot].node_id;
    e.step = n->fail_step;
    e.cause = n->fail_cause;
    e.value = n->fail_value;
    e.index = n->fail_index;
    e.sub = n->fail_sub;
    c4g_co_push_ev(m, &e);
}

static void push_nmt(c4g_co_master_t *m, uint8_t cmd, uint8_t node)
{
    c4g_co_frame_t f;
    (void)c4g_co_nmt_encode(&f, cmd, node);
    c4g_co_push_tx(m, &f);
}

static void pump_sdo(c4g_co_master_t *m)
{
    c4g_co_frame_t f;
    bool have = false;
    (void)c4g_co_sdo_take(&m->sdo, &f, &have);
    if (have) {
        c4g_co_push_tx(m, &f);
    }
}

/* ---- boot */

static void net_started(c4g_co_master_t *m, uint64_t now_ns)
{
    uint32_t i;
    push_nmt(m, C4G_CO_NMT_START, 0U); /* step 6 */
    m->phase = C4G_CO_PHASE_RUN;
    m->next_sync_ns = now_ns;
    for (i = 0U; i < m->cfg.n_nodes; i++) {
        if (m->node[i].boot == (uint8_t)C4G_CO_BOOT_READY) {
            c4g_co_start_node(m, (uint8_t)i, now_ns);
        }
    }
    c4g_co_push_event(m, (uint8_t)C4G_CO_EV_NET_STARTED, 0U, now_ns);
}

/* Starts operation op of node slot; false when its configuration has no more. */
static bool issue_op(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    co_op_t op;
    const c4g_co_node_cfg_t *nc = &m->cfg.node[slot];
    const bool found = op_at(nc, m->node[slot].op, &op);
    if (found) {
        uint8_t buf[4];
        m->cur = slot;
        c4g_put_le(buf, op.value, 4U);
        if (op.size == 0U) {
            (void)c4g_co_sdo_upload(&m->sdo, nc->node_id, op.index, op.sub, now_ns);
        } else {
            (void)c4g_co_sdo_download(&m->sdo, nc->node_id, op.index, op.sub, buf, op.size,
                                      now_ns);
        }
    }
    return found;
}

/* Boot phase: the next node still waiting, or step 6. */
static void next_node(c4g_co_master_t *m, uint64_t now_ns)
{
    uint32_t i = 0U;
    while ((i < m->cfg.n_nodes) && (m->node[i].boot != (uint8_t)C4G_CO_BOOT_WAIT)) {
        i++;
    }
    if (i < m->cfg.n_nodes) {
        m->node[i].boot = (uint8_t)C4G_CO_BOOT_CONFIG;
        m->node[i].op = 0U;
        (void)issue_op(m, (uint8_t)i, now_ns); /* operation 0 (step 2) always exists */
    } else {
        net_started(m, now_ns);
    }
}

static void node_done(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    m->cur = C4G_CO_NO_SLOT;
    if (n->recovering != 0U) {
        /* recovery: step 6 for this node alone */
        push_nmt(m, C4G_CO_NMT_START, m->cfg.node[slot].node_id);
        n->recovering = 0U;
        c4g_co_start_node(m, slot, now_ns);
        c4g_co_push_event(m, (uint8_t)C4G_CO_EV_NODE_RECOVERED, slot, now_ns);
    } else {
        n->boot = (uint8_t)C4G_CO_BOOT_READY;
        c4g_co_push_event(m, (uint8_t)C4G_CO_EV_NODE_READY, slot, now_ns);
        next_node(m, now_ns);
    }
}

static uint8_t cause_of(uint8_t result)
{
    uint8_t c = (uint8_t)C4G_CO_CAUSE_SDO_PROTOCOL;
    if (result == (uint8_t)C4G_CO_SDO_TIMEOUT) {
        c = (uint8_t)C4G_CO_CAUSE_SDO_TIMEOUT;
    } else if (result == (uint8_t)C4G_CO_SDO_ABORTED) {
        c = (uint8_t)C4G_CO_CAUSE_SDO_ABORT;
    } else {
        c = (uint8_t)C4G_CO_CAUSE_SDO_PROTOCOL;
    }
    return c;
}

static void record(c4g_co_node_t *n, const co_op_t *op, uint8_t cause, uint32_t value)
{
    n->fail_step = op->step;
    n->fail_cause = cause;
    n->fail_value = value;
    n->fail_index = op->index;
    n->fail_sub = op->sub;
}

/* The configuration of node slot is aborted (steps 2a, 3a, 4.i, 5a). */
static void node_failed(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    const bool recovery = (m->cfg.node[slot].flags & C4G_CO_F_RECOVERY) != 0U;
    m->cur = C4G_CO_NO_SLOT;
    n->boot = recovery ? (uint8_t)C4G_CO_BOOT_LOST : (uint8_t)C4G_CO_BOOT_FAILED;
    n->next_ns = now_ns + C4G_CO_RECOVERY_POLL_NS;
    c4g_co_push_event(m, (uint8_t)C4G_CO_EV_NODE_FAILED, slot, now_ns);
    if (n->recovering != 0U) {
        n->recovering = 0U;
    } else {
        next_node(m, now_ns);
    }
}

static uint32_t step_flag(uint8_t step)
{
    uint32_t f = C4G_CO_F_BYPASS_PDO;
    if (step == (uint8_t)C4G_CO_STEP_CYCLE) {
        f = C4G_CO_F_BYPASS_CYCLE;
    } else if (step == (uint8_t)C4G_CO_STEP_WATCHDOG) {
        f = C4G_CO_F_BYPASS_WD;
    } else if (step == (uint8_t)C4G_CO_STEP_DEVTYPE) {
        f = 0U; /* no answer at step 2 always aborts */
    } else {
        f = C4G_CO_F_BYPASS_PDO;
    }
    return f;
}

/* A configuration SDO of node slot ended: go on, bypass, or abort. */
static void config_result(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    const c4g_co_node_cfg_t *nc = &m->cfg.node[slot];
    co_op_t op;
    bool go_on = true;
    (void)op_at(nc, n->op, &op);
    if (m->sdo.result != (uint8_t)C4G_CO_SDO_OK) {
        record(n, &op, cause_of(m->sdo.result), m->sdo.abort_code);
        go_on = (nc->flags & step_flag(op.step)) != 0U;
        if (go_on) {
            n->bypassed |= (uint8_t)(1U << op.step);
        }
    } else if (op.step == (uint8_t)C4G_CO_STEP_DEVTYPE) {
        uint32_t v = 0U;
        (void)c4g_co_sdo_value(&m->sdo, &v);
        n->devtype_read = v;
        if ((v != (nc->device_type & ~C4G_CO_DEVTYPE_LG_REVERSE)) &&
            ((nc->flags & C4G_CO_F_IGNORE_DEVTYPE) == 0U)) {
            record(n, &op, (uint8_t)C4G_CO_CAUSE_DEVTYPE, v);
            go_on = false;
        }
    } else {
        /* download acknowledged */
    }
    if (go_on) {
        n->op++;
        if (!issue_op(m, slot, now_ns)) {
            node_done(m, slot, now_ns);
        }
    } else {
        node_failed(m, slot, now_ns);
    }
}

/* A recovery poll of DeviceType ended: a correct answer repeats steps 1-6 for the node. */
static void poll_result(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns)
{
    c4g_co_node_t *n = &m->node[slot];
    const c4g_co_node_cfg_t *nc = &m->cfg.node[slot];
    uint32_t v = 0U;
    m->cur = C4G_CO_NO_SLOT;
    if ((c4g_co_sdo_value(&m->sdo, &v) == C4G_OK) &&
        ((v == (nc->device_type & ~C4G_CO_DEVTYPE_LG_REVERSE)) ||
         ((nc->flags & C4G_CO_F_IGNORE_DEVTYPE) != 0U))) {
        push_nmt(m, C4G_CO_NMT_PREOP, nc->node_id); /* step 1, to this node only */
        n->recovering = 1U;
        n->boot = (uint8_t)C4G_CO_BOOT_CONFIG;
        n->op = 0U;
        (void)issue_op(m, slot, now_ns); /* operation 0 (step 2) always exists */
    }
    /* no or wrong answer: the next poll is due 2.5 s after this one began */
}

static void user_result(c4g_co_master_t *m, uint64_t now_ns)
{
    const uint8_t r = m->sdo.result;
    c4g_co_event_t e;
    (void)memset(&e, 0, sizeof e);
    e.t_ns = now_ns;
    e.kind = (uint8_t)C4G_CO_EV_SDO_DONE;
    e.node = m->cfg.node[m->cur].node_id;
    e.index = m->sdo.index;
    e.sub = m->sdo.sub;
    e.value = m->sdo.abort_code;
    m->user_sdo = 0U;
    m->cur = C4G_CO_NO_SLOT;
    if (r == (uint8_t)C4G_CO_SDO_OK) {
        e.value = 0U;
        (void)c4g_co_sdo_value(&m->sdo, &e.value);
    } else {
        e.cause = cause_of(r);
    }
    c4g_co_push_ev(m, &e);
}

/* After the SDO client ran: hand a finished transfer to its owner. */
static void sdo_check(c4g_co_master_t *m, uint64_t now_ns)
{
    pump_sdo(m);
    if ((m->cur != C4G_CO_NO_SLOT) && !c4g_co_sdo_busy(&m->sdo)) {
        const uint8_t slot = m->cur;
        if (m->user_sdo != 0U) {
            user_result(m, now_ns);
        } else if (m->node[slot].boot == (uint8_t)C4G_CO_BOOT_LOST) {
            poll_result(m, slot, now_ns);
        } else {
            config_result(m, slot, now_ns);
        }
        pump_sdo(m);
    }
}

void c4g_co_sdo_answer(c4g_co_master_t *m, const c4g_co_frame_t *f)
{
    const uint32_t before = m->sdo.ignored;
    const bool mine = c4g_co_sdo_busy(&m->sdo) && (m->sdo.node == (uint8_t)(f->id & 0x7FU));
    (void)c4g_co_sdo_rx(&m->sdo, f);
    if (!mine || (m->sdo.ignored != before)) {
        m->count.sdo_ignored++;
    }
    sdo_check(m, f->t_ns);
}

/* Run phase: the first lost node with the recovery flag whose poll is due. */
static void recovery_poll(c4g_co_master_t *m, uint64_t now_ns)
{
    uint32_t i;
    for (i = 0U; (i < m->cfg.n_nodes) && (m->cur == C4G_CO_NO_SLOT); i++) {
        c4g_co_node_t *n = &m->node[i];
        if ((n->boot == (uint8_t)C4G_CO_BOOT_LOST) && (now_ns >= n->next_ns)) {
            m->cur = (uint8_t)i;
            n->next_ns = now_ns + C4G_CO_RECOVERY_POLL_NS;
            (void)c4g_co_sdo_upload(&m->sdo, m->cfg.node[i].node_id, C4G_CO_OBJ_DEVICE_TYPE,
                                    0U, now_ns);
        }
    }
    pump_sdo(m);
}

/* ---- configuration check */

static bool pdo_ok(const c4g_co_pdo_map_t *map)
{
    uint8_t len = 0U;
    bool ok = c4g_co_pdo_length(map, &len) == C4G_OK;
    if (ok && (map->n > 0U)) {
        ok = ((map->trans >= 1U) && (map->trans <= 240U)) || (map->trans >= 254U);
    }
    return ok;
}

static bool wd_ok(const c4g_co_node_cfg_t *nc)
{
    bool ok = true;
    if (nc->watchdog == (uint8_t)C4G_CO_WD_HEARTBEAT) {
        ok = (nc->heartbeat_ms > 0U) && (nc->consumer_ms > nc->heartbeat_ms);
    } else if (nc->watchdog == (uint8_t)C4G_CO_WD_LIFEGUARD) {
        ok = (nc->guard_ms > 0U) && (nc->life_factor > 0U);
    } else {
        ok = nc->watchdog == (uint8_t)C4G_CO_WD_NONE;
    }
    return ok;
}

static bool node_cfg_ok(const c4g_co_node_cfg_t *nc)
{
    bool ok = c4g_co_node_ok(nc->node_id) && (nc->station >= 1U) && (nc->station <= 64U) &&
              (nc->axis >= 1U) && (nc->axis <= 32U) && (nc->flags <= 0x1FU) && wd_ok(nc);
    uint32_t p;
    for (p = 0U; (p < (2U * C4G_CO_MAX_PDO)) && ok; p++) {
        ok = pdo_ok(pdo_map(nc, p));
    }
    return ok;
}

static bool unique(const c4g_co_net_cfg_t *cfg, uint32_t i)
{
    bool ok = true;
    uint32_t j;
    for (j = 0U; (j < i) && ok; j++) {
        ok = (cfg->node[j].node_id != cfg->node[i].node_id) &&
             (cfg->node[j].station != cfg->node[i].station);
    }
    return ok;
}

c4g_status_t c4g_co_net_check(const c4g_co_net_cfg_t *cfg, uint8_t *bad_node)
{
    c4g_status_t st = C4G_OK;
    if ((cfg == NULL) || (bad_node == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        uint32_t i;
        *bad_node = C4G_CO_NO_SLOT;
        if ((cfg->n_nodes < 1U) || (cfg->n_nodes > C4G_CO_MAX_NODES) ||
            (cfg->channel >= C4G_CO_MAX_CHANNELS) || (cfg->bitrate < 10000U) ||
            (cfg->bitrate > 1000000U) || (cfg->sync_period_ns < 500000U) ||
            (cfg->sync_period_ns > 1000000000U) || (cfg->sdo_timeout_ns < 1000000U) ||
            (cfg->sdo_timeout_ns > 10000000000ULL) || (cfg->sdo_retries > 5U)) {
            st = C4G_ERR_RANGE;
        }
        for (i = 0U; (i < cfg->n_nodes) && (st == C4G_OK); i++) {
            if (!node_cfg_ok(&cfg->node[i]) || !unique(cfg, i)) {
                *bad_node = (uint8_t)i;
                st = C4G_ERR_ARG;
            }
        }
    }
    return st;
}

/* ---- API */

c4g_status_t c4g_co_master_init(c4g_co_master_t *m, const c4g_co_net_cfg_t *cfg)
{
    uint8_t bad = 0U;
    c4g_status_t st = c4g_co_net_check(cfg, &bad);
    if (m == NULL) {
        st = C4G_ERR_NULL;
    } else if (st == C4G_OK) {
        uint32_t i;
        (void)memset(m, 0, sizeof *m);
        m->cfg = *cfg;
        m->cur = C4G_CO_NO_SLOT;
        for (i = 0U; i < C4G_CO_MAX_NODES; i++) {
            m->node[i].nmt = C4G_CO_STATE_UNKNOWN;
        }
        st = c4g_co_sdo_init(&m->sdo, cfg->sdo_timeout_ns, cfg->sdo_retries);
    } else {
        /* st from the check */
    }
    return st;
}

c4g_status_t c4g_co_master_start(c4g_co_master_t *m, uint64_t now_ns)
{
    c4g_status_t st = C4G_OK;
    if (m == NULL) {
        st = C4G_ERR_NULL;
    } else if (m->phase != C4G_CO_PHASE_IDLE) {
        st = C4G_ERR_STATE;
    } else {
        m->phase = C4G_CO_PHASE_BOOT;
        push_nmt(m, C4G_CO_NMT_PREOP, 0U); /* step 1 */
        next_node(m, now_ns);
        pump_sdo(m);
    }
    return st;
}

c4g_status_t c4g_co_master_slot(const c4g_co_master_t *m, uint8_t node_id, uint8_t *slot)
{
    c4g_status_t st = C4G_ERR_ARG;
    if ((m == NULL) || (slot == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        uint32_t i;
        for (i = 0U; (i < m->cfg.n_nodes) && (st != C4G_OK); i++) {
            if (m->cfg.node[i].node_id == node_id) {
                *slot = (uint8_t)i;
                st = C4G_OK;
            }
        }
    }
    return st;
}

c4g_status_t c4g_co_master_rx(c4g_co_master_t *m, const c4g_co_frame_t *f)
{
    c4g_status_t st = C4G_OK;
    c4g_co_kind_t kind = C4G_CO_K_UNKNOWN;
    uint8_t node = 0U;
    uint8_t pdo = 0U;
    if ((m == NULL) || (f == NULL)) {
        st = C4G_ERR_NULL;
    } else if (c4g_co_classify(f, &kind, &node, &pdo) != C4G_OK) {
        m->count.rx++;
        m->count.bad_frame++;
    } else {
        uint8_t slot = C4G_CO_NO_SLOT;
        m->count.rx++;
        if (c4g_co_master_slot(m, node, &slot) != C4G_OK) {
            slot = C4G_CO_NO_SLOT;
        }
        c4g_co_run_rx(m, f, kind, slot, pdo);
    }
    return st;
}

/* t + d + 1 without wrapping: the supervision fires once the quiet time EXCEEDS d */
static uint64_t co_after(uint64_t t, uint64_t d)
{
    const uint64_t room = C4G_NO_DEADLINE - t;
    return (d < room) ? ((t + d) + 1U) : C4G_NO_DEADLINE;
}

static uint64_t co_min(uint64_t a, uint64_t b)
{
    return (a < b) ? a : b;
}

/* When c4g_co_master_poll next has work, from the same conditions as its timers: the SDO
 * timeout, the SYNC, each running node's heartbeat / guard supervision and guard request,
 * and the recovery poll of a lost node (while no SDO runs: one that runs ends first). */
static uint64_t master_deadline(const c4g_co_master_t *m)
{
    uint64_t next = C4G_NO_DEADLINE;
    if (c4g_co_sdo_busy(&m->sdo)) {
        next = m->sdo.deadline_ns;
    }
    if (m->phase == C4G_CO_PHASE_RUN) {
        uint32_t i;
        next = co_min(next, m->next_sync_ns);
        for (i = 0U; i < m->cfg.n_nodes; i++) {
            const c4g_co_node_t *n = &m->node[i];
            const c4g_co_node_cfg_t *nc = &m->cfg.node[i];
            if (n->boot == (uint8_t)C4G_CO_BOOT_RUNNING) {
                if (nc->watchdog == (uint8_t)C4G_CO_WD_HEARTBEAT) {
                    next = co_min(next, co_after(n->last_seen_ns,
                                                 1000000U * (uint64_t)nc->consumer_ms));
                } else if (nc->watchdog == (uint8_t)C4G_CO_WD_LIFEGUARD) {
                    const uint64_t guard = 1000000U * (uint64_t)nc->guard_ms;
                    next = co_min(next, co_after(n->last_seen_ns, guard * nc->life_factor));
                    next = co_min(next, n->next_ns);
                } else {
                    /* no watchdog: nothing to supervise */
                }
            } else if ((n->boot == (uint8_t)C4G_CO_BOOT_LOST) && (m->cur == C4G_CO_NO_SLOT)) {
                next = co_min(next, n->next_ns);
            } else {
                /* booting (its SDO's deadline counts), failed, or not started */
            }
        }
    }
    return next;
}

c4g_status_t c4g_co_master_poll(c4g_co_master_t *m, uint64_t now_ns, uint64_t *next_ns)
{
    c4g_status_t st = C4G_OK;
    if ((m == NULL) || (next_ns == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        (void)c4g_co_sdo_poll(&m->sdo, now_ns);
        sdo_check(m, now_ns);
        if (m->phase == C4G_CO_PHASE_RUN) {
            c4g_co_run_poll(m, now_ns);
            recovery_poll(m, now_ns);
        }
        *next_ns = master_deadline(m);
    }
    return st;
}

c4g_status_t c4g_co_master_tx(c4g_co_master_t *m, c4g_co_frame_t *f, bool *have)
{
    c4g_status_t st = C4G_OK;
    if ((m == NULL) || (f == NULL) || (have == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        *have = m->txq_n > 0U;
        if (*have) {
            *f = m->txq[m->txq_head];
            m->txq_head = (uint16_t)((m->txq_head + 1U) % C4G_CO_TXQ_LEN);
            m->txq_n--;
            m->count.tx++;
        }
    }
    return st;
}

c4g_status_t c4g_co_master_event(c4g_co_master_t *m, c4g_co_event_t *ev, bool *have)
{
    c4g_status_t st = C4G_OK;
    if ((m == NULL) || (ev == NULL) || (have == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        *have = m->evq_n > 0U;
        if (*have) {
            *ev = m->evq[m->evq_head];
            m->evq_head = (uint16_t)((m->evq_head + 1U) % C4G_CO_EVQ_LEN);
            m->evq_n--;
        }
    }
    return st;
}

c4g_status_t c4g_co_master_sdo(c4g_co_master_t *m, uint8_t node_id, bool upload, uint16_t index,
                               uint8_t sub, uint32_t value, uint8_t size, uint64_t now_ns)
{
    uint8_t slot = 0U;
    c4g_status_t st = c4g_co_master_slot(m, node_id, &slot);
    if (st != C4G_OK) {
        /* st: NULL or not configured */
    } else if (!upload && ((size < 1U) || (size > 4U))) {
        st = C4G_ERR_LENGTH;
    } else if ((m->phase != C4G_CO_PHASE_RUN) || (m->cur != C4G_CO_NO_SLOT)) {
        st = C4G_ERR_STATE;
    } else {
        uint8_t buf[4];
        c4g_put_le(buf, value, 4U);
        if (upload) {
            st = c4g_co_sdo_upload(&m->sdo, node_id, index, sub, now_ns);
        } else {
            st = c4g_co_sdo_download(&m->sdo, node_id, index, sub, buf, size, now_ns);
        }
        m->cur = slot;
        m->user_sdo = 1U;
        pump_sdo(m);
    }
    return st;
}

c4g_status_t c4g_co_master_nmt(c4g_co_master_t *m, uint8_t node_id, uint8_t cmd)
{
    uint8_t slot = 0U;
    c4g_status_t st = C4G_OK;
    c4g_co_frame_t f;
    if (m == NULL) {
        st = C4G_ERR_NULL;
    } else if ((node_id != 0U) && (c4g_co_master_slot(m, node_id, &slot) != C4G_OK)) {
        st = C4G_ERR_ARG;
    } else {
        st = c4g_co_nmt_encode(&f, cmd, node_id);
        if (st == C4G_OK) {
            c4g_co_push_tx(m, &f);
        }
    }
    return st;
}
