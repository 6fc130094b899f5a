#!/bin/sh
# make install into a DESTDIR, build a program against it with pkg-config (static and
# shared), run both, then make uninstall removes every installed file.
set -eu
build=$1
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
make -s BUILD="$build" install DESTDIR="$root" PREFIX=/opt/c4g >/dev/null
test -f "$root/opt/c4g/include/c4gopen.h"
test -f "$root/opt/c4g/lib/libc4gopen.a"
soname=$(readelf -d "$root/opt/c4g/lib/libc4gopen.so" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
echo "SONAME: $soname"
test "$soname" = "libc4gopen.so.2"
export PKG_CONFIG_PATH="$root/opt/c4g/lib/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$root"
flags=$(pkg-config --cflags --libs c4gopen)
echo "pkg-config: $flags"
cat >"$root/app.c" <<'C'
#include <c4gopen.h>
#include <stdio.h>
int main(void)
{
    c4g_loop_t lp;
    c4g_loop_config_t cfg;
    c4g_pc_packet_t neutral = {0};
    unsigned char buf[C4G_MAX_CYCLIC_SIZE];
    size_t n = 0;
    neutral.n_axes = 6;
    if (c4g_session_config_default(&cfg.session) != C4G_OK ||
        c4g_engine_config_default(&cfg.engine) != C4G_OK || c4g_loop_init(&lp, &cfg) != C4G_OK ||
        c4g_pc_encode(&neutral, buf, sizeof buf, &n) != C4G_OK)
        return 1;
    printf("%s %u %s\n", C4G_VERSION_STRING, (unsigned)n, c4g_strerror(C4G_ERR_CELL_HEAD));
    return n == C4G_CYCLIC_SIZE(6) ? 0 : 1;
}
C
# shellcheck disable=SC2086
cc -std=c99 -o "$root/app_shared" "$root/app.c" $flags
LD_LIBRARY_PATH="$root/opt/c4g/lib" "$root/app_shared"
cc -std=c99 -o "$root/app_static" "$root/app.c" $(pkg-config --cflags c4gopen) "$root/opt/c4g/lib/libc4gopen.a"
"$root/app_static"
# the README's compile line, verbatim, on the shipped example; then its --help
line=$(grep '^cc -o mode4_loop examples/mode4_loop.c ' README.md)
echo "README: $line"
test -n "$line"
mkdir -p "$root/src" && cp -r examples "$root/src/"
(cd "$root/src" && sh -c "$line") || { echo "the README's compile line failed"; exit 1; }
LD_LIBRARY_PATH="$root/opt/c4g/lib" "$root/src/mode4_loop" --help | grep -q '^Usage: mode4_loop \[-p PORT\]'
rc=0; LD_LIBRARY_PATH="$root/opt/c4g/lib" "$root/src/mode4_loop" -p nope 2>/dev/null || rc=$?
test "$rc" -eq 2
echo "mode4_loop: built by the README's line; --help and a bad port (exit 2) answered"
# static: pkg-config --static carries Libs.private (-lm)
pkg-config --static --libs c4gopen | grep -q -- -lm
# man pages and bash completion installed; the pages render
for p in man1/c4g-server.1 man1/c4g-sim.1 man1/c4g-replay.1 man1/c4g-ident.1 man1/cell-cli.1 man1/cell-sim.1 man3/c4gopen.3; do
  test -s "$root/opt/c4g/share/man/$p" || { echo "not installed: $p"; exit 1; }
done
MANWIDTH=80 man -l "$root/opt/c4g/share/man/man3/c4gopen.3" | grep -q c4g_loop_rx
for t in c4g-server c4g-sim c4g-replay c4g-ident cell-cli cell-sim; do
  test -r "$root/opt/c4g/share/bash-completion/completions/$t" || { echo "no completion for $t"; exit 1; }
done
grep -q "complete -F _c4gopen" "$root/opt/c4g/share/bash-completion/completions/cell-cli"
echo "man pages and bash completions installed"
make -s BUILD="$build" uninstall DESTDIR="$root" PREFIX=/opt/c4g >/dev/null
left=$(find "$root/opt" -type f -o -type l | wc -l)
echo "files left after uninstall: $left"
test "$left" -eq 0
