#!/bin/sh
# Symbol audit of one archive: sh scripts/check-symbols.sh NM ARCHIVE PREFIX KIND HEADER...
#   - every exported symbol carries PREFIX and is declared in one of the HEADERs, and every
#     function those headers declare is exported (the archive exports exactly its headers);
#   - KIND pure: undefined symbols only from an allow-list (mem*, libm, compiler helpers and,
#     for the simulator's archive, libc4gopen's public API), no
#     .data/.bss (no hidden mutable state). KIND host: the C library and POSIX are allowed.
set -u
nm=$1; lib=$2; prefix=$3; kind=$4; shift 4
err=$(mktemp); out=$(mktemp); decl=$(mktemp)
trap 'rm -f "$err" "$out" "$decl" "$out.h"' EXIT
"$nm" -A "$lib" >"$out" 2>"$err"
if [ -s "$err" ]; then echo "audit: $nm complained:" >&2; cat "$err" >&2; exit 1; fi
bad=0
defined=$(awk 'NF >= 3 && $(NF-1) ~ /^[TDRBCGSVW]$/ {print $NF}' "$out" | sort -u)
undef=$(awk 'NF == 3 && $2 == "U" {print $3} NF == 2 && $1 ~ /:U$/ {print $2}' "$out" | sort -u | grep -vxF "$defined" || true)
if [ "$kind" = pure ]; then
  for s in $undef; do
    case $s in
      memcmp|memcpy|memmove|memset|_GLOBAL_OFFSET_TABLE_|__stack_chk_fail|__stack_chk_guard) ;;
      __aeabi_*|__*div[sd]i3|__*mod[sd]i3|__udivmod*|__x86.get_pc_thunk.*) ;;
      sqrt|sqrtf|fabs|fabsf|exp|log|cos|sin|sincos|atan2|floor|ceil|fmod|tanh|pow|round|lround) ;;
      c4g_*) [ "$prefix" = c4gsim_ ] || { echo "audit: $lib: undefined symbol not allowed: $s" >&2; bad=1; } ;;
      *) echo "audit: $lib: undefined symbol not allowed: $s" >&2; bad=1 ;;
    esac
  done
  # Mutable state = bytes in .data/.bss-like sections or common symbols. Const tables of
  # pointers land in .data.rel.ro under PIE/PIC: read-only after relocation, allowed.
  objdump=$(echo "$nm" | sed 's/nm$/objdump/')
  "$objdump" -h "$lib" >"$out.h" 2>"$err" || { cat "$err" >&2; exit 1; }
  state=$(awk '$2 ~ /^\.(data|bss|sdata|sbss|tbss|tdata)(\..*)?$/ && $2 !~ /^\.data\.rel\.ro/ && $3 !~ /^0+$/ {print $2 "(" $3 ")"}' "$out.h" | sort -u | tr '\n' ' ')
  common=$(awk 'NF >= 3 && $(NF-1) == "C" {print $NF}' "$out" | sort -u | tr '\n' ' ')
  if [ -n "$state$common" ]; then echo "audit: $lib: mutable static data: $state$common" >&2; bad=1; fi
fi
exported=$(awk 'NF >= 3 && $(NF-1) ~ /^[TDRBGSV]$/ {print $NF}' "$out" | grep -v '^__x86.get_pc_thunk' | sort -u)
# what the headers declare: functions (prototypes) and objects, by ctags
ctags -x --c-kinds=px --language-force=C "$@" 2>/dev/null | awk '{print $1}' | sort -u >"$decl"
for s in $exported; do
  case $s in "$prefix"*) ;; *) echo "audit: $lib: exported symbol without $prefix prefix: $s" >&2; bad=1; continue ;; esac
  grep -qxF "$s" "$decl" || { echo "audit: $lib: exports $s, which no header declares (make it static)" >&2; bad=1; }
done
for s in $(cat "$decl"); do
  echo "$exported" | grep -qxF "$s" || { echo "audit: $lib: a header declares $s, which the archive does not define" >&2; bad=1; }
done
[ "$bad" -eq 0 ] || exit 1
n=$(echo "$exported" | grep -c .)
echo "audit: $(basename "$lib"): $n exported $prefix symbols = its headers' declarations${undef:+; undefined: $(echo $undef | wc -w)}"
