/* SPDX-License-Identifier: MIT */
/* The datagram classifier: what a datagram is by length and content, before any decode
 * (one place for the length rules the hosts and the capture analysis apply). */
#include "../c4g_internal.h"

c4g_status_t c4g_peek(const uint8_t *buf, size_t len, bool startup, c4g_peek_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((out != NULL) && ((buf != NULL) || (len == 0U))) {
        size_t body = 0U;
        size_t n;
        if (len >= C4G_HEADER_SIZE) {
            body = len - C4G_HEADER_SIZE;
        }
        n = body / C4G_AXIS_SIZE;
        out->kind = C4G_PKT_FOREIGN;
        out->num = (len >= 4U) ? c4g_get_i32le(buf) : -1;
        out->n_axes = 0U;
        if ((len == C4G_INIT_SIZE) && (c4g_get_i32le(&buf[4]) == C4G_FIELDS_PER_PACKET) &&
            (c4g_get_i32le(&buf[8]) == C4G_FIELDS_PER_AXIS)) {
            out->kind = C4G_PKT_INIT;
        } else if ((len > C4G_HEADER_SIZE) && ((body % C4G_AXIS_SIZE) == 0U) && (n <= C4G_MAX_AXES)) {
            out->kind = startup ? C4G_PKT_SYNC : C4G_PKT_CYCLIC;
            out->n_axes = (uint32_t)n;
        } else {
            /* foreign */
        }
        st = C4G_OK;
    }
    return st;
}
