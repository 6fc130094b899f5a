# SPDX-License-Identifier: MIT
# bash completion for the libc4gopen tools: c4g-server, c4g-sim, c4g-replay, c4g-ident,
# cell-cli, cell-sim. Options, their short forms, which take a value and the values an
# option lists ("one of a, b or c", "drop|truncate") come from each tool's own --help (the
# option table it parses with); cell-cli's commands per device from `cell-cli help DEVICE`
# (the library's command table). A new option or command completes without an edit here.
# Installed as .../bash-completion/completions/c4g-server, the other names linked to it.

# One line per option of `TOOL [COMMAND] --help`: "LONG SHORT ARG CHOICES", "-" for none
# (CHOICES comma-separated). A description may go on over the next lines.
_c4gopen_options()
{
    "$@" --help 2>/dev/null | awk '
    function choices(arg, d,    w, n, i, out, lower) {
        if (arg ~ /^[a-z0-9-]+(\|[a-z0-9-]+)+$/) { gsub(/\|/, ",", arg); return arg }
        while (gsub(/\([^()]*\)/, "", d)) {}      # no parenthesised remarks
        gsub(/[ \t]+/, " ", d); gsub(/ ,/, ",", d)
        while ((i = index(d, ": ")) > 0) d = substr(d, i + 2)
        sub(/^ /, "", d)
        # "a, b or c" at the start: the values
        if (!match(d, /^[a-z0-9][a-z0-9-]*(, [a-z0-9][a-z0-9-]*)* or [a-z0-9][a-z0-9-]*([ ,;.]|$)/)) return "-"
        d = substr(d, 1, RLENGTH); sub(/[ ,;.]$/, "", d); gsub(/,? or /, ",", d); gsub(/, /, ",", d)
        n = split(d, w, ","); out = ""; lower = tolower(arg)
        for (i = 1; i <= n; i++) if (w[i] != lower) out = out (out == "" ? "" : ",") w[i]
        return out == "" ? "-" : out
    }
    function flush() { if (long != "") print long, short, arg, choices(arg, desc); long = "" }
    /^Options:/ { inopt = 1; next }
    inopt && /^[ \t]*$/ { flush(); inopt = 0; next }
    inopt && /^ +(-[A-Za-z0-9], )?--[a-z0-9-]+/ {
        flush(); line = $0; sub(/^ +/, "", line); short = "-"
        if (line ~ /^-[A-Za-z0-9], /) { short = substr(line, 1, 2); line = substr(line, 5) }
        match(line, /^--[a-z0-9-]+/); long = substr(line, 1, RLENGTH); line = substr(line, RLENGTH + 1)
        arg = "-"
        if (line ~ /^ [^ ]/) { line = substr(line, 2); match(line, /^[^ ]+/); arg = substr(line, 1, RLENGTH); line = substr(line, RLENGTH + 1) }
        desc = line; next
    }
    inopt && long != "" { desc = desc " " $0 }
    END { flush() }'
}

# the completions of a directory or file name: bash adds the "/" of a directory and quotes
_c4gopen_files()
{
    compopt -o filenames 2>/dev/null
    mapfile -t COMPREPLY < <(compgen "$1" -- "$2")
}

_c4gopen_cell_cli()
{
    local tool=$1 cur=$2 prev=$3 words
    if [ "$COMP_CWORD" -eq 1 ] || [[ $prev == -* ]]; then
        words='robot platform conditioning raw wait sleep connect help'
    else
        case $prev in
        robot | platform | conditioning)
            if [ "$COMP_CWORD" -ge 3 ] && [[ ${COMP_WORDS[COMP_CWORD-2]} == connect ]]; then
                return # connect DEV HOST[:PORT]
            fi
            # the device's own commands, from the command table
            words=$("$tool" help "$prev" 2>/dev/null | awk -v d="$prev" '$1 == d { print $2 }') ;;
        mov | move) words='abs rel' ;;
        raw | wait | connect) words='robot platform conditioning' ;;
        help) # the command words of the overview ("  DEV sta ...", "  robot mov ...", "  raw ...")
            words="$("$tool" help 2>/dev/null | awk '/^  [A-Za-z]/ { w = $1
                if (w == "DEV" || w == "robot" || w == "platform" || w == "conditioning") w = $2
                if (w ~ /^[a-z]/ && !seen[w]++) print w }') robot platform conditioning" ;;
        esac
    fi
    mapfile -t COMPREPLY < <(compgen -W "$words" -- "$cur")
}

_c4gopen()
{
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}
    local tool=${COMP_WORDS[0]} name=${COMP_WORDS[0]##*/} subs='' cmd=()
    COMPREPLY=()
    case $name in
    c4g-replay) subs='summary check export rerun live plot follow' ;;
    c4g-ident) subs='fit excite' ;;
    esac
    if [ -n "$subs" ]; then
        if [ "$COMP_CWORD" -eq 1 ]; then
            mapfile -t COMPREPLY < <(compgen -W "$subs --help --version" -- "$cur")
            return
        fi
        cmd=("${COMP_WORDS[1]}")
    fi
    local table row
    table=$(_c4gopen_options "$tool" "${cmd[@]}")
    # the value of an option, long or short: its listed values, files for FILE-like
    # placeholders, a directory for DIR, nothing for a number or an address
    if [[ $prev == -* ]]; then
        row=$(printf '%s\n' "$table" | awk -v o="$prev" '($1 == o || $2 == o) && $3 != "-" { print $3, $4 }')
        if [ -n "$row" ]; then
            local arg=${row%% *} values=${row#* }
            if [ "$values" != - ]; then
                mapfile -t COMPREPLY < <(compgen -W "${values//,/ }" -- "$cur")
                return
            fi
            case $arg in
            DIR) _c4gopen_files -d "$cur" ;;
            *FILE* | LOG | TRAJ*) _c4gopen_files -f "$cur" ;;
            esac
            return
        fi
    fi
    if [[ $cur == -* ]]; then
        mapfile -t COMPREPLY < <(compgen -W "$(printf '%s\n' "$table" | awk '{ print $1 }') --help --version" -- "$cur")
        return
    fi
    case $name in
    cell-cli) _c4gopen_cell_cli "$tool" "$cur" "$prev" ;;
    c4g-replay | c4g-ident) _c4gopen_files -f "$cur" ;;
    esac
}

complete -F _c4gopen c4g-server c4g-sim c4g-replay c4g-ident cell-cli cell-sim
