# Sourced by the c4g-server benchmarks (bench/server_*.sh): with $build and $tmpname set,
# builds the controller stub and the bare UDP echo loop they measure against, makes $tmp,
# and kills the process in $bpid and removes $tmp on exit. kv FILE KEY reads KEY=value.
srv=$build/bin/c4g-server
stub=$build/e2e-server/ctrl_stub
echo_bin=$build/e2e-server/udp_echo
tmp=$(mktemp -d "${TMPDIR:-/tmp}/$tmpname.XXXXXX")
bpid=""
cleanup() { [ -n "$bpid" ] && kill "$bpid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
trap 'exit 130' INT TERM
mkdir -p "$build/e2e-server"
cc=${CC:-cc}
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Iinclude -Ilib/sim -Ilib/host -o "$stub" \
    tests/e2e/helpers/ctrl_stub.c lib/sim/c4gsim_fixtures.c "$build/lib/libc4gopen.a" -lm || exit 1
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -o "$echo_bin" \
    tests/e2e/helpers/udp_echo.c || exit 1
kv() { sed -n "s/^$2=//p" "$1" | head -n 1; }
