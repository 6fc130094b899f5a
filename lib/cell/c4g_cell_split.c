/* SPDX-License-Identifier: MIT */
/* Cell protocol: streaming line splitter over a caller-owned buffer (TCP reads). */
#include "c4gopen.h"
#include <string.h>

#define SPLIT_MIN_CAP 4U /* "OK\r\n", the shortest line of the protocol */

c4g_status_t c4g_cell_split_init(c4g_cell_splitter_t *sp, char *buf, size_t cap)
{
    c4g_status_t st = C4G_OK;
    if ((sp == NULL) || (buf == NULL)) {
        st = C4G_ERR_NULL;
    } else if (cap < SPLIT_MIN_CAP) {
        st = C4G_ERR_ARG;
    } else {
        sp->buf = buf;
        sp->cap = cap;
        sp->head = 0U;
        sp->tail = 0U;
        sp->dropping = 0U;
    }
    return st;
}

c4g_status_t c4g_cell_split_push(c4g_cell_splitter_t *sp, const char *data, size_t n,
                                      size_t *used)
{
    c4g_status_t st = C4G_OK;
    if ((sp == NULL) || (used == NULL) || (sp->buf == NULL) || ((data == NULL) && (n != 0U))) {
        st = C4G_ERR_NULL;
    } else {
        size_t k = 0U;
        if (sp->head > 0U) {
            /* Compact: lines handed out before this call are no longer valid. */
            const size_t left = sp->tail - sp->head;
            (void)memmove(sp->buf, &sp->buf[sp->head], left);
            sp->head = 0U;
            sp->tail = left;
        }
        k = sp->cap - sp->tail;
        if (n < k) {
            k = n;
        }
        if (k > 0U) {
            (void)memcpy(&sp->buf[sp->tail], data, k);
        }
        sp->tail += k;
        *used = k;
    }
    return st;
}

/* Index of the first LF in buf[from, to), or to. */
static size_t find_lf(const char *buf, size_t from, size_t to)
{
    size_t i = from;
    while ((i < to) && (buf[i] != '\n')) {
        i++;
    }
    return i;
}

c4g_status_t c4g_cell_split_next(c4g_cell_splitter_t *sp, c4g_cell_split_event_t *ev,
                                      const char **line, size_t *len)
{
    c4g_status_t st = C4G_OK;
    if ((sp == NULL) || (ev == NULL) || (line == NULL) || (len == NULL) || (sp->buf == NULL)) {
        st = C4G_ERR_NULL;
    } else {
        uint32_t done = 0U;
        *ev = C4G_CELL_SPLIT_NONE;
        /* Each pass consumes bytes or finishes, so at most two passes run. */
        while (done == 0U) {
            const size_t lf = find_lf(sp->buf, sp->head, sp->tail);
            if (lf < sp->tail) {
                if (sp->dropping != 0U) {
                    sp->dropping = 0U; /* end of the overlong line: resume */
                    sp->head = lf + 1U;
                } else {
                    *line = &sp->buf[sp->head];
                    *len = (lf + 1U) - sp->head;
                    sp->head = lf + 1U;
                    *ev = C4G_CELL_SPLIT_LINE;
                    done = 1U;
                }
            } else {
                if (sp->dropping != 0U) {
                    sp->head = 0U;
                    sp->tail = 0U;
                } else if ((sp->tail - sp->head) >= sp->cap) {
                    /* Full buffer without LF: the line is too long. */
                    sp->head = 0U;
                    sp->tail = 0U;
                    sp->dropping = 1U;
                    *ev = C4G_CELL_SPLIT_OVERLONG;
                } else {
                    /* partial line: wait for more bytes */
                }
                done = 1U;
            }
        }
    }
    return st;
}
