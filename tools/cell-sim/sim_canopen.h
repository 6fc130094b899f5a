/* SPDX-License-Identifier: MIT */
/* cell-sim: the orientation platform on a CANopen bus (docs/canopen.md). The platform's
 * axes A and B are DS402 drives (the first two nodes of the channel's configuration) in
 * cyclic synchronous position mode, driven by libc4gopen's CANopen master; the nodes are
 * simulated (c4gsim_slave) on the in-process virtual bus or on a SocketCAN interface.
 * A text shell on its own TCP port answers the Robox diagnostic commands (CO_RNMT, ...)
 * and injects faults (SIM_UNPLUG, ...). */
#ifndef SIM_CANOPEN_H
#define SIM_CANOPEN_H

#include <stdint.h>
#include "c4gsim_vbus.h"
#include "c4gh_coconfig.h"
#include "c4gh_can.h"
#include "sim_device.h"

#define SIM_CO_COUNTS_PER_RAD 1000000.0 /* drive position unit: 1 urad */
#define SIM_CO_SHELLS 8                 /* shell connections served at once */
#define SIM_CO_SHELL_OUT 4096           /* replies waiting for a client that does not read */
#define SIM_CO_SDO_QUEUE_NS 3000000000ULL /* a user SDO waits this long for the SDO client */

/* One shell connection. A command that needs an SDO (CO_ROBJ, CO_WOBJ, CO_SDO) is answered
 * when the transfer ends, while the event loop goes on; the client's next lines wait. */
typedef struct sim_co_shell {
    int fd;                 /* -1: free */
    char in[512];
    size_t in_len;
    char out[SIM_CO_SHELL_OUT];
    size_t out_len;
    int sdo;                /* 0 none, 1 waiting for the SDO client, 2 its transfer runs */
    uint64_t sdo_since_ns;  /* when the command came */
    uint8_t node, upload, sub, size;
    uint16_t index;
    uint32_t value;
} sim_co_shell_t;

/* SRVON / SRVOF waiting for both drives to reach their DS402 state, while the event loop
 * goes on (at most SIM_CO_SERVO_NS; the bus runs at each sim_co_step). */
#define SIM_CO_SERVO_NS 300000000ULL
typedef struct sim_co_servo {
    int active;
    c4g_cell_instr_t in;
    c4g_co_ds402_t want;
    uint64_t deadline_ns;
} sim_co_servo_t;

typedef struct sim_co {
    c4gh_co_config_t cfg;
    c4g_co_master_t m;
    c4gsim_slave_t slave[C4G_CO_MAX_NODES];
    c4gsim_vbus_t bus;
    c4gh_co_buslog_t log;
    int fd_master, fd_nodes;   /* SocketCAN sockets, -1 on the virtual bus */
    uint64_t t0_ns;            /* bus time 0 */
    uint16_t cw[2];            /* last controlwords sent to the two axes */
    c4g_co_goal_t goal;
    int axis_slot[2];          /* master slots of axes A and B */
    int lost[2];
    int fault_hold[2];         /* a drive fault (EMCY): no fault reset until SRVON */
    int listen_fd;             /* diagnostic shell */
    sim_co_shell_t sh[SIM_CO_SHELLS];
    int sdo_owner;             /* shell connection whose user SDO runs, -1 none */
    int verbose;
    sim_device_t *platform;    /* set by sim_co_step */
    sim_co_servo_t servo;      /* a SRVON / SRVOF whose reply waits for the drives */
} sim_co_t;

/* Loads the configuration, sets up the bus (ifname NULL: virtual), the logs, the shell
 * port (0: none) and boots the network. 0, or -1 with a message. */
int sim_co_open(sim_co_t *s, const char *ini, const char *ifname, const char *candump,
                const char *pcap, const char *shell_bind, unsigned shell_port, char *err,
                size_t errlen);
void sim_co_close(sim_co_t *s);
/* Bus time passes: the platform's ideal positions become the drives' targets; events
 * (lost nodes) latch the platform's error; the shell is served. */
void sim_co_step(sim_co_t *s, uint64_t now_ns, sim_device_t *platform);
/* The platform's instruction on the bus: SRVON/SRVOF through DS402, MOV refused while a
 * drive is lost, STA with the drives' actual positions. A SRVON or SRVOF that must wait for
 * the drives returns NULL with *deferred set: its reply comes from sim_co_servo_poll. Not
 * to be called while sim_co_servo_busy. */
const char *sim_co_exec(sim_co_t *s, sim_device_t *platform, const c4g_cell_instr_t *in,
                        uint64_t now_ns, c4g_cell_reply_t *rep, int *close_after, int *deferred);
/* True while a SRVON / SRVOF waits for the drives. */
int sim_co_servo_busy(const sim_co_t *s);
/* 1 and the reply of the waiting SRVON / SRVOF once the drives are there (or are not, by
 * the deadline); 0 while it still waits or none does. */
int sim_co_servo_poll(sim_co_t *s, sim_device_t *platform, uint64_t now_ns,
                      c4g_cell_reply_t *rep, const char **note, int *close_after);
/* One shell command line (no newline) of connection k: 0 and the reply text in out, or 1
 * when the reply comes later (an SDO: it is queued on that connection when it ends). */
int sim_co_shell(sim_co_t *s, int k, const char *line, uint64_t now_ns, char *out, size_t cap);

#endif /* SIM_CANOPEN_H */
