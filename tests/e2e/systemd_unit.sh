#!/bin/sh
# examples/c4g-server.service: systemd accepts it (systemd-analyze verify, when installed),
# it carries the real-time settings docs/rt-integration.md describes, and c4g-server accepts
# its ExecStart options (run on loopback with a high port until its idle timeout; UDP 31407).
set -u
build=$1
unit=examples/c4g-server.service
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
pass() { echo "PASS: $*"; }
bad() { echo "FAIL: $*"; fail=1; }
for key in CPUSchedulingPolicy=fifo LimitMEMLOCK=infinity 'CPUAffinity=' LimitRTPRIO= \
    AmbientCapabilities= 'ExecStart=/usr/local/bin/c4g-server '; do
  grep -q "^$key" "$unit" && pass "$key" || bad "$unit has no $key"
done
if command -v systemd-analyze >/dev/null 2>&1; then
  sed "s|/usr/local/bin/c4g-server|$(pwd)/$build/bin/c4g-server|" "$unit" >"$tmp/c4g-server.service"
  if systemd-analyze verify "$tmp/c4g-server.service" >"$tmp/v.out" 2>&1 && ! grep -qi "unknown\|invalid\|ignoring" "$tmp/v.out"; then
    pass "systemd-analyze verify: clean"
  else
    bad "systemd-analyze verify: $(cat "$tmp/v.out")"
  fi
else
  echo "SKIP: systemd-analyze not installed"
fi
# the options of ExecStart, with a loopback controller, a high port and files in $tmp
args=$(sed -n 's|^ExecStart=/usr/local/bin/c4g-server ||p' "$unit" |
  sed -e 's|^-c [0-9.]*|-c 127.0.0.1|' -e "s|/var/lib/c4g-server|$tmp|" -e "s|/var/log/c4g-server|$tmp|" -e 's| --rt-strict||')
echo "options: $args"
# shellcheck disable=SC2086
timeout 20 "$build/bin/c4g-server" $args -p 31407 --idle-timeout 0.3 >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ "$rc" -eq 4 ] && [ -s "$tmp/last.json" ]; then
  pass "c4g-server runs with the unit's options (exit 4 at the idle timeout, JSON written)"
else
  bad "c4g-server with the unit's options: exit $rc: $(cat "$tmp/err")"
fi
exit $fail
