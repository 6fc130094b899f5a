/* SPDX-License-Identifier: MIT */
/* Real-time settings: memory locking, SCHED_FIFO, CPU affinity, stack prefault.
 * sched_setaffinity/CPU_SET need _GNU_SOURCE (only this file defines it). */
#define _GNU_SOURCE 1
#include "srv.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <string.h>
#include <sys/mman.h>

static void prefault_stack(void)
{
    volatile unsigned char buf[256 * 1024];
    size_t i;
    for (i = 0U; i < sizeof buf; i += 4096U) {
        buf[i] = 0U;
    }
}

static const char *hint(int e)
{
    return (e == EPERM || e == EACCES)
               ? " (needs root, CAP_SYS_NICE/CAP_IPC_LOCK, or rtprio/memlock limits in "
                 "/etc/security/limits.conf; see docs/rt-integration.md)"
               : "";
}

/* Returns 0, or -1 when a setting was refused and rt_strict is set. Messages go to msg
 * (start-up only: this runs before the real-time loop). */
int srv_rt_setup(const srv_config_t *cfg, FILE *msg)
{
    int fail = 0;
    if (cfg->mlock) {
        if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
            const int e = errno;
            fprintf(msg, "c4g-server: %s: mlockall(MCL_CURRENT|MCL_FUTURE) refused: %s%s\n",
                    cfg->rt_strict ? "error" : "warning", strerror(e), hint(e));
            fail = 1;
        } else if (cfg->verbose) {
            fprintf(msg, "c4g-server: memory locked\n");
        }
        prefault_stack();
    }
    if (cfg->cpu >= 0) {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(cfg->cpu, &set);
        if (sched_setaffinity(0, sizeof set, &set) != 0) {
            const int e = errno;
            fprintf(msg, "c4g-server: %s: CPU affinity to CPU %d refused: %s%s\n",
                    cfg->rt_strict ? "error" : "warning", cfg->cpu, strerror(e),
                    e == EINVAL ? " (no such CPU or not allowed by the cpuset)" : hint(e));
            fail = 1;
        } else if (cfg->verbose) {
            fprintf(msg, "c4g-server: pinned to CPU %d\n", cfg->cpu);
        }
    }
    if (cfg->prio > 0) {
        struct sched_param sp;
        int e;
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = cfg->prio;
        e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
        if (e != 0) {
            fprintf(msg, "c4g-server: %s: SCHED_FIFO priority %d refused: %s%s\n",
                    cfg->rt_strict ? "error" : "warning", cfg->prio, strerror(e), hint(e));
            fail = 1;
        } else if (cfg->verbose) {
            fprintf(msg, "c4g-server: SCHED_FIFO priority %d\n", cfg->prio);
        }
    }
    if (fail && !cfg->rt_strict) {
        fprintf(msg, "c4g-server: continuing without the refused real-time setting(s)\n");
    }
    return (fail && cfg->rt_strict) ? -1 : 0;
}
