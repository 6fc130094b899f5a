#!/bin/sh
# Symbol audit of a static library: undefined symbols from an allow-list only,
# no .data/.bss (no hidden mutable state), every exported symbol prefixed c4g_.
set -u
nm=$1; lib=$2
err=$(mktemp); out=$(mktemp)
"$nm" -A "$lib" >"$out" 2>"$err"
if [ -s "$err" ]; then echo "audit: $nm complained:" >&2; cat "$err" >&2; exit 1; fi
bad=0
undef=$(awk '$2 == "U" {print $3}' "$out" | sort -u)
for s in $undef; do
  case $s in
    memcmp|memcpy|memmove|memset|_GLOBAL_OFFSET_TABLE_|__stack_chk_fail|__stack_chk_guard) ;;
    __aeabi_*|__*div[sd]i3|__*mod[sd]i3|__udivmod*|__x86.get_pc_thunk.*) ;;
    *) echo "audit: $lib: undefined symbol not allowed: $s" >&2; bad=1 ;;
  esac
done
state=$(awk 'NF >= 3 && $(NF-1) ~ /^[BbDdCGgSs]$/ {print $NF}' "$out" | sort -u)
if [ -n "$state" ]; then echo "audit: $lib: mutable static data: $state" >&2; bad=1; fi
exported=$(awk 'NF >= 3 && $(NF-1) ~ /^[TDRBCGS]$/ {print $NF}' "$out" | sort -u)
for s in $exported; do
  case $s in c4g_*|__x86.get_pc_thunk.*) ;; *) echo "audit: $lib: exported symbol without c4g_ prefix: $s" >&2; bad=1 ;; esac
done
rm -f "$err" "$out"
[ "$bad" -eq 0 ] || exit 1
echo "audit: $lib: $(echo "$exported" | wc -w) exported c4g_ symbols, undefined: $(echo $undef | tr '\n' ' ')"
