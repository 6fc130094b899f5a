/* SPDX-License-Identifier: MIT */
#include "replay.h"

int rp_cmd_plot(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, RP_TOOL ": plot: not built yet\n");
    return CLI_EXIT_USAGE;
}
