#!/bin/sh
# Installs, with apt-get, every Debian package ddmr-hil needs to build, test and run.
# Skips apt-get entirely when every package is already installed, so it is cheap
# to call before every build. Needs root (CI and the README's commands run as root).
set -eu

PACKAGES="
build-essential cmake pkg-config
simavr libsimavr-dev libelf-dev zlib1g-dev
gcc-avr binutils-avr avr-libc
arduino-core-avr arduino-builder arduino-ctags
libeigen3-dev libgtest-dev libgmock-dev libbenchmark-dev
libcli11-dev nlohmann-json3-dev libyaml-cpp-dev libfmt-dev libssl-dev
python3 python3-matplotlib python3-jsonschema python3-yaml python3-pytest python3-pytest-xdist python3-numpy python3-distributed
pybind11-dev python3-dev
gdb-avr libpugixml-dev patch
valgrind ccache lld
libnlopt-cxx-dev libinih-dev
cppcheck clang-tidy
"

missing=""
for p in $PACKAGES; do
    status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
    case "$status" in
        "install ok installed") ;;
        *) missing="$missing $p" ;;
    esac
done

if [ -z "$missing" ]; then
    echo "deps: all $(echo $PACKAGES | wc -w) packages present"
    exit 0
fi

echo "deps: installing:$missing"
if [ "$(id -u)" -ne 0 ]; then
    echo "deps: error: missing packages and not root; run as root or: apt-get install$missing" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
# shellcheck disable=SC2086
apt-get install -y -q --no-install-recommends $missing
