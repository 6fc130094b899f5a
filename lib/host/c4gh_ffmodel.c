/* SPDX-License-Identifier: MIT */
/* The identified feedforward model (c4g_ffmodel.h): checksum and evaluation. Kept apart
 * from the parser so that a caller of these (c4g-ident, the server's real-time path)
 * links neither inih nor the text-file layer. No allocation. */
#include "c4gh_ffmodel.h"

#include <math.h>

uint64_t c4gh_ffm_fnv1a64(const void *data, size_t len, uint64_t h)
{
    const unsigned char *p = data;
    size_t i;
    for (i = 0U; i < len; i++) {
        h ^= (uint64_t)p[i];
        h *= C4GH_FFM_FNV_PRIME;
    }
    return h;
}

/* "checksum" then optional blanks and '=' or ':' (inih's separators) at @p s. */
static int ffm_is_checksum_key(const char *s, size_t n)
{
    static const char key[] = "checksum";
    const size_t kl = sizeof key - 1U;
    size_t i;
    if (n < kl) {
        return 0;
    }
    for (i = 0U; i < kl; i++) {
        if (s[i] != key[i]) {
            return 0;
        }
    }
    while (i < n && (s[i] == ' ' || s[i] == '\t')) {
        i++;
    }
    return i < n && (s[i] == '=' || s[i] == ':');
}

int c4gh_ffm_checksum_span(const char *text, size_t len, size_t *start, size_t *end)
{
    size_t b = 0U;
    while (b < len) {
        size_t e = b;
        size_t k = b;
        while (e < len && text[e] != '\n') {
            e++;
        }
        while (k < e && (text[k] == ' ' || text[k] == '\t')) {
            k++;
        }
        if (ffm_is_checksum_key(text + k, e - k)) {
            *start = b;
            *end = (e < len) ? e + 1U : e; /* through its LF */
            return 0;
        }
        b = e + 1U;
    }
    return -1;
}

int c4gh_ffm_checksum_text(const char *text, size_t len, uint64_t *sum)
{
    size_t s = 0U;
    size_t e = 0U;
    if (c4gh_ffm_checksum_span(text, len, &s, &e) != 0) {
        *sum = c4gh_ffm_fnv1a64(text, len, C4GH_FFM_FNV_BASIS);
        return -1;
    }
    *sum = c4gh_ffm_fnv1a64(text + e, len - e, c4gh_ffm_fnv1a64(text, s, C4GH_FFM_FNV_BASIS));
    return 0;
}

void c4gh_ffm_checksum_format(uint64_t sum, char out[25])
{
    static const char hex[] = "0123456789abcdef";
    static const char pre[] = "fnv1a64:";
    unsigned i;
    for (i = 0U; i < 8U; i++) {
        out[i] = pre[i];
    }
    for (i = 0U; i < 16U; i++) {
        out[8U + i] = hex[(sum >> (60U - 4U * i)) & 0xFU];
    }
    out[24] = '\0';
}

/* Fv v + the Coulomb/Stribeck level times the smooth sign + off: both models' friction. */
static double ffm_friction(const c4gh_ffm_axis_t *p, double v)
{
    double level = p->fc;
    double dir;
    if (p->vs > 0.0) {
        const double r = v / p->vs;
        level += (p->fs - p->fc) * exp(-r * r);
    }
    if (p->eps > 0.0) {
        dir = tanh(v / p->eps); /* smooth sign: no chatter around v = 0 */
    } else {
        dir = (v > 0.0) ? 1.0 : ((v < 0.0) ? -1.0 : 0.0);
    }
    return p->fv * v + level * dir + p->off;
}

double c4gh_ffm_current(const c4gh_ffm_axis_t *p, double v, double a, double q, int have_q)
{
    double i = p->ja * a + ffm_friction(p, v);
    if (have_q) {
        i += p->ga * cos(q) + p->gb * sin(q);
    }
    return i;
}

double c4gh_ffm_current_ctrl(const c4gh_ffm_axis_t *p, double v, double a, double ext1, double ext2)
{
    static const double two_pi = 6.283185307179586;
    const double in = p->ks * ext2 * two_pi * a; /* EXT1's inertial part */
    return p->k1 * (ext1 - in) + p->k2 * in + ffm_friction(p, v);
}
