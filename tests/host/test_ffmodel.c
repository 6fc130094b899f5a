/* SPDX-License-Identifier: MIT */
/* c4g-ident's mode-9 parameter file and model (lib/host/c4gh_ffmodel.{h,c},
 * c4g_ffmodel_load.c): FNV-1a values, the checksum line left out of the sum, a good
 * file read exactly, every refusal naming FILE:LINE:COL, [section] and key, and the
 * model's current against values worked out by hand. Tool sources included directly. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "c4gh_textfile.h"
#include "c4gh_ffmodel.h"

#define PI 3.14159265358979323846
#define near(a, b, eps) assert_true(fabs((double)(a) - (double)(b)) < (eps))

/* A file as c4g-ident writes it; seal() fills the checksum in. Lines numbered for the
 * expected messages below. */
static const char GOOD[] =
    "# c4g-ident parameter file\n"             /* 1 */
    "[model]\n"                                /* 2 */
    "format = c4g-ident 1\n"                   /* 3 */
    "model = motor-current-1\n"                /* 4 */
    "arm = 2\n"                                /* 5 */
    "period_ms = 2\n"                          /* 6 */
    "source = run.pcap\n"                      /* 7 */
    "created_by = c4g-ident 1.0.0\n"           /* 8 */
    "checksum = fnv1a64:0000000000000000\n"    /* 9 */
    "\n"                                       /* 10 */
    "[axis 2]\n"                               /* 11 */
    "variant = stribeck+gravity\n"             /* 12 */
    "Ja = 0.00314159\n"                        /* 13 */
    "Fv = 0.00785\n"                           /* 14 */
    "Fc = 0.1875\n"                            /* 15 */
    "Fs = 0.3\n"                               /* 16 */
    "vs = 1.0\n"                               /* 17 */
    "off = 0.025\n"                            /* 18 */
    "ga = 0.5\n"                               /* 19 */
    "gb = -0.25\n"                             /* 20 */
    "eps = 0.01\n"                             /* 21 */
    "delay = -0.21\n"                          /* 22 */
    "v_max = 9.5\n"                            /* 23 */
    "a_max = 120\n"                            /* 24 */
    "\n"                                       /* 25 */
    "; a second axis, optional keys left out\n" /* 26 */
    "[axis 5]\n"                               /* 27 */
    "Ja = 1e-3\n"                              /* 28 */
    "Fv = 0\n"                                 /* 29 */
    "Fc = 0.05\n"                              /* 30 */
    "off = 0\n"                                /* 31 */
    "eps = 0.02\n";                            /* 32 */

static char g_text[4096];
static c4gh_ffm_file_t g_f;

/* Put the right sum into the text's checksum line (16 hex digits after "fnv1a64:"). */
static void seal(char *text)
{
    uint64_t sum = 0U;
    char hex[25];
    char *p = strstr(text, "checksum = fnv1a64:");
    assert_non_null(p);
    assert_int_equal(c4gh_ffm_checksum_text(text, strlen(text), &sum), 0);
    c4gh_ffm_checksum_format(sum, hex);
    memcpy(p + 11, hex, 24U);
}

/* GOOD with the first @p from replaced by @p to (NULL: as is), sealed unless @p raw. */
static const char *edit(const char *from, const char *to, int raw)
{
    char *p;
    strcpy(g_text, GOOD);
    if (from != NULL) {
        p = strstr(g_text, from);
        assert_non_null(p);
        memmove(p + strlen(to), p + strlen(from), strlen(p + strlen(from)) + 1U);
        memcpy(p, to, strlen(to));
    }
    if (!raw && strstr(g_text, "checksum = fnv1a64:") != NULL) {
        seal(g_text);
    }
    return g_text;
}

static int parse(const char *text, char *err, size_t errlen)
{
    return c4gh_ffm_parse_text("m.ini", text, strlen(text), &g_f, err, errlen);
}

static void test_fnv(void **state)
{
    char hex[25];
    uint64_t sum = 0U;
    (void)state;
    assert_true(c4gh_ffm_fnv1a64("", 0U, C4GH_FFM_FNV_BASIS) == 0xcbf29ce484222325ULL);
    assert_true(c4gh_ffm_fnv1a64("a", 1U, C4GH_FFM_FNV_BASIS) == 0xaf63dc4c8601ec8cULL);
    /* the running hash: in pieces as at once */
    assert_true(c4gh_ffm_fnv1a64("bar", 3U, c4gh_ffm_fnv1a64("foo", 3U, C4GH_FFM_FNV_BASIS)) ==
                c4gh_ffm_fnv1a64("foobar", 6U, C4GH_FFM_FNV_BASIS));
    assert_true(c4gh_ffm_fnv1a64("foobar", 6U, C4GH_FFM_FNV_BASIS) == 0x85944171f73967e8ULL);
    c4gh_ffm_checksum_format(0xaf63dc4c8601ec8cULL, hex);
    assert_string_equal(hex, "fnv1a64:af63dc4c8601ec8c");
    c4gh_ffm_checksum_format(0x0123456789abcdefULL, hex);
    assert_string_equal(hex, "fnv1a64:0123456789abcdef");
    /* no checksum line: -1, the hash of everything */
    assert_int_equal(c4gh_ffm_checksum_text("a", 1U, &sum), -1);
    assert_true(sum == 0xaf63dc4c8601ec8cULL);
}

/* The checksum line, from its first byte through its LF, is all that is left out. */
static void test_checksum_span(void **state)
{
    static const struct {
        const char *text;
        const char *rest; /* the text without its checksum line */
    } t[] = {
        {"a\nchecksum = x\nb\n", "a\nb\n"},
        {"a\n  \tchecksum=x\r\nb", "a\nb"},          /* indented, CRLF */
        {"a\nchecksum : x", "a\n"},                  /* last line, no LF; ':' separator */
        {"checksum = x\n", ""},
        {"# checksum = no\nchecksums = no\nchecksum = x\nz", "# checksum = no\nchecksums = no\nz"},
    };
    size_t i;
    (void)state;
    for (i = 0U; i < sizeof t / sizeof t[0]; i++) {
        uint64_t sum = 0U;
        assert_int_equal(c4gh_ffm_checksum_text(t[i].text, strlen(t[i].text), &sum), 0);
        assert_true(sum == c4gh_ffm_fnv1a64(t[i].rest, strlen(t[i].rest), C4GH_FFM_FNV_BASIS));
    }
}

static void test_good_file(void **state)
{
    char err[600];
    const c4gh_ffm_axis_t *a;
    unsigned k;
    (void)state;
    assert_int_equal(parse(edit(NULL, NULL, 0), err, sizeof err), 0);
    assert_int_equal(g_f.arm, 2);
    assert_true(g_f.period_ms == 2.0);
    assert_int_equal(g_f.model_line, 2);
    assert_string_equal(g_f.source, "run.pcap");
    assert_string_equal(g_f.created_by, "c4g-ident 1.0.0");
    a = &g_f.ax[1];
    assert_int_equal(a->set, 1);
    assert_int_equal(a->line, 11);
    assert_string_equal(a->variant, "stribeck+gravity");
    /* exactly the decimal values: strtod's nearest double */
    assert_true(a->ja == 0.00314159 && a->fv == 0.00785 && a->fc == 0.1875 && a->fs == 0.3);
    assert_true(a->vs == 1.0 && a->off == 0.025 && a->ga == 0.5 && a->gb == -0.25);
    assert_true(a->eps == 0.01 && a->delay == -0.21 && a->v_max == 9.5 && a->a_max == 120.0);
    a = &g_f.ax[4];
    assert_int_equal(a->set, 1);
    assert_int_equal(a->line, 27);
    assert_string_equal(a->variant, "");
    assert_true(a->ja == 1e-3 && a->fc == 0.05 && a->eps == 0.02);
    /* optional keys left out are 0 */
    assert_true(a->fs == 0.0 && a->vs == 0.0 && a->ga == 0.0 && a->gb == 0.0 && a->delay == 0.0 &&
                a->v_max == 0.0 && a->a_max == 0.0);
    for (k = 0U; k < C4GH_FFM_AXES; k++) {
        if (k != 1U && k != 4U) {
            assert_int_equal(g_f.ax[k].set, 0);
        }
    }
    /* the verified sum is the one in the text */
    {
        char hex[25];
        c4gh_ffm_checksum_format(g_f.checksum, hex);
        assert_non_null(strstr(g_text, hex));
    }
    /* inline comments, blanks around '=', CRLF line ends: same values */
    assert_int_equal(parse(edit("Fc = 0.1875\n", "  Fc=0.1875 ; fitted\r\n", 0), err, sizeof err), 0);
    assert_true(g_f.ax[1].fc == 0.1875);
}

static void test_fixture(void **state)
{
    char err[600];
    (void)state;
    assert_int_equal(c4gh_ffm_load(FIXTURES_DIR "/server/ff_ident_example.ini", &g_f, err, sizeof err), 0);
    assert_int_equal(g_f.arm, 1);
    assert_true(g_f.period_ms == 2.0);
    assert_int_equal(g_f.ax[1].set, 1);
    assert_true(g_f.ax[1].gb == 7.5 && g_f.ax[1].v_max == 9.5 && g_f.ax[1].fs == 0.3);
    /* a file c4g-ident fit --model ctrl wrote (the arm plant; axis 2 was refused) */
    assert_int_equal(c4gh_ffm_load(FIXTURES_DIR "/server/ff_ctrl_example.ini", &g_f, err, sizeof err), 0);
    assert_true(g_f.ax[0].set && g_f.ax[0].ctrl && !g_f.ax[1].set && g_f.ax[2].ctrl);
    assert_true(g_f.ax[2].k2 == 0.9994060861 && g_f.ax[2].ks == 1.224187137);
    assert_int_equal(c4gh_ffm_load(FIXTURES_DIR "/server/no-such.ini", &g_f, err, sizeof err), -1);
    assert_non_null(strstr(err, "no-such.ini: cannot open"));
    assert_int_equal(c4gh_ffm_load("/dev/zero", &g_f, err, sizeof err), -1);
    assert_non_null(strstr(err, "/dev/zero: more than 1048576 bytes"));
}

static void test_refusals(void **state)
{
    static const struct {
        const char *from, *to;
        int raw;            /* leave the checksum as it is */
        const char *msg;
    } bad[] = {
        /* the checksum */
        {"Fc = 0.1875", "Fc = 0.1876", 1,
         "m.ini:9:12: [model] checksum: checksum mismatch: the file was edited after c4g-ident "
         "wrote it (expected fnv1a64:0000000000000000, computed fnv1a64:"},
        {"checksum = fnv1a64:0000000000000000\n", "", 0,
         "m.ini:2:1: [model] checksum: missing (c4g-ident writes one: was the file written by hand?)"},
        {"fnv1a64:0000000000000000", "fnv1a64:00000000000000", 1,
         "m.ini:9:12: [model] checksum: 'fnv1a64:00000000000000' is not 'fnv1a64:' and 16 lowercase hex digits"},
        {"fnv1a64:0000000000000000", "fnv1a64:000000000000000A", 1,
         "m.ini:9:12: [model] checksum: 'fnv1a64:000000000000000A' is not 'fnv1a64:' and 16 lowercase hex digits"},
        /* [model] */
        {"format = c4g-ident 1", "format = c4g-ident 2", 0,
         "m.ini:3:10: [model] format: 'c4g-ident 2' is not 'c4g-ident 1' (the only format this reader knows)"},
        {"format = c4g-ident 1\n", "", 0, "m.ini:2:1: [model] format: missing"},
        {"model = motor-current-1", "model = joint-torque", 0,
         "m.ini:4:9: [model] model: 'joint-torque' is not 'motor-current-1' or 'rigid-body-1' (the models this "
         "reader evaluates)"},
        {"arm = 2", "arm = 5", 0, "m.ini:5:7: [model] arm: '5' is out of range 1..4"},
        {"arm = 2", "arm = 0", 0, "m.ini:5:7: [model] arm: '0' is out of range 1..4"},
        {"arm = 2", "arm = 1.5", 0, "m.ini:5:7: [model] arm: '1.5' is not an integer"},
        {"arm = 2\n", "", 0, "m.ini:2:1: [model] arm: missing"},
        {"period_ms = 2", "period_ms = 0", 0, "m.ini:6:13: [model] period_ms: '0' must be > 0"},
        {"period_ms = 2", "period_ms = inf", 0, "m.ini:6:13: [model] period_ms: 'inf' is not a finite number"},
        {"source = run.pcap", "sauce = run.pcap", 0,
         "m.ini:7:1: [model] sauce: unknown key (want format, model, arm, period_ms, source, created_by, checksum, "
         "range, consistent, base_params)"},
        {"source = run.pcap\n", "source = run.pcap\narm = 3\n", 0,
         "m.ini:8:1: [model] arm: set twice (first on line 5)"},
        /* sections */
        {"[axis 5]", "[axis 11]", 0,
         "m.ini:27:1: unknown section [axis 11] (want [model], [kinematics], [joint 1]..[joint 7] or [axis 1]..[axis 10])"},
        {"[axis 5]", "[axes 5]", 0,
         "m.ini:27:1: unknown section [axes 5] (want [model], [kinematics], [joint 1]..[joint 7] or [axis 1]..[axis 10])"},
        {"\n; a second", "\n[extra]\n; a second", 0, /* an empty one: inih never shows it */
         "m.ini:26:1: unknown section [extra] (want [model], [kinematics], [joint 1]..[joint 7] or [axis 1]..[axis 10])"},
        {"[axis 5]", "[axis 2]", 0, "m.ini:27:1: [axis 2]: section given twice (first on line 11)"},
        {"[axis 5]", "[axis 2]\n[axis 5]", 0, "m.ini:27:1: [axis 2]: section given twice (first on line 11)"},
        {"[model]\n", "[model]\n[model]\n", 0, "m.ini:3:1: [model]: section given twice (first on line 2)"},
        {"# c4g-ident parameter file\n", "stray = 1\n", 0,
         "m.ini:1:1: stray: a key before the first section (want [model] first)"},
        {"[model]", "[model", 0, "m.ini:2:1: '[model': a section header needs a closing ']'"},
        /* [axis N] keys */
        {"Fc = 0.1875", "Fc = nan", 0, "m.ini:15:6: [axis 2] Fc: 'nan' is not a finite number"},
        {"Fc = 0.1875", "Fc = -inf", 0, "m.ini:15:6: [axis 2] Fc: '-inf' is not a finite number"},
        {"Fc = 0.1875", "Fc = -0.1", 0, "m.ini:15:6: [axis 2] Fc: '-0.1' is out of range 0..1000000"},
        {"Fc = 0.1875", "Fc = 0x10", 0, "m.ini:15:6: [axis 2] Fc: '0x10' is not a decimal number"},
        {"Fc = 0.1875", "Fc =", 0, "m.ini:15:5: [axis 2] Fc: missing number"},
        {"off = 0.025", "off = 1e7", 0, "m.ini:18:7: [axis 2] off: '1e7' is out of range -1000000..1000000"},
        {"gb = -0.25", "gb = -1e999", 0, "m.ini:20:6: [axis 2] gb: '-1e999' is out of range -1000000..1000000"},
        {"Ja = 0.00314159", "Ja = 0", 0, "m.ini:13:6: [axis 2] Ja: '0' must be > 0"},
        {"eps = 0.01", "eps = 0.0", 0, "m.ini:21:7: [axis 2] eps: '0.0' must be > 0"},
        {"vs = 1.0", "vs = -1", 0, "m.ini:17:6: [axis 2] vs: '-1' is out of range 0..1000000"},
        {"Fs = 0.3", "Fs = -0.3", 0, "m.ini:16:6: [axis 2] Fs: '-0.3' is out of range 0..1000000"},
        {"v_max = 9.5", "v_max = -9.5", 0, "m.ini:23:9: [axis 2] v_max: '-9.5' is out of range 0..1000000"},
        {"Fv = 0.00785", "Jv = 0.00785", 0,
         "m.ini:14:1: [axis 2] Jv: unknown key (want model, variant, Ja, Fv, Fc, Fs, vs, off, ga, gb, eps, delay, "
         "v_max, a_max, k1, k2, ks)"},
        {"Fv = 0.00785\n", "Fv = 0.00785\nFv = 0.1\n", 0, "m.ini:15:1: [axis 2] Fv: set twice (first on line 14)"},
        {"Fv = 0.00785\n", "", 0,
         "m.ini:11:1: [axis 2] Fv: missing (Ja, Fv, Fc, off and eps are required)"},
        {"eps = 0.02\n", "", 0,
         "m.ini:27:1: [axis 5] eps: missing (Ja, Fv, Fc, off and eps are required)"},
        {"variant = stribeck+gravity", "variant = viscous", 0,
         "m.ini:12:11: [axis 2] variant: 'viscous' is not coulomb, coulomb+gravity, stribeck, stribeck+gravity, "
         "ctrl+coulomb or ctrl+stribeck"},
        /* the families: model = axis or ctrl, each with its own keys */
        {"variant = stribeck+gravity", "model = joint\nvariant = stribeck+gravity", 0,
         "m.ini:12:9: [axis 2] model: 'joint' is not axis or ctrl"},
        {"variant = stribeck+gravity", "model = axis\nvariant = stribeck+gravity\nk1 = 1", 0,
         "m.ini:14:1: [axis 2] k1: not a key of model = axis"},
        {"variant = stribeck+gravity", "variant = ctrl+stribeck", 0,
         "m.ini:12:1: [axis 2] variant: 'ctrl+stribeck' is not a variant of model = axis"},
        {"variant = stribeck+gravity", "model = ctrl\nvariant = ctrl+stribeck\nk1 = 1\nk2 = 1\nks = 1", 0,
         "m.ini:17:1: [axis 2] Ja: not a key of model = ctrl"},
        {"variant = stribeck+gravity\nJa = 0.00314159", "model = ctrl\nvariant = ctrl+stribeck\nk1 = 1\nk2 = 1", 0,
         "m.ini:21:1: [axis 2] ga: not a key of model = ctrl"},
    };
    char err[600];
    size_t i;
    (void)state;
    for (i = 0U; i < sizeof bad / sizeof bad[0]; i++) {
        memset(err, 0, sizeof err);
        if (parse(edit(bad[i].from, bad[i].to, bad[i].raw), err, sizeof err) != -1) {
            fail_msg("accepted: %s -> %s", bad[i].from, bad[i].to);
        }
        if (strncmp(err, bad[i].msg, strlen(bad[i].msg)) != 0) {
            fail_msg("case %zu:\n  got  %s\n  want %s", i, err, bad[i].msg);
        }
    }
}

/* Whole-file refusals: no [model], no axis, empty, binary content. */
static void test_refusals_file(void **state)
{
    static const struct {
        const char *text, *msg;
    } bad[] = {
        {"", "m.ini: no [model] section (not a c4g-ident parameter file?)"},
        {"[axis 1]\nJa = 1\nFv = 0\nFc = 0\noff = 0\neps = 1\n",
         "m.ini: no [model] section (not a c4g-ident parameter file?)"},
        {"[model]\nformat = c4g-ident 1\nmodel = motor-current-1\narm = 1\nperiod_ms = 2\n"
         "checksum = fnv1a64:0000000000000000\n",
         "m.ini: no [axis N] section: the file sets no axis"},
        {"[model]\nformat = c4g-ident 1\x01\n",
         "m.ini:2:21: control byte \\x01 at byte offset 28 (after 'format = c4g-ident 1')"},
    };
    char err[600];
    char text[512];
    size_t i;
    (void)state;
    for (i = 0U; i < sizeof bad / sizeof bad[0]; i++) {
        strcpy(text, bad[i].text);
        if (strstr(text, "checksum = ") != NULL) {
            seal(text);
        }
        assert_int_equal(parse(text, err, sizeof err), -1);
        if (strncmp(err, bad[i].msg, strlen(bad[i].msg)) != 0) {
            fail_msg("case %zu:\n  got  %s\n  want %s", i, err, bad[i].msg);
        }
    }
}

/* The mismatch message names the sum the text really has. */
static void test_mismatch_sum(void **state)
{
    char err[600];
    char want[25];
    uint64_t sum = 0U;
    (void)state;
    edit("Fc = 0.1875", "Fc = 0.1876", 0);                 /* sealed: right sum */
    assert_int_equal(parse(g_text, err, sizeof err), 0);
    assert_int_equal(c4gh_ffm_checksum_text(g_text, strlen(g_text), &sum), 0);
    memcpy(strstr(g_text, "0.1876"), "0.1877", 6U);        /* then edited */
    assert_int_equal(parse(g_text, err, sizeof err), -1);
    c4gh_ffm_checksum_format(sum, want);
    assert_non_null(strstr(err, want));                    /* expected: what the file says */
    assert_int_equal(c4gh_ffm_checksum_text(g_text, strlen(g_text), &sum), 0);
    c4gh_ffm_checksum_format(sum, want);
    assert_non_null(strstr(err, want));                    /* computed: the edited text's */
}

/* A model = ctrl axis: read exactly beside a model = axis one, its refusals, and its
 * current against a value worked out by hand. */
static const char CTRL[] =
    "[model]\n"                                /* 1 */
    "format = c4g-ident 1\n"                   /* 2 */
    "model = motor-current-1\n"                /* 3 */
    "arm = 1\n"                                /* 4 */
    "period_ms = 2\n"                          /* 5 */
    "checksum = fnv1a64:0000000000000000\n"    /* 6 */
    "[axis 1]\n"                               /* 7 */
    "model = ctrl\n"                           /* 8 */
    "variant = ctrl+coulomb\n"                 /* 9 */
    "k1 = 0.97\n"                              /* 10 */
    "k2 = 1.08\n"                              /* 11 */
    "ks = 1.25\n"                              /* 12 */
    "Fv = 0.008\n"                             /* 13 */
    "Fc = 0.19\n"                              /* 14 */
    "off = 0.02\n"                             /* 15 */
    "eps = 0.05\n"                             /* 16 */
    "v_max = 30\n"                             /* 17 */
    "a_max = 400\n"                            /* 18 */
    "[axis 2]\n"                               /* 19 */
    "model = axis\n"                           /* 20 */
    "Ja = 0.003\n"                             /* 21 */
    "Fv = 0\n"                                 /* 22 */
    "Fc = 0.1\n"                               /* 23 */
    "off = 0\n"                                /* 24 */
    "eps = 0.05\n";                            /* 25 */

static void test_ctrl_file(void **state)
{
    static const struct {
        const char *from, *to, *msg;
    } bad[] = {
        {"k2 = 1.08", "k2 = nan", "m.ini:11:6: [axis 1] k2: 'nan' is not a finite number"},
        {"k1 = 0.97", "k1 = 2e6", "m.ini:10:6: [axis 1] k1: '2e6' is out of range -1000000..1000000"},
        {"ks = 1.25", "ks = 0", "m.ini:12:6: [axis 1] ks: '0' must be > 0"},
        {"k2 = 1.08\n", "", "m.ini:7:1: [axis 1] k2: missing (model = ctrl needs k1, k2, ks, Fv, Fc, off and eps)"},
        {"eps = 0.05\nv_max", "v_max", "m.ini:7:1: [axis 1] eps: missing (model = ctrl needs"},
        {"off = 0.02\n", "off = 0.02\nga = 1\n", "m.ini:16:1: [axis 1] ga: not a key of model = ctrl"},
        {"model = ctrl\n", "model = ctrl\nmodel = ctrl\n", "m.ini:9:1: [axis 1] model: set twice (first on line 8)"},
        {"Ja = 0.003\n", "", "m.ini:19:1: [axis 2] Ja: missing (Ja, Fv, Fc, off and eps are required)"},
    };
    char text[1024];
    char err[600];
    size_t i;
    (void)state;
    strcpy(text, CTRL);
    seal(text);
    assert_int_equal(parse(text, err, sizeof err), 0);
    assert_int_equal(g_f.ax[0].set, 1);
    assert_int_equal(g_f.ax[0].ctrl, 1);
    assert_string_equal(g_f.ax[0].variant, "ctrl+coulomb");
    assert_true(g_f.ax[0].k1 == 0.97 && g_f.ax[0].k2 == 1.08 && g_f.ax[0].ks == 1.25);
    assert_true(g_f.ax[0].ja == 0.0 && g_f.ax[0].fc == 0.19 && g_f.ax[0].a_max == 400.0);
    assert_int_equal(g_f.ax[1].ctrl, 0);
    assert_true(g_f.ax[1].ja == 0.003);
    /* k1 (EXT1 - in) + k2 in + Fv v + Fc tanh(v/eps) + off, in = ks EXT2 2 pi a = 0.1 pi */
    near(c4gh_ffm_current_ctrl(&g_f.ax[0], 2.0, 100.0, 1.5, 0.0004),
         0.97 * (1.5 - 0.1 * PI) + 1.08 * 0.1 * PI + 0.016 + 0.19 * tanh(40.0) + 0.02, 1e-12);
    near(c4gh_ffm_current_ctrl(&g_f.ax[0], 2.0, 100.0, 1.5, 0.0004), 1.7155575192, 1e-9);
    near(c4gh_ffm_current_ctrl(&g_f.ax[0], 0.0, 0.0, -2.0, 0.0004), 0.97 * -2.0 + 0.02, 1e-12);
    for (i = 0U; i < sizeof bad / sizeof bad[0]; i++) {
        char *p;
        strcpy(text, CTRL);
        p = strstr(text, bad[i].from);
        assert_non_null(p);
        memmove(p + strlen(bad[i].to), p + strlen(bad[i].from), strlen(p + strlen(bad[i].from)) + 1U);
        memcpy(p, bad[i].to, strlen(bad[i].to));
        seal(text);
        memset(err, 0, sizeof err);
        if (parse(text, err, sizeof err) != -1) {
            fail_msg("accepted: %s -> %s", bad[i].from, bad[i].to);
        }
        if (strncmp(err, bad[i].msg, strlen(bad[i].msg)) != 0) {
            fail_msg("case %zu:\n  got  %s\n  want %s", i, err, bad[i].msg);
        }
    }
}

static void test_current(void **state)
{
    c4gh_ffm_axis_t p;
    (void)state;
    memset(&p, 0, sizeof p);
    /* Coulomb: 0.01*10 + 0.1*1 + 0.5*tanh(100) + 0.02 */
    p.ja = 0.01;
    p.fv = 0.1;
    p.fc = 0.5;
    p.eps = 0.01;
    p.off = 0.02;
    near(c4gh_ffm_current(&p, 1.0, 10.0, 0.0, 0), 0.72, 1e-12);
    near(c4gh_ffm_current(&p, -1.0, 0.0, 0.0, 0), -0.1 - 0.5 + 0.02, 1e-12);
    near(c4gh_ffm_current(&p, 0.0, 0.0, 0.0, 0), 0.02, 1e-15);              /* tanh(0) = 0 */
    near(c4gh_ffm_current(&p, 0.005, 0.0, 0.0, 0), 0.0005 + 0.5 * tanh(0.5) + 0.02, 1e-12);
    /* Fs and vs unused while vs = 0 */
    p.fs = 9.0;
    near(c4gh_ffm_current(&p, 1.0, 10.0, 0.0, 0), 0.72, 1e-12);
    /* Stribeck: level 0.5 + (0.8 - 0.5) exp(-(0.5/0.5)^2) at v = 0.5 */
    p.fs = 0.8;
    p.vs = 0.5;
    near(c4gh_ffm_current(&p, 0.5, 0.0, 0.0, 0), 0.05 + (0.5 + 0.3 * exp(-1.0)) + 0.02, 1e-12);
    near(c4gh_ffm_current(&p, 0.5, 0.0, 0.0, 0), 0.05 + 0.610363832351 + 0.02, 1e-9);
    near(c4gh_ffm_current(&p, -50.0, 0.0, 0.0, 0), -5.0 - 0.5 + 0.02, 1e-12); /* far: Coulomb */
    /* gravity: only with a link angle */
    p.ga = 2.0;
    p.gb = 3.0;
    near(c4gh_ffm_current(&p, 0.0, 0.0, PI / 6.0, 1), 0.02 + 2.0 * 0.8660254037844386 + 1.5, 1e-12);
    near(c4gh_ffm_current(&p, 0.0, 0.0, PI / 6.0, 0), 0.02, 1e-15);
    /* eps <= 0 (not from a file): the plain sign */
    p.eps = 0.0;
    p.vs = 0.0;
    p.ga = p.gb = 0.0;
    near(c4gh_ffm_current(&p, 1e-9, 0.0, 0.0, 0), 1e-10 + 0.5 + 0.02, 1e-12);
    near(c4gh_ffm_current(&p, 0.0, 0.0, 0.0, 0), 0.02, 1e-15);
}

/* A model = rigid-body-1 file (two joints), as c4g-ident fit --model rigid writes it. */
static const char RIGID[] =
    "[model]\n"                                /* 1 */
    "format = c4g-ident 1\n"                   /* 2 */
    "model = rigid-body-1\n"                   /* 3 */
    "arm = 1\n"                                /* 4 */
    "period_ms = 2\n"                          /* 5 */
    "range = clamp\n"                          /* 6 */
    "consistent = 1\n"                         /* 7 */
    "base_params = 9\n"                        /* 8 */
    "checksum = fnv1a64:0000000000000000\n"    /* 9 */
    "[kinematics]\n"                           /* 10 */
    "convention = modified\n"                  /* 11 */
    "angles = deg\n"                           /* 12 */
    "gravity = 0 0 -9.81\n"                    /* 13 */
    "[joint 1]\n"                              /* 14 */
    "a = 0\n"                                  /* 15 */
    "alpha = 0\n"                              /* 16 */
    "d = 0.45\n"                               /* 17 */
    "theta0 = 0\n"                             /* 18 */
    "kt = 0.8\n"                               /* 19 */
    "m = 40\n"                                 /* 20 */
    "mx = 2\n"                                 /* 21 */
    "my = 0\n"                                 /* 22 */
    "mz = 10\n"                                /* 23 */
    "Ixx = 3.575\n"                            /* 24 */
    "Ixy = 0\n"                                /* 25 */
    "Ixz = -0.5\n"                             /* 26 */
    "Iyy = 3.7833\n"                           /* 27 */
    "Iyz = 0\n"                                /* 28 */
    "Izz = 0.8083\n"                           /* 29 */
    "ia = 0.0366\n"                            /* 30 */
    "q_min = -2.5\n"                           /* 31 */
    "q_max = 2.5\n"                            /* 32 */
    "qd_max = 2\n"                             /* 33 */
    "qdd_max = 20\n"                           /* 34 */
    "[joint 2]\n"                              /* 35 */
    "a = 0.15\n"                               /* 36 */
    "alpha = -90\n"                            /* 37 */
    "d = 0\n"                                  /* 38 */
    "theta0 = -90\n"                           /* 39 */
    "kt = 0.8\n"                               /* 40 */
    "m = 22\n"                                 /* 41 */
    "mx = 6.6\n"                               /* 42 */
    "my = 0\n"                                 /* 43 */
    "mz = 0\n"                                 /* 44 */
    "Ixx = 0.0677\n"                           /* 45 */
    "Ixy = 0\n"                                /* 46 */
    "Ixz = 0\n"                                /* 47 */
    "Iyy = 2.9047\n"                           /* 48 */
    "Iyz = 0\n"                                /* 49 */
    "Izz = 2.9196\n"                           /* 50 */
    "ia = -0.01\n"                             /* 51 */
    "q_min = -1.5\n"                           /* 52 */
    "q_max = 0.5\n"                            /* 53 */
    "qd_max = 2.5\n"                           /* 54 */
    "qdd_max = 25\n"                           /* 55 */
    "[axis 1]\n"                               /* 56 */
    "variant = stribeck\n"                     /* 57 */
    "Fv = 0.0079\n"                            /* 58 */
    "Fc = 0.19\n"                              /* 59 */
    "Fs = 0.25\n"                              /* 60 */
    "vs = 0.5\n"                               /* 61 */
    "off = 0.01\n"                             /* 62 */
    "eps = 0.05\n"                             /* 63 */
    "[axis 2]\n"                               /* 64 */
    "Fv = 0.0079\n"                            /* 65 */
    "Fc = 0.19\n"                              /* 66 */
    "off = -0.02\n"                            /* 67 */
    "eps = 0.05\n";                            /* 68 */

static char g_rigid[8192];

/* RIGID with the first @p from replaced by @p to, sealed. */
static const char *edit_rigid(const char *from, const char *to)
{
    char *p;
    strcpy(g_rigid, RIGID);
    if (from != NULL) {
        p = strstr(g_rigid, from);
        assert_non_null(p);
        memmove(p + strlen(to), p + strlen(from), strlen(p + strlen(from)) + 1U);
        memcpy(p, to, strlen(to));
    }
    if (strstr(g_rigid, "checksum = fnv1a64:") != NULL) {
        seal(g_rigid);
    }
    return g_rigid;
}

/* The file read exactly: the chain built from the kinematics keys, every joint's values. */
static void test_rigid_file(void **state)
{
    char err[600];
    static const double pi1[10] = {40, 2, 0, 10, 3.575, 0, -0.5, 3.7833, 0, 0.8083};
    static const double pi2[10] = {22, 6.6, 0, 0, 0.0677, 0, 0, 2.9047, 0, 2.9196};
    unsigned k;
    (void)state;
    if (parse(edit_rigid(NULL, NULL), err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(g_f.rigid, 1);
    assert_int_equal(g_f.arm, 1);
    assert_int_equal(g_f.consistent, 1);
    assert_int_equal(g_f.base_params, 9);
    assert_int_equal(g_f.kin.n, 2);
    assert_int_equal(g_f.kin.conv, C4G_DYN_DH_MODIFIED);
    assert_true(g_f.kin.j[0].kt == 0.8 && g_f.kin.j[1].a == 0.15 && g_f.kin.j[1].alpha == -90.0);
    assert_true(g_f.kin.gravity[2] == -9.81 && g_f.kin.chain.gravity[2] == -9.81);
    assert_int_equal(g_f.kin.chain.n, 2);
    near(g_f.kin.chain.j[1].theta0, -PI / 2.0, 1e-15);   /* degrees -> rad */
    near(g_f.kin.chain.j[1].pos[0], 0.15, 1e-15);
    for (k = 0U; k < 10U; k++) {
        assert_true(g_f.pi[k] == pi1[k]);
        assert_true(g_f.pi[10U + k] == pi2[k]);
    }
    assert_true(g_f.ia[0] == 0.0366 && g_f.ia[1] == -0.01); /* a base solution's sign is free */
    assert_true(g_f.q_min[0] == -2.5 && g_f.q_max[0] == 2.5 && g_f.qd_max[0] == 2.0 && g_f.qdd_max[0] == 20.0);
    assert_true(g_f.q_min[1] == -1.5 && g_f.q_max[1] == 0.5 && g_f.qd_max[1] == 2.5 && g_f.qdd_max[1] == 25.0);
    assert_int_equal(g_f.joint_line[0], 14);
    assert_int_equal(g_f.joint_line[1], 35);
    assert_true(g_f.ax[0].set && g_f.ax[1].set && !g_f.ax[2].set);
    assert_true(g_f.ax[0].fs == 0.25 && g_f.ax[0].vs == 0.5 && g_f.ax[1].off == -0.02);
    assert_true(g_f.ax[0].ja == 0.0 && g_f.ax[0].ga == 0.0 && g_f.ax[0].ctrl == 0);
    assert_string_equal(g_f.ax[0].variant, "stribeck");
    /* consistent left out: -1 (not said) */
    assert_int_equal(parse(edit_rigid("consistent = 1\n", ""), err, sizeof err), 0);
    assert_int_equal(g_f.consistent, -1);
    /* the order of the sections is free: [model] last */
    {
        char moved[8192];
        const char *body = strstr(RIGID, "[kinematics]");
        const size_t head = (size_t)(body - RIGID);
        strcpy(moved, body);
        strncat(moved, RIGID, head);
        seal(moved);
        if (parse(moved, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        assert_int_equal(g_f.rigid, 1);
        assert_int_equal(g_f.kin.n, 2);
    }
}

/* Writes the parsed file back the way a writer does (%.17g: every double exact), seals it
 * and reads it again: the same values, the checksum of the new text. */
static void test_rigid_round_trip(void **state)
{
    char err[600];
    static char out[8192];
    static c4gh_ffm_file_t a;
    size_t n = 0U;
    unsigned j, k;
    uint64_t sum = 0U;
    (void)state;
    assert_int_equal(parse(edit_rigid(NULL, NULL), err, sizeof err), 0);
    a = g_f;
#define W(...) n += (size_t)snprintf(out + n, sizeof out - n, __VA_ARGS__)
    W("[model]\nformat = c4g-ident 1\nmodel = rigid-body-1\narm = %u\nperiod_ms = %.17g\n", a.arm, a.period_ms);
    W("range = clamp\nconsistent = %d\nbase_params = %u\n", a.consistent, a.base_params);
    W("checksum = fnv1a64:0000000000000000\n[kinematics]\nconvention = modified\nangles = deg\n");
    W("gravity = %.17g %.17g %.17g\n", a.kin.gravity[0], a.kin.gravity[1], a.kin.gravity[2]);
    for (j = 0U; j < a.kin.n; j++) {
        static const char *const names[10] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
        const c4gh_kin_joint_t *J = &a.kin.j[j];
        W("[joint %u]\na = %.17g\nalpha = %.17g\nd = %.17g\ntheta0 = %.17g\nkt = %.17g\n", j + 1U, J->a, J->alpha,
          J->d, J->theta0, J->kt);
        for (k = 0U; k < 10U; k++) {
            W("%s = %.17g\n", names[k], a.pi[(j * 10U) + k]);
        }
        W("ia = %.17g\nq_min = %.17g\nq_max = %.17g\nqd_max = %.17g\nqdd_max = %.17g\n", a.ia[j], a.q_min[j],
          a.q_max[j], a.qd_max[j], a.qdd_max[j]);
        W("[axis %u]\nFv = %.17g\nFc = %.17g\nFs = %.17g\nvs = %.17g\noff = %.17g\neps = %.17g\n", j + 1U,
          a.ax[j].fv, a.ax[j].fc, a.ax[j].fs, a.ax[j].vs, a.ax[j].off, a.ax[j].eps);
    }
#undef W
    seal(out);
    if (parse(out, err, sizeof err) != 0) {
        fail_msg("%s\n%s", err, out);
    }
    assert_int_equal(c4gh_ffm_checksum_text(out, strlen(out), &sum), 0);
    assert_true(g_f.checksum == sum && sum != a.checksum);
    assert_true(memcmp(g_f.pi, a.pi, sizeof a.pi) == 0 && memcmp(g_f.ia, a.ia, sizeof a.ia) == 0);
    assert_true(memcmp(g_f.q_min, a.q_min, sizeof a.q_min) == 0 && memcmp(g_f.q_max, a.q_max, sizeof a.q_max) == 0);
    assert_true(memcmp(g_f.qd_max, a.qd_max, sizeof a.qd_max) == 0 &&
                memcmp(g_f.qdd_max, a.qdd_max, sizeof a.qdd_max) == 0);
    assert_true(memcmp(&g_f.kin.chain, &a.kin.chain, sizeof a.kin.chain) == 0);
    for (j = 0U; j < 2U; j++) {
        assert_true(g_f.ax[j].fv == a.ax[j].fv && g_f.ax[j].fc == a.ax[j].fc && g_f.ax[j].fs == a.ax[j].fs &&
                    g_f.ax[j].vs == a.ax[j].vs && g_f.ax[j].off == a.ax[j].off && g_f.ax[j].eps == a.ax[j].eps);
    }
    /* an edited value after sealing: the checksum says so */
    memcpy(strstr(out, "m = 40"), "m = 41", 6U);
    assert_int_equal(parse(out, err, sizeof err), -1);
    assert_non_null(strstr(err, "m.ini:9:12: [model] checksum: checksum mismatch"));
}

static void test_rigid_refusals(void **state)
{
    static const struct {
        const char *from, *to, *msg;
    } bad[] = {
        /* [model] */
        {"range = clamp", "range = extrapolate",
         "m.ini:6:9: [model] range: 'extrapolate' is not 'clamp' (the only range policy this reader knows)"},
        {"consistent = 1", "consistent = 2", "m.ini:7:14: [model] consistent: '2' is out of range 0..1"},
        {"base_params = 9", "base_params = 0", "m.ini:8:15: [model] base_params: '0' is out of range 1..77"},
        {"base_params = 9", "base_params = 1.5", "m.ini:8:15: [model] base_params: '1.5' is not an integer"},
        {"range = clamp\n", "range = clamp\nrange = clamp\n", "m.ini:7:1: [model] range: set twice (first on line 6)"},
        /* [kinematics] and the DH keys: c4gh_kin_on_key's messages, our positions */
        {"angles = deg", "angles = grad", "m.ini:12:10: [kinematics] angles: 'grad' is not rad or deg"},
        {"convention = modified", "convention = craig", "m.ini:11:14: [kinematics] convention: 'craig' is not standard or modified"},
        {"gravity = 0 0 -9.81\n", "gravity = 0 0 -9.81\nspeed = 1\n",
         "m.ini:14:1: [kinematics] speed: unknown key (want convention, angles, gravity)"},
        {"[kinematics]\nconvention = modified\nangles = deg\ngravity = 0 0 -9.81\n", "",
         "m.ini:1:1: [kinematics]: missing (model = rigid-body-1 needs the arm's convention, angles and gravity)"},
        {"d = 0.45", "d = nan", "m.ini:17:5: [joint 1] d: 'nan' is not a finite number"},
        {"kt = 0.8\nm = 22", "m = 22", "m.ini:36:1: [joint 2] kt: missing (a, alpha, d, theta0 and kt are required)"},
        {"[joint 2]", "[joint 8]",
         "m.ini:35:1: unknown section [joint 8] (want [model], [kinematics], [joint 1]..[joint 7] or [axis 1]..[axis 10])"},
        {"[joint 2]", "[joint 1]", "m.ini:35:1: [joint 1]: section given twice (first on line 14)"},
        {"[kinematics]\n", "[kinematics]\n[kinematics]\n",
         "m.ini:11:1: [kinematics]: section given twice (first on line 10)"},
        /* the joint's own keys */
        {"m = 40", "m = nan", "m.ini:20:5: [joint 1] m: 'nan' is not a finite number"},
        {"Ixz = -0.5", "Ixz = -2e6", "m.ini:26:7: [joint 1] Ixz: '-2e6' is out of range -1000000..1000000"},
        {"ia = 0.0366", "ia = 1e999", "m.ini:30:6: [joint 1] ia: '1e999' is out of range -1000000..1000000"},
        {"qd_max = 2\n", "qd_max = 0\n", "m.ini:33:10: [joint 1] qd_max: '0' must be > 0"},
        {"qdd_max = 25", "qdd_max = -25", "m.ini:55:11: [joint 2] qdd_max: '-25' is out of range 0..1000000"},
        {"q_max = 2.5", "q_max = -2.5", "m.ini:32:1: [joint 1] q_max: -2.5 is not above q_min -2.5"},
        {"Izz = 0.8083\n", "Izz = 0.8083\nIzz = 1\n", "m.ini:30:1: [joint 1] Izz: set twice (first on line 29)"},
        {"Izz = 0.8083\n", "", "m.ini:14:1: [joint 1] Izz: missing (a rigid-body joint needs m, mx, my, mz"},
        {"qdd_max = 25\n", "", "m.ini:35:1: [joint 2] qdd_max: missing"},
        {"ia = 0.0366", "Ia = 0.0366",
         "m.ini:30:1: [joint 1] Ia: unknown key (want a, alpha, d, theta0, kt, m, mx, my, mz, Ixx, Ixy, Ixz, "
         "Iyy, Iyz, Izz, ia, q_min, q_max, qd_max, qdd_max)"},
        /* [axis N]: motors 1..n, friction and offset only */
        {"[axis 2]\nFv = 0.0079\nFc = 0.19\noff = -0.02\neps = 0.05\n", "",
         "m.ini:1:1: [axis 2]: missing (motor 2's friction and offset: every joint of the chain needs its [axis N])"},
        {"[axis 2]", "[axis 3]", "m.ini:1:1: [axis 2]: missing"},
        {"eps = 0.05\n", "eps = 0.05\n[axis 3]\nFv = 0\nFc = 0\noff = 0\neps = 1\n",
         "m.ini:64:1: [axis 3]: the chain has 2 joints: a rigid-body file sets motors 1..2 only"},
        {"off = -0.02\n", "", "m.ini:64:1: [axis 2] off: missing (model = rigid-body-1 needs Fv, Fc, off and eps)"},
        {"off = -0.02\n", "off = -0.02\nJa = 0.003\n",
         "m.ini:68:1: [axis 2] Ja: not a key of model = rigid-body-1 (the rigid-body part holds the inertia and the gravity)"},
        {"off = -0.02\n", "off = -0.02\ngb = 1\n", "m.ini:68:1: [axis 2] gb: not a key of model = rigid-body-1"},
        {"off = -0.02\n", "off = -0.02\nks = 1\n", "m.ini:68:1: [axis 2] ks: not a key of model = rigid-body-1"},
        {"variant = stribeck", "variant = stribeck+gravity",
         "m.ini:57:1: [axis 1] variant: a rigid-body file's variant is coulomb or stribeck"},
        {"variant = stribeck", "model = axis",
         "m.ini:57:1: [axis 1] model: not a key of model = rigid-body-1 (its axes are rigid-body)"},
        /* the other family's keys in a motor-current-1 file */
        {"model = rigid-body-1", "model = motor-current-1",
         "m.ini:6:1: [model] range: not a key of model = motor-current-1 (only of rigid-body-1)"},
        {"model = rigid-body-1\narm = 1\nperiod_ms = 2\nrange = clamp\nconsistent = 1\nbase_params = 9\n",
         "model = motor-current-1\narm = 1\nperiod_ms = 2\n",
         "m.ini:7:1: [kinematics]: a section of model = rigid-body-1 only (this file is model = motor-current-1)"},
        {"model = rigid-body-1", "model = rigid-body-2",
         "m.ini:3:9: [model] model: 'rigid-body-2' is not 'motor-current-1' or 'rigid-body-1' (the models this "
         "reader evaluates)"},
    };
    char err[600];
    size_t i;
    (void)state;
    for (i = 0U; i < sizeof bad / sizeof bad[0]; i++) {
        memset(err, 0, sizeof err);
        if (parse(edit_rigid(bad[i].from, bad[i].to), err, sizeof err) != -1) {
            fail_msg("case %zu accepted: %s -> %s", i, bad[i].from, bad[i].to);
        }
        if (strncmp(err, bad[i].msg, strlen(bad[i].msg)) != 0) {
            fail_msg("case %zu:\n  got  %s\n  want %s", i, err, bad[i].msg);
        }
    }
    /* a motor-current-1 file with only [joint 1] */
    assert_int_equal(parse(edit("; a second axis", "[joint 1]\nm = 1\n; a second axis", 0), err, sizeof err), -1);
    assert_string_equal(err, "m.ini:26:1: [joint 1]: a section of model = rigid-body-1 only (this file is model = "
                             "motor-current-1)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fnv),
        cmocka_unit_test(test_checksum_span),
        cmocka_unit_test(test_good_file),
        cmocka_unit_test(test_fixture),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_refusals_file),
        cmocka_unit_test(test_mismatch_sum),
        cmocka_unit_test(test_current),
        cmocka_unit_test(test_ctrl_file),
        cmocka_unit_test(test_rigid_file),
        cmocka_unit_test(test_rigid_round_trip),
        cmocka_unit_test(test_rigid_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
