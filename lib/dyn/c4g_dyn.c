/* SPDX-License-Identifier: MIT */
/* Rigid-body dynamics of a serial arm (c4gopen_dyn.h): the recursive Newton-Euler pass in
 * link frames, and the same pass written as a regressor. Both keep every quantity in the
 * frame of the link it belongs to, so a joint's torque is the z component of the moment
 * at its own frame's origin. */
#include "c4gopen_dyn.h"

#include <math.h>
#include <stddef.h>

#define DYN_TWO_PI 6.283185307179586
#define DYN_GRAVITY_MAX 100.0

/* The moving frame of one link: rotation from its parent (columns: this frame's axes in the
 * parent's), its origin in the parent, and its motion in its own frame. */
typedef struct dyn_mat3 {
    double m[3][3];
} dyn_mat3_t;

typedef struct dyn_link_state {
    dyn_mat3_t r;
    double p[3];
    double w[3];  /* angular velocity */
    double wd[3]; /* angular acceleration */
    double a[3];  /* linear acceleration of the origin, gravity included (as -g) */
} dyn_link_state_t;

static int dyn_finite3(const double v[3])
{
    return (isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2])) ? 1 : 0;
}

static int dyn_all_finite(const double *v, uint32_t n)
{
    uint32_t i;
    int ok = 1;
    for (i = 0U; i < n; i++) {
        if (!isfinite(v[i])) {
            ok = 0;
        }
    }
    return ok;
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    const double x = (a[1] * b[2]) - (a[2] * b[1]);
    const double y = (a[2] * b[0]) - (a[0] * b[2]);
    const double z = (a[0] * b[1]) - (a[1] * b[0]);
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

/* out = R^T v */
static void rot_t_mul(const dyn_mat3_t *r, const double v[3], double out[3])
{
    uint32_t i;
    for (i = 0U; i < 3U; i++) {
        out[i] = (r->m[0][i] * v[0]) + (r->m[1][i] * v[1]) + (r->m[2][i] * v[2]);
    }
}

/* out = R v */
static void rot_mul(const dyn_mat3_t *r, const double v[3], double out[3])
{
    uint32_t i;
    for (i = 0U; i < 3U; i++) {
        out[i] = (r->m[i][0] * v[0]) + (r->m[i][1] * v[1]) + (r->m[i][2] * v[2]);
    }
}

/* Parent -> link rotation at angle th: rot Rz(th). */
static void joint_rotation(const c4g_dyn_joint_t *jt, double th, dyn_mat3_t *r)
{
    const double c = cos(th);
    const double s = sin(th);
    uint32_t i;
    for (i = 0U; i < 3U; i++) {
        r->m[i][0] = (jt->rot[i][0] * c) + (jt->rot[i][1] * s);
        r->m[i][1] = (jt->rot[i][1] * c) - (jt->rot[i][0] * s);
        r->m[i][2] = jt->rot[i][2];
    }
}

static c4g_status_t check_motion(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd)
{
    c4g_status_t rc = C4G_OK;
    if ((ch == NULL) || (q == NULL) || (qd == NULL) || (qdd == NULL)) {
        rc = C4G_ERR_NULL;
    } else if ((ch->n == 0U) || (ch->n > C4G_DYN_MAX_LINKS)) {
        rc = C4G_ERR_ARG;
    } else if ((dyn_all_finite(q, ch->n) == 0) || (dyn_all_finite(qd, ch->n) == 0) ||
               (dyn_all_finite(qdd, ch->n) == 0) || (dyn_finite3(ch->gravity) == 0)) {
        rc = C4G_ERR_NONFINITE;
    } else {
        /* a chain to run */
    }
    return rc;
}

/* The forward pass: every link's frame and motion. */
static void forward_pass(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                         dyn_link_state_t *st)
{
    double w[3] = {0.0, 0.0, 0.0};
    double wd[3] = {0.0, 0.0, 0.0};
    double a[3];
    uint32_t i;
    a[0] = -ch->gravity[0];
    a[1] = -ch->gravity[1];
    a[2] = -ch->gravity[2];
    for (i = 0U; i < ch->n; i++) {
        dyn_link_state_t *s = &st[i];
        double t[3];
        double u[3];
        uint32_t k;
        joint_rotation(&ch->j[i], q[i] + ch->j[i].theta0, &s->r);
        for (k = 0U; k < 3U; k++) {
            s->p[k] = ch->j[i].pos[k];
        }
        /* the origin's acceleration in the parent frame, then in this one */
        cross3(w, s->p, t);
        cross3(w, t, u);
        cross3(wd, s->p, t);
        for (k = 0U; k < 3U; k++) {
            u[k] += a[k] + t[k];
        }
        rot_t_mul(&s->r, u, s->a);
        rot_t_mul(&s->r, w, s->w);
        rot_t_mul(&s->r, wd, s->wd);
        /* wd += w x (qd z) + qdd z, w += qd z */
        s->wd[0] += s->w[1] * qd[i];
        s->wd[1] -= s->w[0] * qd[i];
        s->wd[2] += qdd[i];
        s->w[2] += qd[i];
        for (k = 0U; k < 3U; k++) {
            w[k] = s->w[k];
            wd[k] = s->wd[k];
            a[k] = s->a[k];
        }
    }
}

/* The checks of c4g_dyn_chain_dh's arguments. */
static c4g_status_t check_dh(const c4g_dyn_chain_t *ch, uint32_t n, c4g_dyn_convention_t conv, const double *a,
                             const double *alpha, const double *d, const double *theta0, const double gravity[3])
{
    c4g_status_t rc = C4G_OK;
    uint32_t i;
    if ((ch == NULL) || (a == NULL) || (alpha == NULL) || (d == NULL) || (theta0 == NULL) || (gravity == NULL)) {
        rc = C4G_ERR_NULL;
    } else if ((n == 0U) || (n > C4G_DYN_MAX_LINKS) ||
               ((conv != C4G_DYN_DH_STANDARD) && (conv != C4G_DYN_DH_MODIFIED))) {
        rc = C4G_ERR_ARG;
    } else if ((dyn_all_finite(a, n) == 0) || (dyn_all_finite(alpha, n) == 0) || (dyn_all_finite(d, n) == 0) ||
               (dyn_all_finite(theta0, n) == 0) || (dyn_finite3(gravity) == 0)) {
        rc = C4G_ERR_NONFINITE;
    } else {
        for (i = 0U; i < n; i++) {
            if ((fabs(a[i]) > C4G_DYN_LENGTH_MAX) || (fabs(d[i]) > C4G_DYN_LENGTH_MAX) ||
                (fabs(alpha[i]) > DYN_TWO_PI) || (fabs(theta0[i]) > DYN_TWO_PI)) {
                rc = C4G_ERR_RANGE;
            }
        }
        if (sqrt((gravity[0] * gravity[0]) + (gravity[1] * gravity[1]) + (gravity[2] * gravity[2])) >
            DYN_GRAVITY_MAX) {
            rc = C4G_ERR_RANGE;
        }
    }
    return rc;
}

c4g_status_t c4g_dyn_chain_dh(c4g_dyn_chain_t *ch, uint32_t n, c4g_dyn_convention_t conv, const double *a,
                              const double *alpha, const double *d, const double *theta0, const double gravity[3])
{
    const c4g_status_t rc = check_dh(ch, n, conv, a, alpha, d, theta0, gravity);
    if (rc == C4G_OK) {
        uint32_t i;
        ch->n = n;
        for (i = 0U; i < C4G_DYN_MAX_LINKS; i++) {
            /* modified: Rx(alpha_{i-1}) Tx(a_{i-1}) then Tz(d_i); standard rewritten on the
             * joint axes is the same with a, alpha taken from the link before (none for the
             * first link); links past n are identities */
            double al = 0.0;
            double ai = 0.0;
            double di = 0.0;
            double th = 0.0;
            c4g_dyn_joint_t *jt = &ch->j[i];
            double c;
            double sn;
            if (i < n) {
                di = d[i];
                th = theta0[i];
                if (conv == C4G_DYN_DH_MODIFIED) {
                    al = alpha[i];
                    ai = a[i];
                } else if (i > 0U) {
                    al = alpha[i - 1U];
                    ai = a[i - 1U];
                } else {
                    /* the base frame is the first joint's */
                }
            }
            c = cos(al);
            sn = sin(al);
            jt->rot[0][0] = 1.0;
            jt->rot[0][1] = 0.0;
            jt->rot[0][2] = 0.0;
            jt->rot[1][0] = 0.0;
            jt->rot[1][1] = c;
            jt->rot[1][2] = -sn;
            jt->rot[2][0] = 0.0;
            jt->rot[2][1] = sn;
            jt->rot[2][2] = c;
            jt->pos[0] = ai;
            jt->pos[1] = -sn * di;
            jt->pos[2] = c * di;
            jt->theta0 = th;
        }
        for (i = 0U; i < 3U; i++) {
            ch->gravity[i] = gravity[i];
        }
    }
    return rc;
}

/* I v for the inertia {Ixx, Ixy, Ixz, Iyy, Iyz, Izz} */
static void inertia_mul(const double *ip, const double v[3], double out[3])
{
    out[0] = (ip[0] * v[0]) + (ip[1] * v[1]) + (ip[2] * v[2]);
    out[1] = (ip[1] * v[0]) + (ip[3] * v[1]) + (ip[4] * v[2]);
    out[2] = (ip[2] * v[0]) + (ip[4] * v[1]) + (ip[5] * v[2]);
}

static c4g_status_t rnea_passes(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                                const double *pi, const double *ia, double *tau);

c4g_status_t c4g_dyn_rnea(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                          const double *pi, const double *ia, double *tau)
{
    c4g_status_t rc = check_motion(ch, q, qd, qdd);
    if ((rc == C4G_OK) && ((pi == NULL) || (tau == NULL))) {
        rc = C4G_ERR_NULL;
    }
    if ((rc == C4G_OK) &&
        ((dyn_all_finite(pi, ch->n * C4G_DYN_PARAMS) == 0) || ((ia != NULL) && (dyn_all_finite(ia, ch->n) == 0)))) {
        rc = C4G_ERR_NONFINITE;
    }
    if (rc == C4G_OK) {
        rc = rnea_passes(ch, q, qd, qdd, pi, ia, tau);
    }
    return rc;
}

c4g_status_t c4g_dyn_model_init(c4g_dyn_model_t *m, const c4g_dyn_chain_t *ch, const double *pi, const double *ia)
{
    c4g_status_t rc = C4G_OK;
    if ((m == NULL) || (ch == NULL) || (pi == NULL)) {
        rc = C4G_ERR_NULL;
    } else {
        m->checked = 0U;
        if ((ch->n == 0U) || (ch->n > C4G_DYN_MAX_LINKS)) {
            rc = C4G_ERR_ARG;
        } else if ((dyn_all_finite(pi, ch->n * C4G_DYN_PARAMS) == 0) ||
                   ((ia != NULL) && (dyn_all_finite(ia, ch->n) == 0)) || (dyn_finite3(ch->gravity) == 0)) {
            rc = C4G_ERR_NONFINITE;
        } else {
            uint32_t i;
            m->chain = *ch;
            for (i = 0U; i < (C4G_DYN_MAX_LINKS * C4G_DYN_PARAMS); i++) {
                m->pi[i] = (i < (ch->n * C4G_DYN_PARAMS)) ? pi[i] : 0.0;
            }
            for (i = 0U; i < C4G_DYN_MAX_LINKS; i++) {
                m->ia[i] = ((ia != NULL) && (i < ch->n)) ? ia[i] : 0.0;
            }
            m->checked = C4G_DYN_CHECKED;
        }
    }
    return rc;
}

c4g_status_t c4g_dyn_model_rnea(const c4g_dyn_model_t *m, const double *q, const double *qd, const double *qdd,
                                double *tau)
{
    c4g_status_t rc = C4G_ERR_NULL;
    if ((m != NULL) && (tau != NULL)) {
        rc = (m->checked == C4G_DYN_CHECKED) ? check_motion(&m->chain, q, qd, qdd) : C4G_ERR_STATE;
    }
    if (rc == C4G_OK) {
        rc = rnea_passes(&m->chain, q, qd, qdd, m->pi, m->ia, tau);
    }
    return rc;
}

/* The validated body of c4g_dyn_rnea. */
static c4g_status_t rnea_passes(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                                const double *pi, const double *ia, double *tau)
{
    dyn_link_state_t st[C4G_DYN_MAX_LINKS];
    double f[3] = {0.0, 0.0, 0.0};
    double nm[3] = {0.0, 0.0, 0.0};
    uint32_t idx;
    c4g_status_t rc = C4G_OK;
    forward_pass(ch, q, qd, qdd, st);
    /* backward: (f, nm) is the wrench the child exerts, in the child's frame at its origin */
    for (idx = ch->n; idx > 0U; idx--) {
        const uint32_t i = idx - 1U;
        const dyn_link_state_t *s = &st[i];
        const double *p = &pi[(size_t)i * C4G_DYN_PARAMS];
        double t[3];
        double u[3];
        double own_f[3];
        double own_n[3];
        uint32_t k;
        /* own: f = m a + wd x h + w x (w x h), n = I wd + w x (I w) + h x a */
        cross3(s->w, &p[1], t);
        cross3(s->w, t, u);
        cross3(s->wd, &p[1], t);
        for (k = 0U; k < 3U; k++) {
            own_f[k] = (p[0] * s->a[k]) + t[k] + u[k];
        }
        inertia_mul(&p[4], s->w, t);
        cross3(s->w, t, u);
        inertia_mul(&p[4], s->wd, t);
        for (k = 0U; k < 3U; k++) {
            own_n[k] = t[k] + u[k];
        }
        cross3(&p[1], s->a, t);
        for (k = 0U; k < 3U; k++) {
            own_n[k] += t[k];
        }
        if ((i + 1U) < ch->n) {
            const dyn_link_state_t *c = &st[i + 1U];
            double rf[3];
            double rn[3];
            rot_mul(&c->r, f, rf);
            rot_mul(&c->r, nm, rn);
            cross3(c->p, rf, t);
            for (k = 0U; k < 3U; k++) {
                own_f[k] += rf[k];
                own_n[k] += rn[k] + t[k];
            }
        }
        for (k = 0U; k < 3U; k++) {
            f[k] = own_f[k];
            nm[k] = own_n[k];
        }
        tau[i] = nm[2] + ((ia != NULL) ? (ia[i] * qdd[i]) : 0.0);
        if (!isfinite(tau[i])) {
            rc = C4G_ERR_NONFINITE;
        }
    }
    return rc;
}

/* The own wrench of one link as a 6 x 10 block: rows fx fy fz nx ny nz, columns pi. */
static void own_block(const dyn_link_state_t *s, double b[6][C4G_DYN_PARAMS])
{
    const double *w = s->w;
    const double *wd = s->wd;
    const double *a = s->a;
    uint32_t r;
    uint32_t k;
    for (r = 0U; r < 6U; r++) {
        for (k = 0U; k < C4G_DYN_PARAMS; k++) {
            b[r][k] = 0.0;
        }
    }
    /* f: m a + ([wd x] + [w x]^2) h */
    for (r = 0U; r < 3U; r++) {
        b[r][0] = a[r];
    }
    for (k = 0U; k < 3U; k++) {
        double e[3] = {0.0, 0.0, 0.0};
        double t[3];
        double u[3];
        e[k] = 1.0;
        cross3(w, e, t);
        cross3(w, t, u);
        cross3(wd, e, t);
        /* n: h x a = e_k x a per unit h_k */
        b[0][1U + k] = t[0] + u[0];
        b[1][1U + k] = t[1] + u[1];
        b[2][1U + k] = t[2] + u[2];
        cross3(e, a, t);
        b[3][1U + k] = t[0];
        b[4][1U + k] = t[1];
        b[5][1U + k] = t[2];
    }
    /* n: I wd + w x (I w), per inertia element */
    for (k = 0U; k < 6U; k++) {
        double ip[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        double t[3];
        double u[3];
        ip[k] = 1.0;
        inertia_mul(ip, w, t);
        cross3(w, t, u);
        inertia_mul(ip, wd, t);
        b[3][4U + k] = t[0] + u[0];
        b[4][4U + k] = t[1] + u[1];
        b[5][4U + k] = t[2] + u[2];
    }
}

static c4g_status_t regressor_passes(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                                     double *y);

c4g_status_t c4g_dyn_regressor(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                               double *y, uint32_t cap)
{
    c4g_status_t rc = check_motion(ch, q, qd, qdd);
    if ((rc == C4G_OK) && (y == NULL)) {
        rc = C4G_ERR_NULL;
    }
    if ((rc == C4G_OK) && (cap < (ch->n * ch->n * C4G_DYN_PARAMS))) {
        rc = C4G_ERR_CAPACITY;
    }
    if (rc == C4G_OK) {
        rc = regressor_passes(ch, q, qd, qdd, y);
    }
    return rc;
}

/* The validated body of c4g_dyn_regressor. */
static c4g_status_t regressor_passes(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *qdd,
                                     double *y)
{
    dyn_link_state_t st[C4G_DYN_MAX_LINKS];
    const uint32_t cols = ch->n * C4G_DYN_PARAMS;
    uint32_t j;
    c4g_status_t rc = C4G_OK;
    for (j = 0U; j < (ch->n * cols); j++) {
        y[j] = 0.0;
    }
    forward_pass(ch, q, qd, qdd, st);
    for (j = 0U; j < ch->n; j++) {
        double b[6][C4G_DYN_PARAMS];
        uint32_t k;
        uint32_t i = j;
        own_block(&st[j], b);
        for (k = 0U; k < C4G_DYN_PARAMS; k++) {
            y[((size_t)i * cols) + ((size_t)j * C4G_DYN_PARAMS) + k] = b[5][k];
        }
        /* carry the block down to each ancestor's frame: F' = R F, N' = R N + p x (R F) */
        while (i > 0U) {
            const dyn_link_state_t *s = &st[i];
            i--;
            for (k = 0U; k < C4G_DYN_PARAMS; k++) {
                double fv[3];
                double nv[3];
                double rf[3];
                double rn[3];
                double t[3];
                uint32_t r;
                for (r = 0U; r < 3U; r++) {
                    fv[r] = b[r][k];
                    nv[r] = b[3U + r][k];
                }
                rot_mul(&s->r, fv, rf);
                rot_mul(&s->r, nv, rn);
                cross3(s->p, rf, t);
                for (r = 0U; r < 3U; r++) {
                    b[r][k] = rf[r];
                    b[3U + r][k] = rn[r] + t[r];
                }
                y[((size_t)i * cols) + ((size_t)j * C4G_DYN_PARAMS) + k] = b[5][k];
            }
        }
    }
    if (dyn_all_finite(y, ch->n * cols) == 0) {
        rc = C4G_ERR_NONFINITE;
    }
    return rc;
}

static void params_about_origin(double m, const double c[3], const double icom[6], double pi[10]);

c4g_status_t c4g_dyn_params_from_com(double m, const double c[3], const double icom[6], double pi[10])
{
    c4g_status_t rc = C4G_OK;
    if ((c == NULL) || (icom == NULL) || (pi == NULL)) {
        rc = C4G_ERR_NULL;
    } else if ((!isfinite(m)) || (dyn_finite3(c) == 0) || (dyn_all_finite(icom, 6U) == 0)) {
        rc = C4G_ERR_NONFINITE;
    } else if (m < 0.0) {
        rc = C4G_ERR_RANGE;
    } else {
        params_about_origin(m, c, icom, pi);
    }
    return rc;
}

/* pi from validated mass, centre and inertia about the centre. */
static void params_about_origin(double m, const double c[3], const double icom[6], double pi[10])
{
    double cc;
    uint32_t r;
    uint32_t k;
    cc = (c[0] * c[0]) + (c[1] * c[1]) + (c[2] * c[2]);
    pi[0] = m;
    for (r = 0U; r < 3U; r++) {
        pi[1U + r] = m * c[r];
    }
    /* parallel axes: I_o = I_c + m (|c|^2 E - c c^T), packed xx xy xz yy yz zz */
    k = 4U;
    for (r = 0U; r < 3U; r++) {
        uint32_t s;
        for (s = r; s < 3U; s++) {
            const double e = (r == s) ? cc : 0.0;
            pi[k] = icom[k - 4U] + (m * (e - (c[r] * c[s])));
            k++;
        }
    }
}
