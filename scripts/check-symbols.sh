#!/bin/sh
# Symbol audit of a static library: undefined symbols from an allow-list only,
# no .data/.bss (no hidden mutable state), every exported symbol prefixed c4g_.
set -u
nm=$1; lib=$2
err=$(mktemp); out=$(mktemp)
"$nm" -A "$lib" >"$out" 2>"$err"
if [ -s "$err" ]; then echo "audit: $nm complained:" >&2; cat "$err" >&2; exit 1; fi
bad=0
# undefined in some member and defined in none: what the archive needs from outside
defined=$(awk 'NF >= 3 && $(NF-1) ~ /^[TDRBCGSVW]$/ {print $NF}' "$out" | sort -u)
undef=$(awk 'NF == 3 && $2 == "U" {print $3} NF == 2 && $1 ~ /:U$/ {print $2}' "$out" | sort -u | grep -vxF "$defined" || true)
for s in $undef; do
  case $s in
    memcmp|memcpy|memmove|memset|_GLOBAL_OFFSET_TABLE_|__stack_chk_fail|__stack_chk_guard) ;;
    __aeabi_*|__*div[sd]i3|__*mod[sd]i3|__udivmod*|__x86.get_pc_thunk.*) ;;
    *) echo "audit: $lib: undefined symbol not allowed: $s" >&2; bad=1 ;;
  esac
done
# Mutable state = bytes in .data/.bss-like sections or common symbols. Const tables of
# pointers land in .data.rel.ro under PIE/PIC: read-only after relocation, allowed.
objdump=$(echo "$nm" | sed 's/nm$/objdump/')
"$objdump" -h "$lib" >"$out.h" 2>"$err" || { cat "$err" >&2; exit 1; }
state=$(awk '$2 ~ /^\.(data|bss|sdata|sbss|tbss|tdata)(\..*)?$/ && $2 !~ /^\.data\.rel\.ro/ && $3 !~ /^0+$/ {print $2 "(" $3 ")"}' "$out.h" | sort -u | tr '\n' ' ')
common=$(awk 'NF >= 3 && $(NF-1) == "C" {print $NF}' "$out" | sort -u | tr '\n' ' ')
rm -f "$out.h"
if [ -n "$state$common" ]; then echo "audit: $lib: mutable static data: $state$common" >&2; bad=1; fi
exported=$(awk 'NF >= 3 && $(NF-1) ~ /^[TDRBCGSV]$/ {print $NF}' "$out" | sort -u)
for s in $exported; do
  case $s in c4g_*|__x86.get_pc_thunk.*) ;; *) echo "audit: $lib: exported symbol without c4g_ prefix: $s" >&2; bad=1 ;; esac
done
rm -f "$err" "$out"
[ "$bad" -eq 0 ] || exit 1
echo "audit: $lib: $(echo "$exported" | wc -w) exported c4g_ symbols, undefined: $(echo $undef | tr '\n' ' ')"
