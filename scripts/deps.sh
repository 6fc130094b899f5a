#!/bin/sh
# Checks the Debian packages one group of targets needs and installs what is missing
# (apt-get, as root); as another user it names them and the command that installs them.
# Idempotent: a second run with everything present installs nothing.
#   sh scripts/deps.sh [lib|tools|check]     (default check: every package below)
#     lib    the library: a C compiler and make
#     tools  the library, the tools' libraries (c4g-ident: C++ and Ceres) and the man pages
#     check  every test and quality gate (the QA set: the whole CHECKS list)
set -eu
group=${1:-check}

# command-or-file probe : Debian package
LIB_CHECKS='
cc:gcc
make:make
ar:binutils
'
TOOL_CHECKS='
/usr/include/pcap/pcap.h:libpcap-dev
/usr/include/ini.h:libinih-dev
/usr/include/jansson.h:libjansson-dev
/usr/include/histedit.h:libedit-dev
/usr/include/linux/can/raw.h:linux-libc-dev
/usr/include/mujoco/mujoco.h:libmujoco-dev
g++:g++
/usr/include/ceres/ceres.h:libceres-dev
/usr/include/eigen3/Eigen/Dense:libeigen3-dev
python3:python3
scdoc:scdoc
'
# every package of every gate (make check, CI)
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

case $group in
lib) list=$LIB_CHECKS ;;
tools) list="$LIB_CHECKS $TOOL_CHECKS" ;;
check) list="$LIB_CHECKS $TOOL_CHECKS $CHECKS" ;;
*) echo "deps: unknown group '$group' (lib, tools or check)" >&2; exit 2 ;;
esac

missing=''
for entry in $list; do
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
  echo "deps ($group): all present"
  exit 0
fi

echo "deps ($group): missing: $missing"
if [ "$(id -u)" -ne 0 ]; then
  echo "deps: not root; run:  sudo apt-get update && sudo apt-get install -y $missing" >&2
  echo "deps: (or: sudo sh scripts/deps.sh $group)" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >/dev/null || { echo "deps: apt-get update failed" >&2; exit 1; }
# shellcheck disable=SC2086
apt-get install -y -q --no-install-recommends $missing >/dev/null || {
  echo "deps: apt-get install failed for: $missing" >&2; exit 1; }
echo "deps: installed $missing"
