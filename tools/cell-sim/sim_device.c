/* SPDX-License-Identifier: MIT */
/* cell-sim device model (see sim_device.h and docs/cell-sim.md). */
#include "sim_device.h"

#include <math.h>
#include <string.h>

#include "c4gh_cell.h"

const char *sim_axis_name(int kind, int axis)
{
    static const char *const r[4] = {"x", "y", "z", "c"};
    static const char *const p[2] = {"a", "b"};
    if (kind == C4GH_CELL_DEV_ROBOT && axis >= 0 && axis < 4) {
        return r[axis];
    }
    if (kind == C4GH_CELL_DEV_PLATFORM && axis >= 0 && axis < 2) {
        return p[axis];
    }
    return "?";
}

void sim_device_init(sim_device_t *d, int kind, double speed_factor)
{
    memset(d, 0, sizeof *d);
    d->kind = kind;
    d->ovr = 100;
    d->cameras = 2;
    if (kind == C4GH_CELL_DEV_ROBOT) {
        static const double lo[4] = {-200.0, -200.0, -100.0, -3.1416};
        static const double hi[4] = {200.0, 200.0, 200.0, 3.1416};
        static const double v[4] = {50.0, 50.0, 50.0, 1.0}; /* mm/s, rad/s */
        d->n_axes = 4;
        d->home[2] = 50.0; /* above the work plane */
        memcpy(d->lo, lo, sizeof lo);
        memcpy(d->hi, hi, sizeof hi);
        memcpy(d->vmax, v, sizeof v);
    } else if (kind == C4GH_CELL_DEV_PLATFORM) {
        d->n_axes = 2;
        d->lo[0] = d->lo[1] = -1.5708;
        d->hi[0] = d->hi[1] = 1.5708;
        d->vmax[0] = d->vmax[1] = 0.5;
    }
    for (int a = 0; a < 4; a++) {
        d->vmax[a] *= speed_factor;
    }
}

/* Seconds a straight segment from pos to t takes at 100 %: the slowest axis decides,
 * so every axis arrives together (linear interpolation). */
static double seg_time(const sim_device_t *d, const double *t)
{
    double r = 0.0;
    for (int a = 0; a < d->n_axes; a++) {
        double s = fabs(t[a] - d->pos[a]) / d->vmax[a];
        if (s > r) {
            r = s;
        }
    }
    return r;
}

void sim_device_update(sim_device_t *d, uint64_t now_ns)
{
    double dt = (now_ns > d->last_ns) ? (double)(now_ns - d->last_ns) * 1e-9 : 0.0;
    double rate = (double)d->ovr / 100.0;
    d->last_ns = now_ns;
    /* Override 0 holds the motion (still "moving"); segments chain without a stop. */
    while (d->moving && dt > 0.0 && rate > 0.0) {
        const double *t = d->seg[d->seg_i];
        double need = seg_time(d, t) / rate;
        if (need <= dt) {
            memcpy(d->pos, t, sizeof d->pos);
            dt -= need;
            d->seg_i++;
            if (d->seg_i >= d->nseg) {
                d->moving = 0;
            }
        } else {
            double f = dt / need;
            for (int a = 0; a < d->n_axes; a++) {
                d->pos[a] += (t[a] - d->pos[a]) * f;
            }
            dt = 0.0;
        }
    }
}

static int in_workspace(const sim_device_t *d, const double *p)
{
    for (int a = 0; a < d->n_axes; a++) {
        if (p[a] < d->lo[a] - 1e-9 || p[a] > d->hi[a] + 1e-9) {
            return 0;
        }
    }
    return 1;
}

static void pose_to_units(const sim_device_t *d, const c4g_cell_pose_t *p, double *out)
{
    for (int a = 0; a < d->n_axes; a++) {
        c4g_cell_unit_t u = (d->kind == C4GH_CELL_DEV_ROBOT && a < 3) ? C4G_CELL_UNIT_MM
                                                                 : C4G_CELL_UNIT_RAD;
        (void)c4g_cell_to_double(p->v[a], u, &out[a]);
    }
}

static void fill_sta(const sim_device_t *d, c4g_cell_reply_t *rep)
{
    rep->kind = C4G_CELL_REPLY_STA;
    rep->moving = (uint8_t)(d->moving ? 1 : 0);
    rep->servo_on = (uint8_t)(d->servo ? 1 : 0);
    rep->override_pct = d->ovr;
    rep->error = d->error;
    rep->pose.n_axes = (uint32_t)d->n_axes;
    for (int a = 0; a < d->n_axes; a++) {
        c4g_cell_unit_t u = (d->kind == C4GH_CELL_DEV_ROBOT && a < 3) ? C4G_CELL_UNIT_MM
                                                                 : C4G_CELL_UNIT_RAD;
        if (c4g_cell_from_double(d->pos[a], u, &rep->pose.v[a]) != C4G_OK) {
            rep->pose.v[a] = 0; /* limits keep positions in range; defensive only */
        }
    }
}

/* ER reply; device errors (not protocol errors) latch into STA's error field. */
static const char *fail(sim_device_t *d, c4g_cell_reply_t *rep, int32_t code, const char *note)
{
    rep->kind = C4G_CELL_REPLY_ER;
    rep->error = code;
    if (code == C4G_CELL_E_GENERIC || code == C4G_CELL_E_SERVO1 || code == C4G_CELL_E_SERVO2 ||
        code == C4G_CELL_E_SERVO_OFF || code == C4G_CELL_E_WORKSPACE) {
        d->error = code;
    }
    return note;
}

static const char *start_motion(sim_device_t *d, c4g_cell_reply_t *rep)
{
    for (int s = 0; s < d->nseg; s++) {
        if (!in_workspace(d, d->seg[s])) {
            d->nseg = 0;
            return fail(d, rep, C4G_CELL_E_WORKSPACE, "target outside the workspace");
        }
    }
    d->seg_i = 0;
    d->moving = d->nseg > 0;
    rep->kind = C4G_CELL_REPLY_OK;
    return "motion started";
}

static const char *exec_motion_dev(sim_device_t *d, const c4g_cell_instr_t *in,
                                   c4g_cell_reply_t *rep)
{
    double t[4] = {0, 0, 0, 0};
    switch (in->cmd) {
    case C4G_CELL_CMD_STA:
        fill_sta(d, rep);
        return "status";
    case C4G_CELL_CMD_SRVON:
        if (d->servo_fault == 1 || d->servo_fault == 2) {
            d->servo = 0;
            return fail(d, rep, d->servo_fault == 1 ? C4G_CELL_E_SERVO1 : C4G_CELL_E_SERVO2,
                        "servo fault (injected)");
        }
        d->servo = 1;
        rep->kind = C4G_CELL_REPLY_OK;
        return "servo on";
    case C4G_CELL_CMD_SRVOF:
        d->servo = 0;
        d->moving = 0;
        rep->kind = C4G_CELL_REPLY_OK;
        return "servo off";
    case C4G_CELL_CMD_OVR:
        d->ovr = in->value;
        rep->kind = C4G_CELL_REPLY_OK;
        return "override set";
    case C4G_CELL_CMD_MOV:
        if ((int)in->pose.n_axes != d->n_axes) {
            return fail(d, rep, C4G_CELL_E_MALFORMED, "MOV layout of another device");
        }
        if (!d->servo) {
            return fail(d, rep, C4G_CELL_E_SERVO_OFF, "MOV refused: servo off");
        }
        if (d->moving) {
            return fail(d, rep, C4G_CELL_E_BUSY, "MOV refused: moving");
        }
        pose_to_units(d, &in->pose, t);
        for (int a = 0; a < d->n_axes; a++) {
            d->seg[0][a] = in->relative ? d->pos[a] + t[a] : t[a];
        }
        d->nseg = 1;
        return start_motion(d, rep);
    case C4G_CELL_CMD_PNP: {
        double clear;
        if (d->kind != C4GH_CELL_DEV_ROBOT) {
            return fail(d, rep, C4G_CELL_E_UNSUPPORTED, "PNP is robot only");
        }
        if (!d->servo) {
            return fail(d, rep, C4G_CELL_E_SERVO_OFF, "PNP refused: servo off");
        }
        if (d->moving) {
            return fail(d, rep, C4G_CELL_E_BUSY, "PNP refused: moving");
        }
        pose_to_units(d, &in->pose, t);
        (void)c4g_cell_to_double(in->clearance, C4G_CELL_UNIT_MM, &clear);
        if (clear < d->pos[2] || clear < t[2]) {
            return fail(d, rep, C4G_CELL_E_RANGE, "PNP clearance below start or target Z");
        }
        /* lift to the clearance height, travel above the target, descend */
        memcpy(d->seg[0], d->pos, sizeof d->seg[0]);
        d->seg[0][2] = clear;
        memcpy(d->seg[1], t, sizeof d->seg[1]);
        d->seg[1][2] = clear;
        memcpy(d->seg[2], t, sizeof d->seg[2]);
        d->nseg = 3;
        return start_motion(d, rep);
    }
    case C4G_CELL_CMD_STP:
    case C4G_CELL_CMD_ITR:
        d->moving = 0;
        rep->kind = C4G_CELL_REPLY_OK;
        return in->cmd == C4G_CELL_CMD_STP ? "stopped" : "interrupted";
    case C4G_CELL_CMD_RST:
        d->moving = 0;
        d->error = 0;
        rep->kind = C4G_CELL_REPLY_OK;
        if (d->servo) {
            memcpy(d->seg[0], d->home, sizeof d->seg[0]);
            d->nseg = 1;
            d->seg_i = 0;
            d->moving = 1;
            return "reset: homing";
        }
        return "reset (servo off: no homing)";
    default:
        return fail(d, rep, C4G_CELL_E_UNSUPPORTED, "not handled by this device");
    }
}

static const char *exec_conditioning(sim_device_t *d, const c4g_cell_instr_t *in,
                                     c4g_cell_reply_t *rep)
{
    switch (in->cmd) {
    case C4G_CELL_CMD_ACQ:
        if (in->value < 1 || in->value > d->cameras) {
            return fail(d, rep, C4G_CELL_E_RANGE, "no such camera");
        }
        d->acquisitions++;
        rep->kind = C4G_CELL_REPLY_OK;
        return "image acquired";
    case C4G_CELL_CMD_HND:
        if (in->value < 0 || in->value >= SIM_GRIPPERS) {
            return fail(d, rep, C4G_CELL_E_RANGE, "no such gripper valve");
        }
        d->valve[in->value] = in->open ? 1 : 0;
        rep->kind = C4G_CELL_REPLY_OK;
        if (in->value == 0) {
            return in->open ? "vacuum on" : "vacuum off";
        }
        return in->open ? "blow on" : "blow off";
    case C4G_CELL_CMD_RST:
        d->valve[0] = d->valve[1] = 0;
        d->error = 0;
        rep->kind = C4G_CELL_REPLY_OK;
        return "reset: valves closed";
    default:
        return fail(d, rep, C4G_CELL_E_UNSUPPORTED, "not handled by the conditioning controller");
    }
}

const char *sim_device_exec(sim_device_t *d, const c4g_cell_instr_t *in, uint64_t now_ns,
                            c4g_cell_reply_t *rep, int *close_after)
{
    memset(rep, 0, sizeof *rep);
    *close_after = 0;
    sim_device_update(d, now_ns);
    if (in->cmd == C4G_CELL_CMD_CLO) {
        rep->kind = C4G_CELL_REPLY_OK;
        *close_after = 1;
        return "close requested";
    }
    if (d->kind == C4GH_CELL_DEV_CONDITIONING) {
        return exec_conditioning(d, in, rep);
    }
    if (in->cmd == C4G_CELL_CMD_ACQ || in->cmd == C4G_CELL_CMD_HND) {
        return fail(d, rep, C4G_CELL_E_UNSUPPORTED, "ACQ/HND go to the conditioning controller");
    }
    return exec_motion_dev(d, in, rep);
}
