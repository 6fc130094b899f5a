/* SPDX-License-Identifier: MIT */
/* NUM arithmetic and the reply NUM policy: the one definition the PC end, the controller
 * end and the capture analysis share (the 15-bit counter and its wrap live only here). */
#include "../c4g_internal.h"

#define NUM_MASK ((uint32_t)C4G_NUM_MODULO - 1U)

int32_t c4g_reply_num(int32_t num, c4g_num_policy_t policy)
{
    return c4g_reply_num_inline(num, policy);
}

int32_t c4g_num_next(int32_t num)
{
    return (num >= C4G_NUM_MAX) ? 0 : (num + 1);
}

int32_t c4g_num_delta(int32_t from, int32_t to)
{
    return c4g_num_wrap_delta(from, to);
}

bool c4g_num_accepts(c4g_num_policy_t policy, int32_t sent, int32_t got)
{
    const bool plus = (got == c4g_reply_num(sent, C4G_NUM_PLUS_ONE));
    const bool echo = (got == sent);
    bool ok = plus || echo; /* C4G_NUM_EITHER */
    if (policy == C4G_NUM_PLUS_ONE) {
        ok = plus;
    } else if (policy == C4G_NUM_ECHO) {
        ok = echo;
    } else {
        /* either */
    }
    return ok;
}

bool c4g_num_answers_recent(c4g_num_policy_t policy, int32_t cur, int32_t got, int32_t window)
{
    /* echo: got answers packet got; plus-one: packet got - 1 (one further back) */
    const int32_t d_echo = c4g_num_delta(got, cur);
    const uint32_t plus_u = ((uint32_t)d_echo + 1U) & NUM_MASK;
    const int32_t d_plus = (int32_t)plus_u;
    const bool echo = (policy != C4G_NUM_PLUS_ONE) && (d_echo >= 1) && (d_echo <= window);
    const bool plus = (policy != C4G_NUM_ECHO) && (d_plus >= 1) && (d_plus <= window);
    return echo || plus;
}

static const char *const policy_names[3] = {"plus-one", "echo", "either"};

const char *c4g_num_policy_name(int policy)
{
    const char *n = "unknown";
    if ((policy >= 0) && (policy <= (int)C4G_NUM_EITHER)) {
        n = policy_names[policy];
    }
    return n;
}

/* 1 if the NUL-terminated @p a equals @p b (the library links no string functions but
 * memcpy/memset/memcmp; the names are short and bounded). */
static bool name_is(const char *a, const char *b)
{
    uint32_t i = 0U;
    bool same = true;
    bool end = false;
    while (same && !end && (i < 16U)) {
        same = (a[i] == b[i]);
        end = (b[i] == '\0');
        i++;
    }
    return same && end;
}

c4g_status_t c4g_num_policy_parse(const char *name, c4g_num_policy_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((name != NULL) && (out != NULL)) {
        uint32_t i;
        st = C4G_ERR_ARG;
        for (i = 0U; i < 3U; i++) {
            if (name_is(name, policy_names[i])) {
                *out = (c4g_num_policy_t)i;
                st = C4G_OK;
            }
        }
    }
    return st;
}
