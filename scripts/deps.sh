#!/bin/sh
# Checks every build/test dependency and installs what is missing (apt-get, as root).
# Idempotent: a second run with everything present installs nothing.
set -eu

# command-or-file probe : Debian package
CHECKS='
cc:gcc
g++:g++
make:make
pkg-config:pkg-config
/usr/include/cmocka.h:libcmocka-dev
/usr/include/pcap/pcap.h:libpcap-dev
clang:clang
/usr/lib/llvm-14/lib/clang/14.0.6/lib/linux/libclang_rt.fuzzer-x86_64.a:libclang-rt-14-dev
cppcheck:cppcheck
clang-tidy:clang-tidy
arm-none-eabi-gcc:gcc-arm-none-eabi
/usr/lib/arm-none-eabi/newlib/libc.a:libnewlib-arm-none-eabi
qemu-arm:qemu-user
valgrind:valgrind
tshark:tshark
text2pcap:wireshark-common
lcov:lcov
python3:python3
ss:iproute2
/usr/include/histedit.h:libedit-dev
/usr/include/ini.h:libinih-dev
/usr/include/linux/can/raw.h:linux-libc-dev
/usr/include/jansson.h:libjansson-dev
/usr/include/mujoco/mujoco.h:libmujoco-dev
gnuplot:gnuplot-nox
tcpdump:tcpdump
editcap:wireshark-common
/usr/bin/time:time
/usr/include/ceres/ceres.h:libceres-dev
/usr/include/eigen3/Eigen/Dense:libeigen3-dev
/usr/lib/python3/dist-packages/scipy/__init__.py:python3-scipy
/usr/lib/python3/dist-packages/pytest/__init__.py:python3-pytest
scdoc:scdoc
man:man-db
nroff:groff-base
/usr/share/bash-completion/bash_completion:bash-completion
'

missing=''
for entry in $CHECKS; do
  probe=${entry%%:*}
  pkg=${entry#*:}
  case $probe in
    /*) [ -e "$probe" ] && continue ;;
    *) command -v "$probe" >/dev/null 2>&1 && continue ;;
  esac
  case " $missing " in *" $pkg "*) ;; *) missing="$missing $pkg" ;; esac
done

# the clang runtime path depends on the exact clang version: accept any fuzzer runtime
if [ -n "$missing" ]; then
  case " $missing " in
    *" libclang-rt-14-dev "*)
      if ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
        missing=$(echo "$missing" | sed 's/ libclang-rt-14-dev//')
      fi ;;
  esac
fi

missing=$(echo "$missing" | sed 's/^ *//')
if [ -z "$missing" ]; then
  echo "deps: all present"
  exit 0
fi

echo "deps: missing: $missing"
if [ "$(id -u)" -ne 0 ]; then
  echo "deps: not root; run:  sudo apt-get update && sudo apt-get install -y $missing" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >/dev/null || { echo "deps: apt-get update failed" >&2; exit 1; }
# shellcheck disable=SC2086
apt-get install -y -q --no-install-recommends $missing >/dev/null || {
  echo "deps: apt-get install failed for: $missing" >&2; exit 1; }
echo "deps: installed $missing"
