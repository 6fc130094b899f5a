#!/bin/sh
# Writes fixtures/replay/golden/NAME.json: `c4g-replay summary --json` of every capture in
# fixtures/replay (options from fixtures/replay/golden/OPTIONS), without the "tool" key
# (it carries the version). The e2e test tests/e2e/test_replay.py makes the same comparison;
# review the diff (git diff fixtures/replay/golden) before committing new ones.
#   sh scripts/make-replay-golden.sh BUILD_DIR [--check]
# --check: compare instead of writing; exit 1 on any difference.
set -u
B=${1:?usage: sh scripts/make-replay-golden.sh BUILD_DIR [--check]}
mode=${2:-write}
R=$B/bin/c4g-replay
G=fixtures/replay/golden
[ -x "$R" ] || { echo "make-replay-golden: $R not built" >&2; exit 2; }
tmp=$(mktemp "${TMPDIR:-/tmp}/c4ggold.XXXXXX")
trap 'rm -f "$tmp"' EXIT
bad=0; n=0
for f in fixtures/replay/*.pcap fixtures/replay/*.pcapng; do
  [ -f "$f" ] || continue
  base=$(basename "$f"); name=${base%.*}
  opts=$(awk -v n="$name" '$1 == n { $1 = ""; print }' "$G/OPTIONS")
  # shellcheck disable=SC2086
  "$R" summary --json --no-progress $opts "$f" 2>/dev/null |
    python3 -c 'import json, sys; d = json.load(sys.stdin); d.pop("tool", None); print(json.dumps(d, indent=2))' \
      >"$tmp" || { echo "make-replay-golden: $f: summary failed" >&2; bad=1; continue; }
  n=$((n + 1))
  if [ "$mode" = --check ]; then
    if ! cmp -s "$tmp" "$G/$name.json"; then
      echo "golden: $name.json differs:"; diff -u "$G/$name.json" "$tmp" | head -40; bad=1
    fi
  else
    cp "$tmp" "$G/$name.json"
  fi
done
[ "$mode" = --check ] && echo "golden: $n captures compared, $([ $bad -eq 0 ] && echo all equal || echo DIFFERENCES)"
[ "$mode" = --check ] || echo "golden: $n files written in $G"
exit $bad
