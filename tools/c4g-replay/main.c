/* SPDX-License-Identifier: MIT */
/* c4g-replay: read, check, export, re-run and replay captured C4G Open sessions. One binary,
 * one command per job: c4g-replay COMMAND [OPTIONS] FILE... */
#include "replay.h"

#include <pcap/pcap.h>
#include <stdlib.h>
#include <string.h>

typedef struct rp_command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *help;
} rp_command_t;

static const rp_command_t commands[] = {
    {"summary", rp_cmd_summary, "what happened in each session, and a one-line verdict"},
    {"check", rp_cmd_check, "the same analysis for CI: one line per finding, exit 0/1/2"},
    {"export", rp_cmd_export, "one CSV row (or JSON line) per cyclic tick, every field both ways"},
    {"rerun", rp_cmd_rerun, "feed the controller's packets through c4g-server's code, diff replies"},
    {"live", rp_cmd_live, "play the controller's side to a running PC server over UDP"},
    {"plot", rp_cmd_plot, "a field over time with mode changes marked (gnuplot)"},
    {"follow", rp_cmd_follow, "following error and DSA current while the target moves, capture by capture"},
};

static void usage(FILE *out)
{
    size_t i;
    fprintf(out,
            "Usage: " RP_TOOL " COMMAND [OPTIONS] FILE...\n"
            "Read captures of C4G Open sessions (pcap or pcapng from tcpdump, Wireshark, c4g-sim or\n"
            "c4g-server --pcap): see what happened, hand the data to other tools, and reproduce a\n"
            "field bug on a desk.\n\nCommands:\n");
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        fprintf(out, "  %-9s %s\n", commands[i].name, commands[i].help);
    }
    fprintf(out,
            "\n  " RP_TOOL " COMMAND --help   options and examples of one command\n"
            "  -h, --help                 this text\n"
            "  -V, --version              version of the tool, libc4gopen and libpcap\n\n"
            "Examples:\n"
            "  " RP_TOOL " summary field.pcapng\n"
            "  " RP_TOOL " check --allow late captures/*.pcap\n"
            "  " RP_TOOL " export --moni 20 field.pcap > moni.csv\n"
            "  " RP_TOOL " rerun field.pcap --behaviour server -- --sine 0.25,0.5,0.5\n"
            "  " RP_TOOL " live field.pcap --target 127.0.0.1:1000\n"
            "  " RP_TOOL " follow move0.pcap move9.pcap\n\n"
            "Exit status: 0 success (check: clean), 1 findings or a failed job, 2 bad usage or an\n"
            "unreadable input, 3 (check) a file without any C4G Open session. See docs/c4g-replay.md\n"
            "and c4g-replay(1).\n");
}

int main(int argc, char **argv)
{
    size_t i;
    if (argc < 2) {
        usage(stderr);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return C4GH_CLI_EXIT_OK;
    }
    if (strcmp(argv[1], "-V") == 0 || strcmp(argv[1], "--version") == 0) {
        printf(RP_TOOL " %s (libc4gopen %s, %s)\n", C4G_VERSION_STRING, C4G_VERSION_STRING,
               pcap_lib_version());
        return C4GH_CLI_EXIT_OK;
    }
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(argv[1], commands[i].name) == 0) {
            return commands[i].run(argc - 1, argv + 1);
        }
    }
    {
        char shown[80];
        c4gh_cli_path_text(argv[1], shown, sizeof shown);
        if (argv[1][0] == '-') {
            fprintf(stderr, RP_TOOL ": unrecognized option '%s' (see " RP_TOOL " --help)\n", shown);
        } else {
            fprintf(stderr, RP_TOOL ": unknown command '%s' (commands: summary, check, export, rerun, "
                    "live, plot, follow; see " RP_TOOL " --help)\n", shown);
        }
    }
    return C4GH_CLI_EXIT_USAGE;
}
