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
test "$soname" = "libc4gopen.so.1"
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
make -s BUILD="$build" uninstall DESTDIR="$root" PREFIX=/opt/c4g >/dev/null
left=$(find "$root/opt" -type f | wc -l)
echo "files left after uninstall: $left"
test "$left" -eq 0
