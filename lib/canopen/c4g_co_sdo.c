/* SPDX-License-Identifier: MIT */
/* SDO client (CiA 301 7.2.4): expedited and segmented upload/download, timeouts, retries,
   abort codes. One transfer at a time; the caller moves the frames. */
#include "c4gopen_canopen.h"
#include "c4g_co_internal.h"

#define ST_IDLE 0U
#define ST_UP_INIT 1U
#define ST_UP_SEG 2U
#define ST_DN_INIT 3U
#define ST_DN_SEG 4U

#define SCS_UP_SEG 0U
#define SCS_DN_SEG 1U
#define SCS_UP_INIT 2U
#define SCS_DN_INIT 3U
#define SCS_ABORT 4U

const char *c4g_co_abort_name(uint32_t code)
{
    const char *t = "unknown abort code";
    switch (code) {
    case C4G_CO_ABORT_TOGGLE: t = "toggle bit not alternated"; break;
    case C4G_CO_ABORT_TIMEOUT: t = "SDO protocol timed out"; break;
    case C4G_CO_ABORT_COMMAND: t = "client/server command specifier not valid or unknown"; break;
    case C4G_CO_ABORT_BLOCK_SIZE: t = "invalid block size"; break;
    case C4G_CO_ABORT_SEQUENCE: t = "invalid sequence number"; break;
    case C4G_CO_ABORT_CRC: t = "CRC error"; break;
    case C4G_CO_ABORT_MEMORY: t = "out of memory"; break;
    case C4G_CO_ABORT_ACCESS: t = "unsupported access to an object"; break;
    case C4G_CO_ABORT_WRITE_ONLY: t = "attempt to read a write only object"; break;
    case C4G_CO_ABORT_READ_ONLY: t = "attempt to write a read only object"; break;
    case C4G_CO_ABORT_NO_OBJECT: t = "object does not exist in the object dictionary"; break;
    case C4G_CO_ABORT_NO_MAP: t = "object cannot be mapped to the PDO"; break;
    case C4G_CO_ABORT_MAP_LENGTH: t = "number and length of objects to be mapped exceeds PDO length"; break;
    case C4G_CO_ABORT_PARAM_INCOMPAT: t = "general parameter incompatibility"; break;
    case C4G_CO_ABORT_DEVICE_INCOMPAT: t = "general internal incompatibility in the device"; break;
    case C4G_CO_ABORT_HARDWARE: t = "access failed due to a hardware error"; break;
    case C4G_CO_ABORT_TYPE_LENGTH: t = "data type does not match, length of service parameter does not match"; break;
    case C4G_CO_ABORT_TYPE_HIGH: t = "data type does not match, length of service parameter too high"; break;
    case C4G_CO_ABORT_TYPE_LOW: t = "data type does not match, length of service parameter too low"; break;
    case C4G_CO_ABORT_NO_SUB: t = "sub-index does not exist"; break;
    case C4G_CO_ABORT_VALUE: t = "invalid value for parameter"; break;
    case C4G_CO_ABORT_VALUE_HIGH: t = "value of parameter written too high"; break;
    case C4G_CO_ABORT_VALUE_LOW: t = "value of parameter written too low"; break;
    case C4G_CO_ABORT_MAX_MIN: t = "maximum value is less than minimum value"; break;
    case C4G_CO_ABORT_RESOURCE: t = "resource not available: SDO connection"; break;
    case C4G_CO_ABORT_GENERAL: t = "general error"; break;
    case C4G_CO_ABORT_STORE: t = "data cannot be transferred or stored to the application"; break;
    case C4G_CO_ABORT_STORE_LOCAL: t = "data cannot be transferred or stored because of local control"; break;
    case C4G_CO_ABORT_STORE_STATE: t = "data cannot be transferred or stored because of the present device state"; break;
    case C4G_CO_ABORT_NO_DICTIONARY: t = "object dictionary dynamic generation fails or no object dictionary is present"; break;
    case C4G_CO_ABORT_NO_DATA: t = "no data available"; break;
    default: t = "unknown abort code"; break;
    }
    return t;
}

c4g_status_t c4g_co_sdo_abort_encode(c4g_co_frame_t *f, uint16_t cob, uint16_t index,
                                     uint8_t sub, uint32_t code)
{
    c4g_status_t st = C4G_OK;
    if (f == NULL) {
        st = C4G_ERR_NULL;
    } else if (cob > 0x7FFU) {
        st = C4G_ERR_ARG;
    } else {
        c4g_co_frame_clear(f, cob, 8U);
        f->data[0] = 0x80U;
        c4g_put_le(&f->data[1], index, 2U);
        f->data[3] = sub;
        c4g_put_le(&f->data[4], code, 4U);
    }
    return st;
}

c4g_status_t c4g_co_sdo_init(c4g_co_sdo_client_t *c, uint64_t timeout_ns, uint8_t retries)
{
    c4g_status_t st = C4G_OK;
    if (c == NULL) {
        st = C4G_ERR_NULL;
    } else if ((timeout_ns < 1000000U) || (timeout_ns > 10000000000ULL) || (retries > 5U)) {
        st = C4G_ERR_ARG;
    } else {
        (void)memset(c, 0, sizeof *c);
        c->timeout_ns = timeout_ns;
        c->retries = retries;
    }
    return st;
}

bool c4g_co_sdo_busy(const c4g_co_sdo_client_t *c)
{
    return (c != NULL) && (c->state != ST_IDLE);
}

/* The request of the current phase, with a fresh deadline. */
static void send_request(c4g_co_sdo_client_t *c, uint64_t now_ns)
{
    c4g_co_frame_t *f = &c->out;
    c4g_co_frame_clear(f, (uint16_t)(C4G_CO_COB_SDO_RX + c->node), 8U);
    if (c->state == ST_UP_INIT) {
        f->data[0] = 0x40U;
    } else if (c->state == ST_UP_SEG) {
        f->data[0] = (uint8_t)(0x60U | ((uint32_t)c->toggle << 4U));
    } else if (c->state == ST_DN_INIT) {
        if (c->len <= 4U) {
            f->data[0] = (uint8_t)(0x23U | ((4U - (uint32_t)c->len) << 2U));
            c4g_put_le(&f->data[4], c4g_get_le(c->data, c->len), c->len);
        } else {
            f->data[0] = 0x21U;
            c4g_put_le(&f->data[4], c->len, 4U);
        }
    } else {
        uint32_t i;
        uint8_t last = 0U;
        for (i = 0U; (i < 7U) && (((uint32_t)c->pos + i) < c->len); i++) {
            f->data[1U + i] = c->data[c->pos + i];
        }
        if (((uint32_t)c->pos + i) >= c->len) {
            last = 1U;
        }
        f->data[0] = (uint8_t)(((uint32_t)c->toggle << 4U) | ((7U - i) << 1U) | last);
    }
    if ((c->state == ST_UP_INIT) || (c->state == ST_DN_INIT)) {
        c4g_put_le(&f->data[1], c->index, 2U);
        f->data[3] = c->sub;
    }
    c->deadline_ns = now_ns + c->timeout_ns;
    c->out_ready = 1U;
}

static void finish(c4g_co_sdo_client_t *c, uint8_t result, uint32_t code)
{
    c->state = ST_IDLE;
    c->result = result;
    c->abort_code = code;
}

/* The client aborts: tells the server and ends the transfer. */
static void client_abort(c4g_co_sdo_client_t *c, uint8_t result, uint32_t code)
{
    (void)c4g_co_sdo_abort_encode(&c->out, (uint16_t)(C4G_CO_COB_SDO_RX + c->node), c->index,
                                  c->sub, code);
    c->out_ready = 1U;
    finish(c, result, code);
}

static c4g_status_t begin(c4g_co_sdo_client_t *c, uint8_t node, uint16_t index, uint8_t sub,
                          uint8_t state, uint64_t now_ns)
{
    c4g_status_t st = C4G_OK;
    if (!c4g_co_node_ok(node)) {
        st = C4G_ERR_ARG;
    } else {
        c->node = node;
        c->index = index;
        c->sub = sub;
        c->state = state;
        c->pos = 0U;
        c->toggle = 0U;
        c->tries_left = c->retries;
        c->result = (uint8_t)C4G_CO_SDO_NONE;
        c->abort_code = 0U;
        send_request(c, now_ns);
    }
    return st;
}

c4g_status_t c4g_co_sdo_upload(c4g_co_sdo_client_t *c, uint8_t node, uint16_t index,
                               uint8_t sub, uint64_t now_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (c != NULL) {
        c->len = 0U;
        if (c->state != ST_IDLE) {
            st = C4G_ERR_STATE;
        } else {
            st = begin(c, node, index, sub, ST_UP_INIT, now_ns);
        }
    }
    return st;
}

c4g_status_t c4g_co_sdo_download(c4g_co_sdo_client_t *c, uint8_t node, uint16_t index,
                                 uint8_t sub, const uint8_t *data, uint16_t len, uint64_t now_ns)
{
    c4g_status_t st = C4G_OK;
    if ((c == NULL) || (data == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((len == 0U) || (len > C4G_CO_SDO_MAX)) {
        st = C4G_ERR_LENGTH;
    } else if (c->state != ST_IDLE) {
        st = C4G_ERR_STATE;
    } else {
        (void)memcpy(c->data, data, len);
        c->len = len;
        st = begin(c, node, index, sub, ST_DN_INIT, now_ns);
    }
    return st;
}

static bool same_object(const c4g_co_sdo_client_t *c, const c4g_co_frame_t *f)
{
    return (c4g_get_le(&f->data[1], 2U) == c->index) && (f->data[3] == c->sub);
}

static void rx_upload_init(c4g_co_sdo_client_t *c, const c4g_co_frame_t *f, uint64_t now_ns)
{
    const uint32_t b = f->data[0];
    const uint32_t n = (b >> 2U) & 3U;
    if ((b & 0x02U) != 0U) {
        /* expedited: the size is 4 - n if indicated, else 4 */
        c->len = 4U;
        if ((b & 0x01U) != 0U) {
            c->len = (uint16_t)(4U - n);
        }
        (void)memcpy(c->data, &f->data[4], c->len);
        finish(c, (uint8_t)C4G_CO_SDO_OK, 0U);
    } else {
        const uint32_t size = ((b & 0x01U) != 0U) ? c4g_get_le(&f->data[4], 4U)
                                                   : C4G_CO_SDO_MAX;
        if (size > C4G_CO_SDO_MAX) {
            client_abort(c, (uint8_t)C4G_CO_SDO_PROTOCOL, C4G_CO_ABORT_MEMORY);
        } else {
            c->len = (uint16_t)size;
            c->state = ST_UP_SEG;
            send_request(c, now_ns);
        }
    }
}

static void rx_upload_seg(c4g_co_sdo_client_t *c, const c4g_co_frame_t *f, uint64_t now_ns)
{
    const uint32_t b = f->data[0];
    const uint32_t n = 7U - ((b >> 1U) & 7U);
    if (((b >> 4U) & 1U) != c->toggle) {
        client_abort(c, (uint8_t)C4G_CO_SDO_PROTOCOL, C4G_CO_ABORT_TOGGLE);
    } else if (((uint32_t)c->pos + n) > c->len) {
        client_abort(c, (uint8_t)C4G_CO_SDO_PROTOCOL, C4G_CO_ABORT_TYPE_HIGH);
    } else {
        (void)memcpy(&c->data[c->pos], &f->data[1], n);
        c->pos = (uint16_t)(c->pos + n);
        if ((b & 0x01U) != 0U) {
            c->len = c->pos;
            finish(c, (uint8_t)C4G_CO_SDO_OK, 0U);
        } else {
            c->toggle ^= 1U;
            send_request(c, now_ns);
        }
    }
}

static void rx_download_seg(c4g_co_sdo_client_t *c, const c4g_co_frame_t *f, uint64_t now_ns)
{
    const uint16_t left = (uint16_t)(c->len - c->pos);
    if ((((uint32_t)f->data[0] >> 4U) & 1U) != c->toggle) {
        client_abort(c, (uint8_t)C4G_CO_SDO_PROTOCOL, C4G_CO_ABORT_TOGGLE);
    } else if (left <= 7U) {
        c->pos = c->len;
        finish(c, (uint8_t)C4G_CO_SDO_OK, 0U);
    } else {
        c->pos = (uint16_t)(c->pos + 7U);
        c->toggle ^= 1U;
        send_request(c, now_ns);
    }
}

/* The answer's server command specifier for each phase. */
static uint8_t expected_scs(uint8_t state)
{
    uint8_t scs = SCS_DN_SEG;
    if (state == ST_UP_INIT) {
        scs = SCS_UP_INIT;
    } else if (state == ST_UP_SEG) {
        scs = SCS_UP_SEG;
    } else if (state == ST_DN_INIT) {
        scs = SCS_DN_INIT;
    } else {
        scs = SCS_DN_SEG;
    }
    return scs;
}

static void rx_answer(c4g_co_sdo_client_t *c, const c4g_co_frame_t *f)
{
    const uint8_t scs = (uint8_t)((uint32_t)f->data[0] >> 5U);
    const bool init = (c->state == ST_UP_INIT) || (c->state == ST_DN_INIT);
    if (scs == SCS_ABORT) {
        if (same_object(c, f)) {
            finish(c, (uint8_t)C4G_CO_SDO_ABORTED, c4g_get_le(&f->data[4], 4U));
        } else {
            c->ignored++;
        }
    } else if (scs != expected_scs(c->state)) {
        client_abort(c, (uint8_t)C4G_CO_SDO_PROTOCOL, C4G_CO_ABORT_COMMAND);
    } else if (init && !same_object(c, f)) {
        c->ignored++; /* a late answer to another request: not ours */
    } else if (c->state == ST_UP_INIT) {
        rx_upload_init(c, f, f->t_ns);
    } else if (c->state == ST_UP_SEG) {
        rx_upload_seg(c, f, f->t_ns);
    } else if (c->state == ST_DN_INIT) {
        if (c->len <= 4U) {
            finish(c, (uint8_t)C4G_CO_SDO_OK, 0U);
        } else {
            c->state = ST_DN_SEG;
            send_request(c, f->t_ns);
        }
    } else {
        rx_download_seg(c, f, f->t_ns);
    }
}

c4g_status_t c4g_co_sdo_rx(c4g_co_sdo_client_t *c, const c4g_co_frame_t *f)
{
    c4g_status_t st = C4G_OK;
    if ((c == NULL) || (f == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((c->node == 0U) || (f->id != (uint16_t)(C4G_CO_COB_SDO_TX + c->node))) {
        /* another node's channel: not for this client */
    } else if ((c->state == ST_IDLE) || (f->dlc != 8U) || (f->rtr != 0U)) {
        c->ignored++;
    } else {
        rx_answer(c, f);
    }
    return st;
}

c4g_status_t c4g_co_sdo_poll(c4g_co_sdo_client_t *c, uint64_t now_ns)
{
    c4g_status_t st = C4G_OK;
    if (c == NULL) {
        st = C4G_ERR_NULL;
    } else if ((c->state != ST_IDLE) && (now_ns >= c->deadline_ns)) {
        if (c->tries_left > 0U) {
            c->tries_left--;
            c->state = ((c->state == ST_UP_INIT) || (c->state == ST_UP_SEG)) ? ST_UP_INIT
                                                                              : ST_DN_INIT;
            c->pos = 0U;
            c->toggle = 0U;
            send_request(c, now_ns);
        } else {
            client_abort(c, (uint8_t)C4G_CO_SDO_TIMEOUT, C4G_CO_ABORT_TIMEOUT);
        }
    } else {
        /* nothing due */
    }
    return st;
}

c4g_status_t c4g_co_sdo_take(c4g_co_sdo_client_t *c, c4g_co_frame_t *f, bool *have)
{
    c4g_status_t st = C4G_OK;
    if ((c == NULL) || (f == NULL) || (have == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        *have = (c->out_ready != 0U);
        if (*have) {
            *f = c->out;
            c->out_ready = 0U;
        }
    }
    return st;
}

c4g_status_t c4g_co_sdo_value(const c4g_co_sdo_client_t *c, uint32_t *value)
{
    c4g_status_t st = C4G_OK;
    if ((c == NULL) || (value == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((c->result != (uint8_t)C4G_CO_SDO_OK) || (c->len == 0U)) {
        st = C4G_ERR_STATE;
    } else {
        *value = c4g_get_le(c->data, (c->len < 4U) ? c->len : 4U);
    }
    return st;
}
