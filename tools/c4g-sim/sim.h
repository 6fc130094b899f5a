/* SPDX-License-Identifier: MIT */
/* c4g-sim: the controller (SMP+ + DSA + PDL2 program) without I/O. main.c owns the
 * socket, the clock, fault injection and the output files. */
#ifndef SIM_SIM_H
#define SIM_SIM_H

#include <stdint.h>
#include <stdio.h>

#include "c4gopen.h"
#include "c4gsim_model.h"
#include "plant_arm.h"
#include "scenario.h"

#define SIM_MAX_ERRORS 64
#define SIM_DSA_HZ 2000.0

/** Everything configurable (command line and INI file). */
typedef struct sim_config {
    char server[64];
    unsigned port;
    char bind_addr[64];
    unsigned local_port;
    int period_ms;              /* 1 or 2 */
    unsigned t_cycle1_us;       /* reply budget counted as "late" */
    c4g_num_policy_t policy;
    unsigned max_miss;          /* consecutive missing/wrong replies -> ERR_C4GOPEN_UDP */
    uint64_t seed;
    unsigned long ticks;        /* cyclic ticks to run at most, 0 = no limit */
    int hold;                   /* keep running after the scenario ends */
    unsigned sync_before;       /* 9 */
    unsigned sync_after;        /* 2 */
    double drive_on_ms;         /* duration of the 501 phase */
    double switch_ms;           /* control switching counter (modes 1, 2), chapter 24 */
    int check_follow;           /* controller following-error check on/off */
    int n_arms;
    unsigned open_mask[C4G_ARMS];   /* bit l: logical axis l open */
    int option_ok[C4G_ARMS];        /* C4G Open software option present */
    int version[3];
    c4gsim_axis_params_t ax[C4G_ARMS][C4G_AXES_PER_ARM];
    plant_cfg_t plant;          /* plant.path "": every axis the decoupled model */
} sim_config_t;

void sim_config_default(sim_config_t *c);
/** "KG" or "KG@X,Y,Z" (--payload, INI payload): 0, or -1 with the reason in @p why. */
int sim_parse_payload(const char *v, double *mass, double com[3], char *why, size_t wl);
/** Total open axes; -1 if more than 20 or an arm has none. */
int sim_config_axes(const sim_config_t *c);
/** Load an INI file over @p c (at most 1 MiB). Returns 0, or -1 with
 *  "FILE:LINE:COL: ..." in err. */
int sim_config_load(sim_config_t *c, const char *path, char *err, size_t errlen);
struct c4gh_tf_file;
/** The same over a file already in memory (lib/host/c4gh_textfile.h). */
int sim_config_parse(sim_config_t *c, struct c4gh_tf_file *f, char *err, size_t errlen);

typedef struct sim_error {
    c4g_ctrl_error_t code;
    unsigned long tick;
    char text[128];
} sim_error_t;

typedef enum drive_state { DRV_OFF = 0, DRV_DRIVING_ON, DRV_ON } drive_state_t;

typedef struct sim_arm {
    drive_state_t drive;
    long drive_ticks;           /* ticks left in the 501 phase */
    int cmd;                    /* C4GOPEN_CMD[1] byte */
    int moving;                 /* trajectory active */
    double move_t;              /* time into the move [s] */
    int exit_seen;              /* EXIT_FROM_OPEN received (WAIT PC) */
    int frozen_a;               /* active freezing (500) */
} sim_arm_t;

typedef struct sim_ax {
    int arm;                    /* 0..3 */
    int logical;                /* 0..9 */
    const c4gsim_axis_params_t *p;
    c4gsim_axis_t m;               /* model + DSA */
    int mode;                   /* mode of the last packet sent */
    int set_mode;               /* mode set by PDL2/PC (shown unless driving on) */
    int req_mode;               /* pending request from the scenario, -1 none */
    int standby_ticks;          /* one-tick exit modes (14, 15, 170) */
    long counter;               /* control switching counter (modes 1, 2) */
    double pos_i, vel_i;        /* SMP+ trajectory [turns, turns/s] */
    c4gsim_ref_t ref;              /* mode 5 integrator, modes 7/8 offset, last reference */
    double pos_ref, vel_ref;    /* what went to the DSA */
    double hold;                /* hold position while driving on */
    double prev_tick_meas;
    double act_vel_tick;        /* measured delta turns in the last tick */
    c4gsim_trap_t trap;
    c4g_pc_axis_t rx;           /* last PC data applied */
    int fresh;                  /* rx came with this tick's reply */
    int in_plant;               /* moved by the arm plant (sim_t.plant), not by the decoupled model */
    double model_cur;           /* arm plant: the controller's dynamic-model current [A] (EXT1) */
    double model_inertia;       /* arm plant: its diagonal inertia [kg m^2] (EXT2) */
} sim_ax_t;

/** Communication phase as the controller sees it. */
typedef enum sim_phase {
    PH_SYNC_PRE = 0, PH_INIT, PH_SYNC_POST, PH_CYCLIC, PH_ENDED
} sim_phase_t;

typedef struct sim {
    sim_config_t cfg;
    c4g_init_t init;
    c4g_axis_map_t map;
    int n_axes;
    sim_ax_t ax[C4G_MAX_AXES];
    sim_arm_t arm[C4G_ARMS];
    c4gsim_rng_t rng;
    double period;              /* s */
    double override;            /* 0..1 */
    int selector_prog;
    unsigned long tick;         /* cyclic ticks simulated */
    /* scenario */
    const scn_t *scn;
    int pc;                     /* next command */
    int scn_done;
    int scn_aborted;
    unsigned long wait_until;   /* DELAY end tick */
    int waiting;                /* current command blocks */
    unsigned long wait_pc_deadline;
    int expect_failed, expect_passed;
    char expect_first[200];     /* the first failed EXPECT: "line N: EXPECT ...: why" */
    int scn_timeout;
    /* requests for main.c */
    long freeze_ticks;          /* >0: passive freezing requested (ticks of silence) */
    int restart_req;
    int exit_open_req;
    int special_out;            /* one-shot special mode for all axes in the next packet */
    /* errors */
    sim_error_t err[SIM_MAX_ERRORS];
    int n_err;
    int fatal;                  /* stop communicating */
    unsigned long udp_debug;    /* missing replies (ERR_C4GOPEN_UDP_DEBUG, not fatal) */
    unsigned long mode_rejected;
    unsigned long mode_mismatch;
    FILE *log;                  /* event log (stderr), NULL = quiet */
    plant_arm_t *plant;         /* the arm plant of arm 1's axes 1..6, or NULL */
    int plant_ax[PLANT_AXES];   /* their indexes in ax[] */
    char init_err[400];         /* why sim_init failed, when an error code cannot say it */
} sim_t;

/** Build the controller from the configuration. Returns 0, or -1 (error raised). */
int sim_init(sim_t *s, const sim_config_t *cfg, const scn_t *scn, FILE *log);
/** Release what sim_init allocated (the arm plant); safe to call twice. */
void sim_free(sim_t *s);
/** Raise a table 17.1 error (formatted message). */
void sim_raise(sim_t *s, c4g_ctrl_error_t code, int a1, int a2);
int sim_has_error(const sim_t *s, const char *name);
/**
 * One cyclic tick: apply the PC reply to the previous packet (NULL = none), run the
 * scenario, the trajectory and the DSA/plant for one period, check following errors,
 * then fill the next packet.
 */
void sim_tick(sim_t *s, const c4g_pc_packet_t *reply, c4g_ctrl_packet_t *out);
/** Fill a packet with the current state without advancing time (freeze in/out, 504, 506). */
void sim_fill(sim_t *s, c4g_ctrl_packet_t *out);
/** Drive every arm off (safety state). */
void sim_all_drive_off(sim_t *s);
/** 1 while an arm is in active freezing (replies are not checked). */
int sim_checks_suspended(const sim_t *s);

#endif
