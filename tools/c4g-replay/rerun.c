/* SPDX-License-Identifier: MIT */
#include "replay.h"

int rp_cmd_rerun(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, RP_TOOL ": rerun: not built yet\n");
    return CLI_EXIT_USAGE;
}
