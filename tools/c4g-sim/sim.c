/* SPDX-License-Identifier: MIT */
/* c4g-sim controller: modes (chapter 14), special modes (15), state machine (24),
 * errors (17), PDL2-like scenario interpreter (figure 24.4). No I/O but the log. */
#include "sim.h"
#include "c4gsim_fixtures.h"

#include <math.h>
#include <stdarg.h>
#include <string.h>

#define SUBSTEPS_PER_MS 2   /* DSA at 2 kHz */

static void logf_(sim_t *s, const char *fmt, ...)
{
    va_list ap;
    if (s->log == NULL) {
        return;
    }
    va_start(ap, fmt);
    fprintf(s->log, "c4g-sim: tick %lu: ", s->tick);
    vfprintf(s->log, fmt, ap);
    fputc('\n', s->log);
    va_end(ap);
}

void sim_raise(sim_t *s, c4g_ctrl_error_t code, int a1, int a2)
{
    sim_error_t *e;
    char armtxt[16];
    if (s->n_err >= SIM_MAX_ERRORS) {
        return;
    }
    e = &s->err[s->n_err++];
    e->code = code;
    e->tick = s->tick;
    switch (code) {
    case C4G_CERR_CONFIGURATION_AX:
        snprintf(e->text, sizeof e->text, "C4GOpen: Arm %d Axis %d not present", a1, a2);
        break;
    case C4G_CERR_FOLLOW_ERROR:
        /* The manual's message has "arm %s". */
        snprintf(armtxt, sizeof armtxt, "%d", a1);
        snprintf(e->text, sizeof e->text, "C4GOpen: arm %s axis %d Following error out of range",
                 armtxt, a2);
        break;
    case C4G_CERR_OPT_HW:
        snprintf(e->text, sizeof e->text, "C4GOpen: software option not allowed for arm %d", a1);
        break;
    case C4G_CERR_SET_0_MODALITY:
        snprintf(e->text, sizeof e->text, "C4GOpen: arm %d , forced 0 modality", a1);
        break;
    default:
        snprintf(e->text, sizeof e->text, "%s", c4g_ctrl_error_message(code));
        break;
    }
    if (s->log != NULL) {
        fprintf(s->log, "c4g-sim: tick %lu: %s: %s\n", s->tick, c4g_ctrl_error_name(code), e->text);
    }
}

int sim_has_error(const sim_t *s, const char *name)
{
    int i;
    for (i = 0; i < s->n_err; i++) {
        if (strcmp(c4g_ctrl_error_name(s->err[i].code), name) == 0) {
            return 1;
        }
    }
    return 0;
}

static void arm_drive_off(sim_t *s, int arm);

/* The axis model refused a value (not finite, out of range): the arm's drives go off, as a
 * real drive faults, rather than running on with a state nobody can trust. */
static void model_fault(sim_t *s, const sim_ax_t *x, const char *what)
{
    logf_(s, "arm %d axis %d: the model refused its %s input: drives off", x->arm + 1, x->logical + 1,
          what);
    arm_drive_off(s, x->arm);
}

static void arm_drive_off(sim_t *s, int arm)
{
    int i;
    s->arm[arm].drive = DRV_OFF;
    s->arm[arm].moving = 0;
    s->arm[arm].frozen_a = 0;
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        if (x->arm == arm) {
            x->m.drive_on = 0;
            x->set_mode = C4G_MODE_0;
            x->req_mode = -1;
            x->counter = 0;
            x->standby_ticks = 0;
            x->pos_i = x->m.meas_pos;
            x->vel_i = 0.0;
            x->ref.offset = 0.0;
        }
    }
}

void sim_all_drive_off(sim_t *s)
{
    int a;
    for (a = 0; a < (int)C4G_ARMS; a++) {
        arm_drive_off(s, a);
    }
}

int sim_checks_suspended(const sim_t *s)
{
    int a;
    for (a = 0; a < (int)C4G_ARMS; a++) {
        if (s->arm[a].frozen_a) {
            return 1;
        }
    }
    return 0;
}

/* The controller's dynamic model of the arm plant's axes at motor positions @p qm, velocities
 * @p vm and accelerations @p am, into each axis's model_cur and model_inertia. */
static int plant_model(sim_t *s, const double *qm, const double *vm, const double *am)
{
    double cur[PLANT_AXES];
    double in[PLANT_AXES];
    int k;
    if (plant_arm_model(s->plant, qm, vm, am, cur, in) != 0) {
        return -1;
    }
    for (k = 0; k < PLANT_AXES; k++) {
        s->ax[s->plant_ax[k]].model_cur = cur[k];
        s->ax[s->plant_ax[k]].model_inertia = in[k];
    }
    return 0;
}

/* The arm plant moves logical axes 1..6 of arm 1 (all six must be open); other axes and
 * arms keep the decoupled model. */
static int plant_init(sim_t *s)
{
    const int sub = SUBSTEPS_PER_MS * s->cfg.period_ms;
    const c4gsim_axis_params_t *p[PLANT_AXES];
    double qm[PLANT_AXES];
    double zero[PLANT_AXES] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    int k;
    int i;
    for (k = 0; k < PLANT_AXES; k++) {
        s->plant_ax[k] = -1;
        for (i = 0; i < s->n_axes; i++) {
            if (s->ax[i].arm == 0 && s->ax[i].logical == k) {
                s->plant_ax[k] = i;
            }
        }
        if (s->plant_ax[k] < 0) {
            snprintf(s->init_err, sizeof s->init_err, "%s: the arm plant moves axes 1..6 of arm 1: axis %d "
                     "is not open", s->cfg.plant.path, k + 1);
            return -1;
        }
        p[k] = s->ax[s->plant_ax[k]].p;
        qm[k] = s->ax[s->plant_ax[k]].m.pos;
        s->ax[s->plant_ax[k]].in_plant = 1;
    }
    if (plant_arm_open(&s->plant, &s->cfg.plant, &s->init, 0U, p, s->period / (double)sub, s->init_err,
                       sizeof s->init_err) != 0) {
        return -1;
    }
    if (plant_arm_reset(s->plant, qm) != 0 || plant_model(s, qm, zero, zero) != 0) {
        snprintf(s->init_err, sizeof s->init_err, "%s: the start positions are not convertible to joints",
                 s->cfg.plant.path);
        sim_free(s);
        return -1;
    }
    return 0;
}

int sim_init(sim_t *s, const sim_config_t *cfg, const scn_t *scn, FILE *log)
{
    int a;
    int l;
    int n = 0;
    memset(s, 0, sizeof *s);
    s->cfg = *cfg;
    s->log = log;
    s->scn = scn;
    s->override = 1.0;
    s->period = (double)cfg->period_ms / 1000.0;
    (void)c4gsim_rng_seed(&s->rng, cfg->seed); /* cannot fail: s->rng exists */
    if (sim_config_axes(cfg) < 0) {
        sim_raise(s, C4G_CERR_CONFIG, 0, 0);
        return -1;
    }
    for (a = 0; a < cfg->n_arms; a++) {
        if (!cfg->option_ok[a]) {
            sim_raise(s, C4G_CERR_OPT_HW, a + 1, 0);
            return -1;
        }
    }
    /* Initialization packet (field facts order): figure 10.1 shape, our axes. */
    (void)c4gsim_fig10_1(&s->init);
    s->init.period_ms = cfg->period_ms;
    s->init.version_major = cfg->version[0];
    s->init.version_minor = cfg->version[1];
    s->init.version_build = cfg->version[2];
    for (a = 0; a < (int)C4G_ARMS; a++) {
        for (l = 0; l < (int)C4G_AXES_PER_ARM; l++) {
            const c4gsim_axis_params_t *p = &cfg->ax[a][l];
            const int open = (a < cfg->n_arms) && ((cfg->open_mask[a] >> l) & 1U);
            s->init.open_ax[a][l] = open ? n : C4G_OPEN_AX_NONE;
            s->init.open_mask[a][l] = open ? p->startup_mode : 0;
            s->init.cal_data[a][l] = open ? (float)p->cal : 0.0F;
            s->init.az_lim[a][l] = open ? (float)p->az_lim : 0.0F;
            s->init.ax_info[a][l] = open ? (float)p->ax_info : 0.0F;
            s->init.tx_rate[a][l] = open ? (float)p->tx_rate : 0.0F;
            s->init.follow_error[a][l] = open ? (float)p->follow_error : 0.0F;
            if (open) {
                sim_ax_t *x = &s->ax[n];
                x->arm = a;
                x->logical = l;
                x->p = &s->cfg.ax[a][l];
                if (c4gsim_axis_reset(&x->m, x->p, &s->rng) != C4G_OK) {
                    sim_raise(s, C4G_CERR_CONFIG, 0, 0); /* parameters the model refuses */
                    return -1;
                }
                x->mode = p->startup_mode;
                x->set_mode = p->startup_mode;
                x->req_mode = -1;
                x->pos_i = x->m.meas_pos;
                x->pos_ref = x->pos_i;
                x->prev_tick_meas = x->m.meas_pos;
                n++;
            }
        }
    }
    s->init.n_ax_open = n;
    s->n_axes = n;
    if (c4g_init_validate(&s->init, NULL) != C4G_OK ||
        c4g_axis_map_build(&s->init, &s->map, NULL) != C4G_OK) {
        sim_raise(s, C4G_CERR_CONFIG, 0, 0);
        return -1;
    }
    if (cfg->plant.path[0] != '\0' && plant_init(s) != 0) {
        sim_raise(s, C4G_CERR_CONFIG, 0, 0);
        return -1;
    }
    return 0;
}

void sim_free(sim_t *s)
{
    plant_arm_close(s->plant);
    s->plant = NULL;
}

/* ---- scenario ------------------------------------------------------------ */

static int arm_axes(const sim_t *s, int arm)
{
    int i;
    int k = 0;
    for (i = 0; i < s->n_axes; i++) {
        k += (s->ax[i].arm == arm);
    }
    return k;
}

static sim_ax_t *find_axis(sim_t *s, int arm, int logical)
{
    int i;
    for (i = 0; i < s->n_axes; i++) {
        if (s->ax[i].arm == arm && s->ax[i].logical == logical) {
            return &s->ax[i];
        }
    }
    return NULL;
}

static int arm_in_transition(const sim_t *s, int arm)
{
    int i;
    for (i = 0; i < s->n_axes; i++) {
        const sim_ax_t *x = &s->ax[i];
        if (x->arm == arm && (x->set_mode == C4G_MODE_1_STANDBY || x->set_mode == C4G_MODE_2_STANDBY ||
                              x->set_mode == C4G_MODE_4_STANDBY || x->set_mode == C4G_MODE_5_STANDBY ||
                              x->set_mode == C4G_MODE_7_STANDBY ||
                              x->set_mode == C4G_MODE_7_STANDBY_EXIT)) {
            return 1;
        }
    }
    return 0;
}

static void start_move(sim_t *s, const scn_cmd_t *c)
{
    const int arm = c->arm - 1;
    double dur = 0.0;
    int i;
    int k = 0;
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        if (x->arm == arm) {
            const double tgt = (k < c->n) ? ((c->op == SCN_MOVE) ? c->v[k] : x->pos_i + c->v[k]) : x->pos_i;
            const double ov = (s->override > 0.01) ? s->override : 0.01;
            const double t = c4gsim_trap_min_time(tgt - x->pos_i, x->p->vmax * ov, x->p->amax * ov * ov);
            if (t > dur) {
                dur = t;
            }
            x->trap.p0 = x->pos_i;
            x->trap.d = tgt - x->pos_i;
            k++;
        }
    }
    /* Whole ticks, all axes of the arm synchronised. */
    dur = ceil(dur / s->period) * s->period;
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        if (x->arm == arm) {
            if (c4gsim_trap_plan(&x->trap, x->trap.p0, x->trap.p0 + x->trap.d, dur) != C4G_OK) {
                model_fault(s, x, "trajectory");
            }
        }
    }
    s->arm[arm].moving = 1;
    s->arm[arm].move_t = 0.0;
}

static void request_mode(sim_t *s, const scn_cmd_t *c)
{
    const int arm = c->arm - 1;
    int l;
    for (l = 0; l < (int)C4G_AXES_PER_ARM; l++) {
        sim_ax_t *x;
        if (c->axes_mask != 0U && !((c->axes_mask >> l) & 1U)) {
            continue;
        }
        x = find_axis(s, arm, l);
        if (x == NULL) {
            if (c->axes_mask != 0U) {
                sim_raise(s, C4G_CERR_CONFIGURATION_AX, c->arm, l + 1);
            }
            continue;
        }
        x->req_mode = c->iv;
    }
    if (arm_axes(s, arm) == 0) {
        sim_raise(s, C4G_CERR_CONFIGURATION_AX, c->arm, 1);
    }
}

static void expect_fail(sim_t *s, const scn_cmd_t *c, const char *fmt, double got, double want)
{
    char why[120];
    snprintf(why, sizeof why, fmt, got, want);
    s->expect_failed++;
    if (s->expect_first[0] == '\0') { /* the summary names it, with or without -v */
        snprintf(s->expect_first, sizeof s->expect_first, "line %d: %s failed: %s", c->line,
                 scn_op_name(c->op), why);
    }
    if (s->log != NULL) {
        fprintf(s->log, "c4g-sim: scenario line %d: %s failed: %s\n", c->line, scn_op_name(c->op),
                why);
    }
}

/* ---- one function per scenario command: 1 if it blocks (the interpreter stays on it) */

static int cmd_drive_on(sim_t *s, const scn_cmd_t *c, int first)
{
    const int arm = c->arm - 1;
    int a;
    for (a = 0; first && a < s->cfg.n_arms; a++) {
        if ((c->arm == 0 || a == arm) && s->arm[a].drive == DRV_OFF) {
            int i;
            s->arm[a].drive = DRV_DRIVING_ON;
            s->arm[a].drive_ticks = (long)ceil(s->cfg.drive_on_ms / (1000.0 * s->period));
            for (i = 0; i < s->n_axes; i++) {
                if (s->ax[i].arm == a) {
                    s->ax[i].m.drive_on = 1;
                    s->ax[i].hold = s->ax[i].m.meas_pos;
                    s->ax[i].pos_i = s->ax[i].hold;
                    s->ax[i].m.integ = 0.0;
                }
            }
        }
    }
    /* waits until every arm it drives on is on */
    for (a = 0; a < s->cfg.n_arms; a++) {
        if ((c->arm == 0 || a == arm) && s->arm[a].drive != DRV_ON) {
            return 1;
        }
    }
    return 0;
}

static int cmd_drive_off(sim_t *s, const scn_cmd_t *c, int first)
{
    int a;
    (void)first;
    for (a = 0; a < (int)C4G_ARMS; a++) {
        if (c->arm == 0 || a == c->arm - 1) {
            arm_drive_off(s, a);
        }
    }
    return 0;
}

static int cmd_move(sim_t *s, const scn_cmd_t *c, int first)
{
    const int arm = c->arm - 1;
    if (first) {
        if (s->arm[arm].drive != DRV_ON) {
            logf_(s, "scenario line %d: MOVE with the drives of arm %d off: aborted", c->line, c->arm);
            s->scn_aborted = 1;
            return 1;
        }
        start_move(s, c);
    }
    return c->nowait ? 0 : s->arm[arm].moving;
}

static int cmd_wait_move(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)first;
    return s->arm[c->arm - 1].moving;
}

static unsigned long ms_ticks(const sim_t *s, double ms)
{
    return (unsigned long)ceil(ms / (1000.0 * s->period));
}

static int cmd_delay(sim_t *s, const scn_cmd_t *c, int first)
{
    if (first) {
        s->wait_until = s->tick + ms_ticks(s, c->ms);
    }
    return s->tick < s->wait_until;
}

static int cmd_mode(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)first;
    request_mode(s, c);
    return 0;
}

static int cmd_cmd(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)first;
    s->arm[c->arm - 1].cmd = c->iv;
    return 0;
}

static int cmd_wait_pc(sim_t *s, const scn_cmd_t *c, int first)
{
    const int arm = c->arm - 1;
    if (first) {
        s->wait_pc_deadline = (c->ms > 0.0) ? s->tick + ms_ticks(s, c->ms) : 0UL;
    }
    if (s->arm[arm].exit_seen && !arm_in_transition(s, arm)) {
        s->arm[arm].exit_seen = 0;
        return 0;
    }
    if (s->wait_pc_deadline != 0UL && s->tick >= s->wait_pc_deadline) {
        logf_(s, "scenario line %d: WAIT PC timed out after %.0f ms", c->line, c->ms);
        s->scn_timeout = 1;
        s->scn_aborted = 1;
    }
    return 1;
}

static int cmd_freeze(sim_t *s, const scn_cmd_t *c, int first)
{
    if (first) {
        s->special_out = C4G_MODE_FREEZING_P_IN;
        s->freeze_ticks = (long)ceil(c->ms / (1000.0 * s->period));
        if (s->freeze_ticks < 1) {
            s->freeze_ticks = 1;
        }
        return 1;
    }
    return s->freeze_ticks > 0;
}

static int cmd_restart(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)c;
    if (first) {
        s->special_out = C4G_MODE_SVR_RESTART;
        s->restart_req = 1;
        return 1;
    }
    return s->restart_req != 0;
}

static int cmd_exit_open(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)c;
    if (first) {
        s->special_out = C4G_MODE_EXIT_OPEN;
    }
    s->exit_open_req = 1;
    return 1;
}

static int cmd_override(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)first;
    s->override = c->ms / 100.0;
    return 0;
}

/* The state selector changed with a mode other than 0 set: back to mode 0 and
 * ERR_C4GOPEN_SET_0_MODALITY for each arm concerned. */
static int cmd_selector(sim_t *s, const scn_cmd_t *c, int first)
{
    int forced[C4G_ARMS] = {0, 0, 0, 0};
    int i;
    (void)first;
    if (c->iv == s->selector_prog) {
        return 0;
    }
    s->selector_prog = c->iv;
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        if (x->set_mode != C4G_MODE_0) {
            x->set_mode = C4G_MODE_0;
            x->pos_i = x->m.meas_pos;
            x->ref.offset = 0.0;
            x->counter = 0;
            forced[x->arm] = 1;
        }
    }
    for (i = 0; i < (int)C4G_ARMS; i++) {
        if (forced[i]) {
            sim_raise(s, C4G_CERR_SET_0_MODALITY, i + 1, 0);
        }
    }
    return 0;
}

static int cmd_expect_axis(sim_t *s, const scn_cmd_t *c, int first)
{
    const sim_ax_t *x = find_axis(s, c->arm - 1, c->iv - 1);
    (void)first;
    if (x == NULL) {
        expect_fail(s, c, "axis not open (%g, %g)", 0.0, 0.0);
    } else if (c->op == SCN_EXPECT_POS) {
        if (fabs(x->m.meas_pos - c->v[0]) > c->v[1]) {
            expect_fail(s, c, "position %.6f, expected %.6f", x->m.meas_pos, c->v[0]);
        } else {
            s->expect_passed++;
        }
    } else if (x->mode != (int)c->v[0]) {
        expect_fail(s, c, "mode %g, expected %g", (double)x->mode, c->v[0]);
    } else {
        s->expect_passed++;
    }
    return 0;
}

static int cmd_expect_error(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)first;
    if ((strcmp(c->name, "NONE") == 0) ? (s->n_err != 0) : !sim_has_error(s, c->name)) {
        expect_fail(s, c, "errors raised: %g (%g)", (double)s->n_err, 0.0);
    } else {
        s->expect_passed++;
    }
    return 0;
}

static int cmd_end(sim_t *s, const scn_cmd_t *c, int first)
{
    (void)c;
    (void)first;
    s->scn_done = 1;
    return 1;
}

typedef int (*cmd_fn)(sim_t *s, const scn_cmd_t *c, int first);

/* Indexed by scn_op_t (1 = SCN_DRIVE_ON .. SCN_END). */
static const cmd_fn cmd_fns[] = {
    NULL, cmd_drive_on, cmd_drive_off, cmd_move, cmd_move, cmd_wait_move, cmd_delay,
    cmd_mode, cmd_cmd, cmd_wait_pc, cmd_freeze, cmd_restart, cmd_exit_open,
    cmd_override, cmd_selector, cmd_expect_axis, cmd_expect_axis, cmd_expect_error, cmd_end};

/* Execute one command; returns 1 if it blocks (the interpreter stays on it). */
static int run_cmd(sim_t *s, const scn_cmd_t *c, int first)
{
    const int op = (int)c->op;
    typedef char one_fn_per_op[(sizeof cmd_fns / sizeof cmd_fns[0] == (size_t)SCN_END + 1U) ? 1 : -1];
    (void)sizeof(one_fn_per_op);
    if (op < 1 || op >= (int)(sizeof cmd_fns / sizeof cmd_fns[0])) {
        return 0;
    }
    return cmd_fns[op](s, c, first);
}

static void run_scenario(sim_t *s)
{
    int guard = 0;
    if (s->scn == NULL || s->scn_done || s->scn_aborted) {
        return;
    }
    while (s->pc < s->scn->n && guard++ < SCN_MAX_CMDS) {
        const int first = !s->waiting;
        const scn_cmd_t *c = &s->scn->cmd[s->pc];
        if (c->op != SCN_DRIVE_ON && c->op != SCN_DRIVE_OFF && c->op != SCN_DELAY &&
            c->op != SCN_RESTART && c->op != SCN_FREEZE && c->op != SCN_EXIT_OPEN &&
            c->op != SCN_OVERRIDE && c->op != SCN_SELECTOR && c->op != SCN_END &&
            c->op != SCN_EXPECT_ERROR && c->arm > s->cfg.n_arms) {
            logf_(s, "scenario line %d: arm %d is not configured: aborted", c->line, c->arm);
            s->scn_aborted = 1;
            return;
        }
        if (run_cmd(s, c, first)) {
            s->waiting = 1;
            return;
        }
        s->waiting = 0;
        s->pc++;
    }
    if (s->pc >= s->scn->n) {
        s->scn_done = 1;
    }
}

/* ---- modes --------------------------------------------------------------- */

static int is_pc_current_mode(int m)
{
    return m == C4G_MODE_1 || m == C4G_MODE_1_STANDBY || m == C4G_MODE_2 || m == C4G_MODE_2_STANDBY;
}

static void enter_mode(sim_t *s, sim_ax_t *x, int m)
{
    if (!c4g_mode_is_known(m) || m == C4G_MODE_3 || m == C4G_MODE_6 || (m >= 101 && m <= 202) ||
        m == C4G_MODE_DRIVING_ON || m == C4G_MODE_EXIT_OPEN || m == C4G_MODE_SVR_RESTART ||
        m == C4G_MODE_FREEZING_P_IN || m == C4G_MODE_FREEZING_P_OUT) {
        logf_(s, "mode %d requested on arm %d axis %d: not available, ignored", m, x->arm + 1,
              x->logical + 1);
        s->mode_rejected++;
        return;
    }
    if (s->arm[x->arm].drive == DRV_DRIVING_ON) {
        /* Chapter 15.2: no mode change while driving on. */
        s->mode_rejected++;
        return;
    }
    if (m == C4G_MODE_5 && x->set_mode != C4G_MODE_5) {
        x->ref.pos_k = x->pos_i;
    }
    if ((m == C4G_MODE_7 || m == C4G_MODE_8) && x->set_mode != m) {
        x->ref.offset = 0.0;
    }
    if ((m == C4G_MODE_1 || m == C4G_MODE_2) && !is_pc_current_mode(x->set_mode)) {
        x->counter = 0;
    }
    if (m == C4G_MODE_4_STANDBY || m == C4G_MODE_5_STANDBY || m == C4G_MODE_7_STANDBY_EXIT) {
        x->standby_ticks = 1;
    }
    x->set_mode = m;
}

/* EXIT_FROM_OPEN from the PC for one axis (chapter 24.2). */
static void exit_from_open(sim_t *s, sim_ax_t *x)
{
    switch (x->set_mode) {
    case C4G_MODE_1:
        x->set_mode = C4G_MODE_1_STANDBY;
        break;
    case C4G_MODE_2:
        x->set_mode = C4G_MODE_2_STANDBY;
        break;
    case C4G_MODE_4:
        x->pos_i = x->pos_ref;
        x->vel_i = 0.0;
        x->set_mode = C4G_MODE_4_STANDBY;
        x->standby_ticks = 1;
        break;
    case C4G_MODE_5:
        x->pos_i = x->ref.pos_k; /* pos_i updated to the accumulated pos_k */
        x->set_mode = C4G_MODE_5_STANDBY;
        x->standby_ticks = 1;
        break;
    case C4G_MODE_7:
        x->pos_i += x->ref.offset;
        x->trap.p0 += x->ref.offset;
        x->ref.offset = 0.0;
        if (s->arm[x->arm].moving) {
            x->set_mode = C4G_MODE_7_STANDBY;
        } else {
            x->set_mode = C4G_MODE_7_STANDBY_EXIT;
            x->standby_ticks = 1;
        }
        break;
    case C4G_MODE_8:
        /* the integrated velocity additions stay where they took the axis */
        x->pos_i += x->ref.offset;
        x->trap.p0 += x->ref.offset;
        x->ref.offset = 0.0;
        x->set_mode = C4G_MODE_0;
        break;
    case C4G_MODE_9:
    case C4G_MODE_FREEZING_A:
        x->set_mode = C4G_MODE_0;
        break;
    default:
        break;
    }
}

static void apply_reply(sim_t *s, const c4g_pc_packet_t *r)
{
    int i;
    int a;
    int exit_arm[C4G_ARMS] = {0, 0, 0, 0};
    for (a = 0; a < (int)C4G_ARMS; a++) {
        exit_arm[a] = c4g_arm_byte(r->infpar, (uint32_t)a) == C4G_EXIT_FROM_OPEN;
        if (exit_arm[a] && a < s->cfg.n_arms) {
            s->arm[a].exit_seen = 1;
            s->arm[a].frozen_a = 0;
        }
    }
    for (i = 0; i < s->n_axes && i < (int)r->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        const int m = r->ax[i].mode;
        x->rx = r->ax[i];
        x->fresh = 1;
        if (m == C4G_MODE_DRIVE_OFF || m == C4G_MODE_FOLLOW_ERROR) {
            if (s->arm[x->arm].drive != DRV_OFF) {
                if (m == C4G_MODE_DRIVE_OFF) {
                    sim_raise(s, C4G_CERR_DRIVEOFF_SERVER, 0, 0);
                } else {
                    sim_raise(s, C4G_CERR_FOLLOW_ERROR, x->arm + 1, x->logical + 1);
                }
                arm_drive_off(s, x->arm);
                s->scn_aborted = 1;
            }
        } else if (m == C4G_MODE_FREEZING_A) {
            if (!s->arm[x->arm].frozen_a && x->set_mode == C4G_MODE_0) {
                logf_(s, "active freezing (500) on arm %d", x->arm + 1);
            }
            if (x->set_mode == C4G_MODE_0 || x->set_mode == C4G_MODE_FREEZING_A) {
                s->arm[x->arm].frozen_a = 1;
                x->set_mode = C4G_MODE_FREEZING_A;
            }
        } else if (m == C4G_MODE_2_STANDBY && x->set_mode == C4G_MODE_2) {
            x->set_mode = C4G_MODE_2_STANDBY; /* the PC ends mode 2 (chapter 24.2.4) */
            s->arm[x->arm].exit_seen = 1;
        } else if (m != x->mode) {
            s->mode_mismatch++;
        }
    }
    for (i = 0; i < s->n_axes; i++) {
        if (exit_arm[s->ax[i].arm]) {
            exit_from_open(s, &s->ax[i]);
        }
    }
}

/* DSA inputs for one axis in the mode of the packet the reply answered. A missing reply, or
 * one of another mode, adds nothing: the reference holds (modes 1 and 2, where the PC closes
 * the loops, keep the last current of their own mode). */
static void dsa_inputs(sim_t *s, sim_ax_t *x, c4gsim_dsa_in_t *in)
{
    const double T = s->period;
    const c4g_pc_axis_t *r = &x->rx;
    const int same_mode = (r->mode == x->mode);
    const c4g_pc_axis_t *pc = (same_mode && (x->fresh || is_pc_current_mode(x->mode))) ? r : NULL;
    memset(in, 0, sizeof *in);
    in->pos_ref = x->pos_i;
    in->vel_ff = x->vel_i;
    if (s->arm[x->arm].drive == DRV_DRIVING_ON) {
        in->pos_ref = x->hold;
        in->vel_ff = 0.0;
        x->ref.pos_ref = x->hold;
        return;
    }
    if (x->mode == C4G_MODE_0_DEBUG) {
        in->pos_ref = (pc != NULL) ? r->target_pos : x->pos_i;
        in->vel_ff = (pc != NULL) ? r->target_vel / T : x->vel_i;
        x->ref.pos_ref = in->pos_ref;
    } else if (x->mode == C4G_MODE_4_STANDBY) {
        in->pos_ref = x->pos_i;
        in->vel_ff = 0.0;
        x->ref.pos_ref = in->pos_ref;
    } else {
        if (c4gsim_ref_step(&x->ref, x->mode, pc, x->pos_i, x->vel_i, s->override, T, in) != C4G_OK) {
            model_fault(s, x, "reference");
        }
    }
    if (is_pc_current_mode(x->mode)) {
        in->pc_share = (s->cfg.switch_ms > 0.0)
                           ? (double)x->counter / ceil(s->cfg.switch_ms / (1000.0 * T)) : 1.0;
    }
}

static void advance_trajectory(sim_t *s)
{
    int a;
    int i;
    for (a = 0; a < (int)C4G_ARMS; a++) {
        if (s->arm[a].moving) {
            s->arm[a].move_t += s->period;
        }
    }
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        if (s->arm[x->arm].moving) {
            if (c4gsim_trap_eval(&x->trap, s->arm[x->arm].move_t, &x->pos_i, &x->vel_i) != C4G_OK) {
                model_fault(s, x, "trajectory");
            }
        } else {
            x->vel_i = 0.0;
        }
    }
    for (a = 0; a < (int)C4G_ARMS; a++) {
        if (s->arm[a].moving) {
            int done = 1;
            for (i = 0; i < s->n_axes; i++) {
                if (s->ax[i].arm == a && s->arm[a].move_t < s->ax[i].trap.t_total) {
                    done = 0;
                }
            }
            if (done) {
                s->arm[a].moving = 0;
            }
        }
    }
}

/* Mode bookkeeping after the period: switching counters, stand-by exits, requests. */
static void update_modes(sim_t *s)
{
    int i;
    const long nsw = (long)ceil(s->cfg.switch_ms / (1000.0 * s->period));
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        switch (x->set_mode) {
        case C4G_MODE_1:
        case C4G_MODE_2:
            if (x->counter < nsw) {
                x->counter++;
            }
            break;
        case C4G_MODE_1_STANDBY:
        case C4G_MODE_2_STANDBY:
            if (x->counter > 0) {
                x->counter--;
            }
            if (x->counter <= 0) {
                if (x->set_mode == C4G_MODE_1_STANDBY) {
                    x->pos_i = x->m.meas_pos; /* SMP+ takes over where the robot is */
                }
                x->set_mode = C4G_MODE_0;
            }
            break;
        case C4G_MODE_4_STANDBY:
        case C4G_MODE_5_STANDBY:
        case C4G_MODE_7_STANDBY_EXIT:
            if (--x->standby_ticks < 0) {
                x->set_mode = C4G_MODE_0;
            }
            break;
        case C4G_MODE_7_STANDBY:
            if (!s->arm[x->arm].moving) {
                x->set_mode = C4G_MODE_7_STANDBY_EXIT;
                x->standby_ticks = 0;
            }
            break;
        default:
            break;
        }
        if (x->req_mode >= 0) {
            const int m = x->req_mode;
            x->req_mode = -1;
            enter_mode(s, x, m);
        }
    }
}

static void check_following(sim_t *s)
{
    int i;
    if (!s->cfg.check_follow) {
        return;
    }
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        const double fe = x->p->follow_error;
        if (fe <= 0.0 || !x->m.drive_on || x->mode == C4G_MODE_1 || x->mode == C4G_MODE_1_STANDBY) {
            continue;
        }
        if (fabs(x->pos_ref - x->m.meas_pos) > fe) {
            sim_raise(s, C4G_CERR_FOLLOW_ERROR, x->arm + 1, x->logical + 1);
            arm_drive_off(s, x->arm);
            s->scn_aborted = 1;
        }
    }
}

void sim_fill(sim_t *s, c4g_ctrl_packet_t *out)
{
    int i;
    int a;
    memset(out, 0, sizeof *out);
    out->n_axes = (uint32_t)s->n_axes;
    for (a = 0; a < s->cfg.n_arms; a++) {
        if (s->arm[a].drive == DRV_ON) {
            out->infpar = c4g_arm_byte_set(out->infpar, (uint32_t)a, C4G_STS_MOVING);
        }
        out->cmd = c4g_arm_byte_set(out->cmd, (uint32_t)a, (uint8_t)s->arm[a].cmd);
    }
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        c4g_ctrl_axis_t *o = &out->ax[i];
        x->mode = (s->arm[x->arm].drive == DRV_DRIVING_ON) ? C4G_MODE_DRIVING_ON : x->set_mode;
        o->mode = (s->special_out != 0) ? s->special_out : x->mode;
        /* D1, D2: the SMP+ target; in mode 10 the trajectory the PC must copy back. */
        o->target_pos = (float)((x->mode == C4G_MODE_0_DEBUG) ? x->pos_i : x->pos_ref);
        o->target_vel = (float)(((x->mode == C4G_MODE_0_DEBUG) ? x->vel_i : x->vel_ref) * s->period);
        o->actual_pos = (float)x->m.meas_pos;
        o->actual_vel = (float)x->act_vel_tick;
        o->current_ref = (float)x->m.cur_report;
        if (x->in_plant) {
            /* the controller's own model of the arm (docs/c4g-sim.md) */
            o->ext[0] = (float)x->model_cur;
            o->ext[1] = (float)x->model_inertia;
        } else {
            o->ext[0] = (float)(c4gsim_axis_gravity(x->p, x->m.pos) / x->p->kt); /* dynamic model [A] */
            o->ext[1] = (float)x->p->j;                                     /* diagonal inertia */
        }
        o->ext[2] = 0.0F;
    }
    s->special_out = 0;
}

/* The arm plant's share of the ticks: the controller's model on this tick's references (the
 * acceleration from the change of the velocity reference over the period), fed to the drives
 * (limited to the axis's amax) in the modes where SMP+ drives. In mode 9 the channel carries the PC's D5 instead (manual
 * 14.12.4); in modes 1 and 2 the switching counter fades the model out as it fades the PC's
 * current in (chapter 12). EXT1 reports the model in every mode. */
static void plant_feedforward(sim_t *s, c4gsim_dsa_in_t *in, const double *prev_vel)
{
    double qm[PLANT_AXES];
    double vm[PLANT_AXES];
    double am[PLANT_AXES];
    int k;
    for (k = 0; k < PLANT_AXES; k++) {
        const int i = s->plant_ax[k];
        qm[k] = in[i].pos_ref;
        vm[k] = in[i].vel_ff;
        /* limited to the axis's trajectory acceleration: a reply that did not come holds the
         * reference for a tick, and its velocity step is no acceleration to feed forward */
        am[k] = (in[i].vel_ff - prev_vel[i]) / s->period;
        am[k] = (am[k] > s->ax[i].p->amax) ? s->ax[i].p->amax
                                           : ((am[k] < -s->ax[i].p->amax) ? -s->ax[i].p->amax : am[k]);
    }
    if (plant_model(s, qm, vm, am) != 0) {
        model_fault(s, &s->ax[s->plant_ax[0]], "dynamic model");
        return;
    }
    for (k = 0; k < PLANT_AXES; k++) {
        const int i = s->plant_ax[k];
        const sim_ax_t *x = &s->ax[i];
        double gain = 1.0;
        if (x->mode == C4G_MODE_9) {
            gain = 0.0;
        } else if (is_pc_current_mode(x->mode)) {
            gain = 1.0 - ((in[i].pc_share < 0.0) ? 0.0 : ((in[i].pc_share > 1.0) ? 1.0 : in[i].pc_share));
        }
        in[i].cur_add += gain * x->model_cur;
    }
}

/* One DSA step of the arm plant: the currents c4gsim_dsa_current set move the arm, then each
 * motor's encoder is read. */
static void plant_step(sim_t *s, double dt)
{
    c4gsim_axis_t *ax[PLANT_AXES];
    int k;
    for (k = 0; k < PLANT_AXES; k++) {
        ax[k] = &s->ax[s->plant_ax[k]].m;
    }
    if (plant_arm_step(s->plant, ax, &s->rng) != 0) {
        model_fault(s, &s->ax[s->plant_ax[0]], "arm plant");
    }
    for (k = 0; k < PLANT_AXES; k++) {
        sim_ax_t *x = &s->ax[s->plant_ax[k]];
        if (c4gsim_axis_measure(&x->m, x->p, dt, &s->rng) != C4G_OK) {
            model_fault(s, x, "encoder");
        }
    }
}

void sim_tick(sim_t *s, const c4g_pc_packet_t *reply, c4g_ctrl_packet_t *out)
{
    int i;
    int a;
    int k;
    const int sub = SUBSTEPS_PER_MS * s->cfg.period_ms;
    const double dt = s->period / (double)sub;
    c4gsim_dsa_in_t in[C4G_MAX_AXES];
    double prev_ref[C4G_MAX_AXES];
    double prev_vel[C4G_MAX_AXES];

    s->tick++;
    for (i = 0; i < s->n_axes; i++) {
        s->ax[i].fresh = 0;
    }
    if (reply != NULL) {
        apply_reply(s, reply);
    }
    run_scenario(s);
    /* Drive-on phase (501) countdown. */
    for (a = 0; a < (int)C4G_ARMS; a++) {
        if (s->arm[a].drive == DRV_DRIVING_ON && --s->arm[a].drive_ticks <= 0) {
            s->arm[a].drive = DRV_ON;
            logf_(s, "arm %d drives on", a + 1);
        }
    }
    advance_trajectory(s);
    for (i = 0; i < s->n_axes; i++) {
        dsa_inputs(s, &s->ax[i], &in[i]);
        prev_ref[i] = s->ax[i].pos_ref;
        prev_vel[i] = s->ax[i].vel_ref;
        s->ax[i].pos_ref = in[i].pos_ref;
        s->ax[i].vel_ref = in[i].vel_ff;
    }
    if (s->plant != NULL) {
        plant_feedforward(s, in, prev_vel);
    }
    /* The DSA interpolates the SMP+ references over its steps, as a real drive does: a
     * reference held for the whole period would put a ripple at the SMP+ rate into the
     * current (c4gsim_dsa_interp). Step k regulates at the period's instant
     * k/sub, where its encoder reading was taken: a perfect feedforward leaves no following
     * error. */
    for (k = 0; k < sub; k++) {
        const double w = (double)k / (double)sub;
        for (i = 0; i < s->n_axes; i++) {
            c4gsim_dsa_in_t step = in[i];
            if (c4gsim_dsa_interp(prev_ref[i], prev_vel[i], in[i].pos_ref, in[i].vel_ff, w, s->period,
                                  &step.pos_ref, &step.vel_ff) != C4G_OK ||
                (s->ax[i].in_plant ? c4gsim_dsa_current(&s->ax[i].m, s->ax[i].p, &step, dt)
                                   : c4gsim_axis_step(&s->ax[i].m, s->ax[i].p, &step, dt, &s->rng)) != C4G_OK) {
                model_fault(s, &s->ax[i], "DSA step");
            }
        }
        if (s->plant != NULL) {
            plant_step(s, dt);
        }
    }
    for (i = 0; i < s->n_axes; i++) {
        sim_ax_t *x = &s->ax[i];
        double cur;
        if (c4gsim_axis_report_current(&x->m, x->p, &s->rng, &cur) != C4G_OK) {
            model_fault(s, x, "current");
        }
        x->act_vel_tick = x->m.meas_pos - x->prev_tick_meas;
        x->prev_tick_meas = x->m.meas_pos;
        if (x->set_mode == C4G_MODE_0 || x->set_mode == C4G_MODE_FREEZING_A) {
            /* nothing: pos_i is the SMP+ trajectory */
        }
    }
    check_following(s);
    update_modes(s);
    sim_fill(s, out);
}
