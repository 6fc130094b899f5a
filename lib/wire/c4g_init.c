/* SPDX-License-Identifier: MIT */
/* Initialization packet (1200 bytes, 300 little-endian fields) and the axis index maps. */
#include "../c4g_internal.h"
#include "c4g_wire_hot.h"

#define PER_ARM_BYTES (4U * C4G_AXES_PER_ARM)
#define MAX_PERIOD_MS 1000
#define PER_BLOCK_WORDS ((size_t)C4G_ARMS * C4G_AXES_PER_ARM) /* a block of 40 values */

typedef int32_t arm_ints_t[C4G_ARMS][C4G_AXES_PER_ARM];
typedef float arm_floats_t[C4G_ARMS][C4G_AXES_PER_ARM];

static uint32_t block_off(uint32_t base, uint32_t arm, uint32_t axis)
{
    return base + (arm * PER_ARM_BYTES) + (4U * axis);
}

static void put_ints(uint8_t *buf, uint32_t base, const arm_ints_t src)
{
    uint32_t arm;
    uint32_t ax;
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        for (ax = 0U; ax < C4G_AXES_PER_ARM; ax++) {
            c4g_put_i32le(&buf[block_off(base, arm, ax)], src[arm][ax]);
        }
    }
}

static void put_floats(uint8_t *buf, uint32_t base, const arm_floats_t src)
{
    uint32_t arm;
    uint32_t ax;
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        for (ax = 0U; ax < C4G_AXES_PER_ARM; ax++) {
            c4g_put_f32le(&buf[block_off(base, arm, ax)], src[arm][ax]);
        }
    }
}

/* Every float of a block finite; @p nonneg additionally demands >= 0. */
static c4g_status_t check_floats(const arm_floats_t v, uint32_t base, c4g_field_t field,
                                 int nonneg, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t arm;
    uint32_t ax;
    for (arm = 0U; (arm < C4G_ARMS) && (st == C4G_OK); arm++) {
        for (ax = 0U; (ax < C4G_AXES_PER_ARM) && (st == C4G_OK); ax++) {
            const float f = v[arm][ax];
            if (c4g_f32_finite(f) == 0) {
                st = C4G_ERR_NONFINITE;
            } else if ((nonneg != 0) && (f < 0.0F)) {
                st = C4G_ERR_RANGE;
            } else {
                continue;
            }
            c4g_diag_set(diag, st, field, block_off(base, arm, ax), (int32_t)arm, (int32_t)ax,
                         (int64_t)c4g_f32_bits(f));
        }
    }
    return st;
}

static c4g_status_t check_header(const c4g_init_t *in, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    if (in->num != C4G_INIT_NUM) {
        st = C4G_ERR_NUM;
        c4g_diag_set(diag, st, C4G_FIELD_NUM, 0U, -1, -1, in->num);
    } else if (in->n_field_pck != C4G_FIELDS_PER_PACKET) {
        st = C4G_ERR_INIT_FIELDS;
        c4g_diag_set(diag, st, C4G_FIELD_NFIELDPCK, 4U, -1, -1, in->n_field_pck);
    } else if (in->n_field_ax != C4G_FIELDS_PER_AXIS) {
        st = C4G_ERR_INIT_FIELDS;
        c4g_diag_set(diag, st, C4G_FIELD_NFIELDAX, 8U, -1, -1, in->n_field_ax);
    } else if ((in->n_ax_open < 1) || (in->n_ax_open > (int32_t)C4G_MAX_AXES)) {
        st = C4G_ERR_AXES;
        c4g_diag_set(diag, st, C4G_FIELD_NAXOPEN, 12U, -1, -1, in->n_ax_open);
    } else if ((in->period_ms < 1) || (in->period_ms > MAX_PERIOD_MS)) {
        st = C4G_ERR_PERIOD;
        c4g_diag_set(diag, st, C4G_FIELD_PERIOD, C4G_INIT_OFF_PERIOD, -1, -1, in->period_ms);
    } else {
        /* header consistent */
    }
    return st;
}

/* Start-up modes of the open axes only: field tools fill OpenMask with -1 for axes that are
 * not open (the field library initialises the whole array so), and the value carries no
 * meaning there. */
static c4g_status_t check_modes(const c4g_init_t *in, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t arm;
    uint32_t ax;
    for (arm = 0U; (arm < C4G_ARMS) && (st == C4G_OK); arm++) {
        for (ax = 0U; (ax < C4G_AXES_PER_ARM) && (st == C4G_OK); ax++) {
            const int32_t m = in->open_mask[arm][ax];
            /* 0xFF: open, start-up mode not specified (manual chapter 10). */
            if ((in->open_ax[arm][ax] != C4G_OPEN_AX_NONE) && (m != C4G_OPEN_AX_NONE) &&
                (!c4g_mode_is_known(m))) {
                st = C4G_ERR_MODE;
                c4g_diag_set(diag, st, C4G_FIELD_OPENMASK,
                             block_off(C4G_INIT_OFF_OPENMASK, arm, ax), (int32_t)arm,
                             (int32_t)ax, m);
            }
        }
    }
    return st;
}

/* An open axis with a current limit of 0 or below would let no current through, or turn
 * every clamp into a current the PC never asked for: such a packet is refused (the values
 * are finite: check_floats ran first). */
static c4g_status_t check_az_lim(const c4g_init_t *in, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t arm;
    uint32_t ax;
    for (arm = 0U; (arm < C4G_ARMS) && (st == C4G_OK); arm++) {
        for (ax = 0U; (ax < C4G_AXES_PER_ARM) && (st == C4G_OK); ax++) {
            const float f = in->az_lim[arm][ax];
            if ((in->open_ax[arm][ax] != C4G_OPEN_AX_NONE) && (f <= 0.0F)) {
                st = C4G_ERR_RANGE;
                c4g_diag_set(diag, st, C4G_FIELD_AZLIM, block_off(C4G_INIT_OFF_AZLIM, arm, ax),
                             (int32_t)arm, (int32_t)ax, (int64_t)c4g_f32_bits(f));
            }
        }
    }
    return st;
}

/* OpenAx: 0..nAxOpen-1 or 0xFF, each OPEN index exactly once. Fills @p map if given. */
static c4g_status_t check_open_ax(const c4g_init_t *in, c4g_axis_map_t *map, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint8_t used[C4G_MAX_AXES];
    uint32_t count = 0U;
    uint32_t arm;
    uint32_t ax;
    (void)memset(used, 0, sizeof used);
    if (map != NULL) {
        (void)memset(map, 0, sizeof *map);
        (void)memset(map->open_of, C4G_OPEN_AX_NONE, sizeof map->open_of);
    }
    for (arm = 0U; (arm < C4G_ARMS) && (st == C4G_OK); arm++) {
        for (ax = 0U; (ax < C4G_AXES_PER_ARM) && (st == C4G_OK); ax++) {
            const int32_t v = in->open_ax[arm][ax];
            if (v == C4G_OPEN_AX_NONE) {
                continue;
            }
            if ((v < 0) || (v >= in->n_ax_open) || (used[v] != 0U)) {
                st = C4G_ERR_INIT_MAP;
                c4g_diag_set(diag, st, C4G_FIELD_OPENAX, block_off(C4G_INIT_OFF_OPENAX, arm, ax),
                             (int32_t)arm, (int32_t)ax, v);
            } else {
                used[v] = 1U;
                count++;
                if (map != NULL) {
                    map->arm_of[v] = (uint8_t)arm;
                    map->logical_of[v] = (uint8_t)ax;
                    map->open_of[arm][ax] = (uint8_t)v;
                    map->n_axes_arm[arm]++;
                }
            }
        }
    }
    if ((st == C4G_OK) && (count != (uint32_t)in->n_ax_open)) {
        st = C4G_ERR_INIT_MAP;
        c4g_diag_set(diag, st, C4G_FIELD_NAXOPEN, 12U, -1, -1, (int64_t)count);
    }
    if ((map != NULL) && (st == C4G_OK)) {
        map->n_axes = count;
    }
    return st;
}

/* 1 when every float of the packet is finite, AzLim and FollowError >= 0 (the checks of
 * check_floats): the NaN/infinity pass on 64-bit lanes (see c4g_axes_carry), then the
 * signs compared as floats, as the ordered checks do once the values are finite. */
static uint32_t floats_ok(const c4g_init_t *in)
{
    uint32_t ok = 0U;
    if ((c4g_axes_carry((const uint8_t *)in->cal_data, PER_BLOCK_WORDS, 0U) |
         c4g_axes_carry((const uint8_t *)in->az_lim, PER_BLOCK_WORDS, 0U) |
         c4g_axes_carry((const uint8_t *)in->ax_info, PER_BLOCK_WORDS, 0U) |
         c4g_axes_carry((const uint8_t *)in->tx_rate, PER_BLOCK_WORDS, 0U) |
         c4g_axes_carry((const uint8_t *)in->follow_error, PER_BLOCK_WORDS, 0U)) == 0U) {
        uint32_t neg = 0U;
        uint32_t arm;
        uint32_t ax;
        for (arm = 0U; arm < C4G_ARMS; arm++) {
            for (ax = 0U; ax < C4G_AXES_PER_ARM; ax++) {
                neg |= c4g_flag(in->az_lim[arm][ax] < 0.0F) |
                       c4g_flag(in->follow_error[arm][ax] < 0.0F);
            }
        }
        ok = neg ^ 1U;
    }
    return ok;
}

/* 1 when every open axis has a valid, unused OPEN index below nAxOpen, a known start-up
 * mode or 0xFF, an AzLim above 0, and nAxOpen of them are open (check_modes, check_open_ax,
 * check_az_lim); @p map is then the axis maps, as check_open_ax builds them. */
static uint32_t open_axes_ok(const c4g_init_t *in, c4g_axis_map_t *map)
{
    uint8_t used[C4G_MAX_AXES];
    uint32_t bad = 0U;
    uint32_t count = 0U;
    uint32_t arm;
    uint32_t ax;
    (void)memset(used, 0, sizeof used);
    (void)memset(map, 0, sizeof *map);
    (void)memset(map->open_of, C4G_OPEN_AX_NONE, sizeof map->open_of);
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        for (ax = 0U; ax < C4G_AXES_PER_ARM; ax++) {
            const int32_t v = in->open_ax[arm][ax];
            const int32_t m = in->open_mask[arm][ax];
            if (v == C4G_OPEN_AX_NONE) {
                continue;
            }
            if ((v < 0) || (v >= in->n_ax_open) || (used[v] != 0U) || (in->az_lim[arm][ax] <= 0.0F) ||
                ((m != C4G_OPEN_AX_NONE) && (mode_unknown_fast(m) != 0U))) {
                bad = 1U;
            } else {
                used[v] = 1U;
                count++;
                map->arm_of[v] = (uint8_t)arm;
                map->logical_of[v] = (uint8_t)ax;
                map->open_of[arm][ax] = (uint8_t)v;
                map->n_axes_arm[arm]++;
            }
        }
    }
    map->n_axes = count;
    return c4g_flag((bad == 0U) && (count == (uint32_t)in->n_ax_open));
}

/* Every check of c4g_init_validate, without naming the first failure: 1 when the packet
 * passes them all (and @p map is its axis maps), 0 when one fails (c4g_init_validate then
 * runs the checks in their order and names the first). */
static uint32_t init_ok_fast(const c4g_init_t *in, c4g_axis_map_t *map)
{
    uint32_t ok = 0U;
    if ((in->num == C4G_INIT_NUM) && (in->n_field_pck == C4G_FIELDS_PER_PACKET) &&
        (in->n_field_ax == C4G_FIELDS_PER_AXIS) && (in->n_ax_open >= 1) &&
        (in->n_ax_open <= (int32_t)C4G_MAX_AXES) && (in->period_ms >= 1) &&
        (in->period_ms <= MAX_PERIOD_MS) && (floats_ok(in) != 0U)) {
        ok = open_axes_ok(in, map);
    }
    return ok;
}

/* The checks in their order, the first failure named (every check of init_ok_fast). */
static c4g_status_t init_validate_ordered(const c4g_init_t *init, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_ERR_NULL;
    c4g_diag_set(diag, C4G_OK, C4G_FIELD_NONE, 0U, -1, -1, 0);
    if (init != NULL) {
        st = check_header(init, diag);
        if (st == C4G_OK) {
            st = check_modes(init, diag);
        }
        if (st == C4G_OK) {
            st = check_open_ax(init, NULL, diag);
        }
        if (st == C4G_OK) {
            st = check_floats(init->cal_data, C4G_INIT_OFF_CALDATA, C4G_FIELD_CALDATA, 0, diag);
        }
        if (st == C4G_OK) {
            st = check_floats(init->az_lim, C4G_INIT_OFF_AZLIM, C4G_FIELD_AZLIM, 1, diag);
        }
        if (st == C4G_OK) {
            st = check_az_lim(init, diag);
        }
        if (st == C4G_OK) {
            st = check_floats(init->ax_info, C4G_INIT_OFF_AXINFO, C4G_FIELD_AXINFO, 0, diag);
        }
        if (st == C4G_OK) {
            st = check_floats(init->tx_rate, C4G_INIT_OFF_TXRATE, C4G_FIELD_TXRATE, 0, diag);
        }
        if (st == C4G_OK) {
            st = check_floats(init->follow_error, C4G_INIT_OFF_FOLLOWERROR,
                              C4G_FIELD_FOLLOWERROR, 1, diag);
        }
    } else {
        c4g_diag_set(diag, st, C4G_FIELD_NONE, 0U, -1, -1, 0);
    }
    return st;
}

c4g_status_t c4g_init_validate(const c4g_init_t *init, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_ERR_NULL;
    c4g_axis_map_t map;
    if ((init != NULL) && (init_ok_fast(init, &map) != 0U)) {
        st = C4G_OK;
        c4g_diag_set(diag, C4G_OK, C4G_FIELD_NONE, 0U, -1, -1, 0);
    } else {
        st = init_validate_ordered(init, diag);
    }
    return st;
}

/* c4g_init_t holds the packet's 300 words in the packet's order, 4 bytes each without
 * padding (tests/lib/test_init.c checks every block's offset): the packet is one copy into
 * host order, then one pass of checks that also builds the axis maps. */
c4g_status_t c4g_init_decode_map(const uint8_t *buf, size_t len, c4g_init_t *out,
                                 c4g_axis_map_t *map, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_ERR_NULL;
    c4g_diag_set(diag, st, C4G_FIELD_NONE, 0U, -1, -1, 0);
    if ((buf != NULL) && (out != NULL)) {
        if (len != C4G_INIT_SIZE) {
            (void)memset(out, 0, sizeof *out);
            st = C4G_ERR_LENGTH;
            c4g_diag_set(diag, st, C4G_FIELD_LENGTH, 0U, -1, -1, (int64_t)len);
        } else {
            /* Deviation D-02 (MISRA 21.15): the packet's words into the struct of them. */
            /* cppcheck-suppress misra-c2012-21.15 */
            c4g_words_le((uint8_t *)out, buf, (size_t)C4G_INIT_SIZE / 4U, c4g_host_big_endian());
            if (init_ok_fast(out, map) != 0U) {
                st = C4G_OK;
                c4g_diag_set(diag, st, C4G_FIELD_NONE, 0U, -1, -1, 0);
            } else {
                st = init_validate_ordered(out, diag);
            }
        }
    }
    return st;
}

c4g_status_t c4g_init_decode(const uint8_t *buf, size_t len, c4g_init_t *out, c4g_diag_t *diag)
{
    c4g_axis_map_t map;
    return c4g_init_decode_map(buf, len, out, &map, diag);
}

c4g_status_t c4g_init_encode(const c4g_init_t *init, uint8_t *buf, size_t cap, size_t *out_len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((init != NULL) && (buf != NULL) && (out_len != NULL)) {
        *out_len = 0U;
        st = c4g_init_validate(init, NULL);
        if ((st == C4G_OK) && (cap < C4G_INIT_SIZE)) {
            st = C4G_ERR_CAPACITY;
        }
        if (st == C4G_OK) {
            uint32_t k;
            c4g_put_i32le(&buf[0], init->num);
            c4g_put_i32le(&buf[4], init->n_field_pck);
            c4g_put_i32le(&buf[8], init->n_field_ax);
            c4g_put_i32le(&buf[12], init->n_ax_open);
            put_ints(buf, C4G_INIT_OFF_OPENMASK, init->open_mask);
            for (k = 0U; k < C4G_N_FIELD_TYPES; k++) {
                c4g_put_i32le(&buf[C4G_INIT_OFF_TYPES + (4U * k)], init->field_type[k]);
            }
            c4g_put_i32le(&buf[C4G_INIT_OFF_PERIOD], init->period_ms);
            put_ints(buf, C4G_INIT_OFF_OPENAX, init->open_ax);
            put_floats(buf, C4G_INIT_OFF_CALDATA, init->cal_data);
            put_floats(buf, C4G_INIT_OFF_AZLIM, init->az_lim);
            c4g_put_i32le(&buf[C4G_INIT_OFF_VERSION], init->version_major);
            c4g_put_i32le(&buf[C4G_INIT_OFF_VERSION + 4U], init->version_minor);
            c4g_put_i32le(&buf[C4G_INIT_OFF_VERSION + 8U], init->version_build);
            put_floats(buf, C4G_INIT_OFF_AXINFO, init->ax_info);
            put_floats(buf, C4G_INIT_OFF_TXRATE, init->tx_rate);
            put_floats(buf, C4G_INIT_OFF_FOLLOWERROR, init->follow_error);
            *out_len = C4G_INIT_SIZE;
        }
    }
    return st;
}

c4g_status_t c4g_axis_map_build(const c4g_init_t *init, c4g_axis_map_t *map, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_ERR_NULL;
    c4g_diag_set(diag, C4G_OK, C4G_FIELD_NONE, 0U, -1, -1, 0);
    if ((init != NULL) && (map != NULL)) {
        st = check_header(init, diag);
        if (st == C4G_OK) {
            st = check_open_ax(init, map, diag);
        }
        if (st != C4G_OK) {
            (void)memset(map, 0, sizeof *map);
        }
    }
    return st;
}
