/* SPDX-License-Identifier: MIT */
/* The kinematics file: the arm plant's fixture read into the chain the dynamics tests use
 * (same torques for the same parameters), the two angle units, and one test per refusal,
 * each asserting the FILE:LINE:COL and the named key. */
#include "test_helpers.h"
#include "c4gh_kinfile.h"

#include <math.h>

#ifndef FIXTURES_DIR
#define FIXTURES_DIR "fixtures"
#endif

static const char good_rad[] =
    "[arm]\nconvention = standard\nangles = rad\ngravity = 0 0 -9.81\n"
    "[joint 1]\na = 0.7\nalpha = 0\nd = 0\ntheta0 = 0\nkt = 0.8\n"
    "[joint 2]\na = 0.4\nalpha = 0\nd = 0\ntheta0 = 0\nkt = 0.5\n";

static void test_fixture(void **state)
{
    const double hp = 1.5707963267948966;
    const double a[6] = {0.0, 0.15, 0.59, 0.11, 0.0, 0.0};
    const double alpha[6] = {0.0, -hp, 0.0, -hp, hp, -hp};
    const double d[6] = {0.45, 0.0, 0.0, 0.64, 0.0, 0.0};
    const double th[6] = {0.0, -hp, 0.0, 0.0, 0.0, 0.0};
    const double g[3] = {0.0, 0.0, -9.81};
    c4gh_kinfile_t k;
    c4g_dyn_chain_t want;
    double pi[60];
    double q[6] = {0.3, -0.4, 1.1, 0.2, -0.9, 2.0};
    double qd[6] = {0.5, 0.1, -0.3, 1.0, 0.4, -0.8};
    double qdd[6] = {1.0, -2.0, 0.5, 3.0, -1.5, 0.7};
    double t1[6];
    double t2[6];
    char err[256] = "";
    int i;
    (void)state;
    assert_int_equal(c4gh_kin_load(FIXTURES_DIR "/ident/smart-six.kin", &k, err, sizeof err), 0);
    assert_int_equal(k.n, 6);
    assert_int_equal(k.conv, C4G_DYN_DH_MODIFIED);
    assert_int_equal(k.deg, 1);
    assert_true(k.j[3].kt == 0.5 && k.j[0].kt == 0.8);
    assert_true(k.j[1].alpha == -90.0);
    assert_int_equal(c4g_dyn_chain_dh(&want, 6, C4G_DYN_DH_MODIFIED, a, alpha, d, th, g), C4G_OK);
    for (i = 0; i < 60; i++) {
        pi[i] = 0.1 + 0.01 * i;
    }
    assert_int_equal(c4g_dyn_rnea(&k.chain, q, qd, qdd, pi, NULL, t1), C4G_OK);
    assert_int_equal(c4g_dyn_rnea(&want, q, qd, qdd, pi, NULL, t2), C4G_OK);
    for (i = 0; i < 6; i++) {
        assert_true(fabs(t1[i] - t2[i]) <= 1e-12 * (1.0 + fabs(t2[i])));
    }
    assert_int_equal(c4gh_kin_parse_text("r.kin", good_rad, strlen(good_rad), &k, err, sizeof err), 0);
    assert_int_equal(k.n, 2);
    assert_int_equal(k.conv, C4G_DYN_DH_STANDARD);
    assert_int_equal(k.deg, 0);
}

/* The text of good_rad with @p from replaced by @p to: refused with @p want in the message. */
static void refused(const char *from, const char *to, const char *want)
{
    char text[1024];
    char err[256] = "";
    c4gh_kinfile_t k;
    const char *p = strstr(good_rad, from);
    size_t n;
    assert_non_null(p);
    n = (size_t)(p - good_rad);
    memcpy(text, good_rad, n);
    snprintf(text + n, sizeof text - n, "%s%s", to, p + strlen(from));
    assert_int_equal(c4gh_kin_parse_text("b.kin", text, strlen(text), &k, err, sizeof err), -1);
    if (strstr(err, want) == NULL) {
        fail_msg("'%s' lacks '%s'", err, want);
    }
}

static void test_refusals(void **state)
{
    char err[256] = "";
    c4gh_kinfile_t k;
    (void)state;
    refused("convention = standard", "convention = craig", "b.kin:2:14: [arm] convention: 'craig' is not standard or modified");
    refused("angles = rad\n", "", "b.kin: [arm] angles: missing");
    refused("angles = rad", "angles = grad", "[arm] angles: 'grad' is not rad or deg");
    refused("gravity = 0 0 -9.81", "gravity = 0 -9.81", "[arm] gravity: fewer than three numbers");
    refused("gravity = 0 0 -9.81", "gravity = 0 0 -9.81 1", "[arm] gravity: more than three numbers");
    refused("gravity = 0 0 -9.81", "gravity = 0 0 -981", "b.kin:4:11: [arm] gravity: '-981' is out of range");
    refused("a = 0.7", "a = nan", "b.kin:6:5: [joint 1] a: 'nan'");
    refused("kt = 0.8", "kt = 0", "[joint 1] kt: '0' is out of range");
    refused("kt = 0.5\n", "", "b.kin:12:1: [joint 2] kt: missing");
    refused("kt = 0.8\n", "kt = 0.8\nkt = 0.9\n", "b.kin:11:1: [joint 1] kt: set twice (first on line 10)");
    refused("[joint 2]", "[joint 3]", "b.kin:12:1: [joint 3]: joint 2 is missing");
    refused("[joint 2]", "[joint 8]", "[joint 8]: joint number out of 1..7");
    refused("[joint 2]", "[link 2]", "unknown section [link 2]");
    refused("kt = 0.5", "ktt = 0.5", "[joint 2] ktt: unknown key (want a, alpha, d, theta0, kt)");
    refused("angles = rad", "angles = rad\nunits = si", "[arm] units: unknown key");
    refused("alpha = 0\nd = 0\ntheta0 = 0\nkt = 0.5", "alpha = 0\nd = 0\ntheta0 = 90\nkt = 0.5",
            "b.kin:12:1: [joint 2]: an angle over 2 pi rad (angles = rad: was it written in degrees?)");
    refused("a = 0.7", "a = 101", "[joint 1] a: '101' is out of range");
    refused("[arm]\n", "x = 1\n[arm]\n", "x: a key before the first section");
    {
        const char *t = "[arm]\nconvention = modified\nangles = deg\ngravity = 0 0 0\n";
        assert_int_equal(c4gh_kin_parse_text("e.kin", t, strlen(t), &k, err, sizeof err), -1);
    }
    assert_non_null(strstr(err, "e.kin: no [joint 1] section"));
    assert_int_equal(c4gh_kin_load("/nonexistent/x.kin", &k, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.kin"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixture),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
