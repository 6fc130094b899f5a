# SPDX-License-Identifier: MIT
# bash completion for the libc4gopen tools: c4g-server, c4g-sim, c4g-replay, c4g-ident,
# cell-cli, cell-sim. Options, and which of them take a value, come from each tool's own
# --help (the option table it parses with), so a new option completes without an edit here.
# Installed as .../bash-completion/completions/c4g-server, the other names linked to it.

# "NAME ARG" per long option of `TOOL [COMMAND] --help` (ARG empty for a flag)
_c4gopen_options()
{
    "$@" --help 2>/dev/null |
        sed -n 's/^  *\(-[A-Za-z0-9], \)\{0,1\}\(--[a-z0-9-]*\)\( \([^ ]\{1,\}\)\)\{0,1\}.*/\2 \4/p'
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
    local table arg
    table=$(_c4gopen_options "$tool" "${cmd[@]}")
    # the value of an option: files for FILE-like placeholders, a directory for DIR
    if [[ $prev == --* ]]; then
        arg=$(printf '%s\n' "$table" | awk -v o="$prev" '$1 == o { print $2 }')
        case $arg in
        DIR) mapfile -t COMPREPLY < <(compgen -d -- "$cur"); return ;;
        *FILE* | LOG | TRAJ*) mapfile -t COMPREPLY < <(compgen -f -- "$cur"); return ;;
        ?*) return ;; # a number, an address ...: nothing to offer
        esac
    fi
    if [[ $cur == -* ]]; then
        mapfile -t COMPREPLY < <(compgen -W "$(printf '%s\n' "$table" | awk '{ print $1 }') --help --version" -- "$cur")
        return
    fi
    case $name in
    cell-cli)
        local words
        if [ "$COMP_CWORD" -eq 1 ] || [[ $prev == -* ]]; then
            words='robot platform conditioning raw wait sleep help'
        else
            case $prev in
            robot | platform | conditioning) words='sta srvon srvof ovr mov stp itr rst clo pnp acq hnd' ;;
            mov) words='abs rel' ;;
            raw | wait) words='robot platform conditioning' ;;
            esac
        fi
        mapfile -t COMPREPLY < <(compgen -W "$words" -- "$cur")
        ;;
    c4g-replay | c4g-ident) mapfile -t COMPREPLY < <(compgen -f -- "$cur") ;;
    esac
}

complete -F _c4gopen c4g-server c4g-sim c4g-replay c4g-ident cell-cli cell-sim
