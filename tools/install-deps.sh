#!/bin/sh
# SPDX-License-Identifier: MIT
# Installs the Debian packages sonarslam needs, and only those that are missing.
#
#   tools/install-deps.sh [GROUP...]     groups: test sim firmware flash linux compare fuzz
#                                        web ros all (default: all)
#
# Idempotent: when everything is present it installs nothing and says so. Before
# installing it says how many packages that means and their size. When another program
# holds apt's lock (a fresh Debian's unattended upgrades, say) it says so and waits, up to
# INSTALL_DEPS_LOCK_WAIT seconds (default 900), then gives up with a message naming the
# process. Uses sudo when not run as root. Exit status is non-zero when an install fails.
set -eu

LOCK_WAIT=${INSTALL_DEPS_LOCK_WAIT:-900}
LOCK_POLL=${INSTALL_DEPS_LOCK_POLL:-5}

usage() {
    echo "usage: tools/install-deps.sh [test|sim|firmware|flash|linux|compare|fuzz|web|ros|all]...   (default: all)"
    echo "Installs the missing Debian packages the named parts of sonarslam need."
}

# What each group needs (Debian bookworm package names).
# web: the bridge between the robot and the browser page (tools/telemetry.py serve); the
# page itself needs nothing but a browser.
pkgs_web="python3 python3-websockets"
# ros: runs as ROS 1 bags (host_sim --bag, tools/telemetry.py to-bag).
pkgs_ros="python3 python3-numpy python3-rosbag python3-nav-msgs python3-sensor-msgs python3-geometry-msgs python3-tf2-msgs"
# The tests also drive the page in headless Chromium. On a bookworm system with the rest
# of the test group, chromium, chromium-driver, python3-selenium and the web and ros groups
# were 90 packages, 138 MB to download and 466 MB installed.
pkgs_test="cmake make gcc clang clang-format pkg-config libcmocka-dev gcc-multilib libcmocka-dev:i386 valgrind binutils libtsan2 python3-hypothesis chromium chromium-driver python3-selenium $pkgs_web $pkgs_ros"
pkgs_sim="cmake make gcc pkg-config libcmocka-dev python3 python3-numpy python3-matplotlib python3-serial"
pkgs_firmware="cmake make gcc gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi qemu-system-arm python3 python3-unicorn"
pkgs_flash="openocd gdb-multiarch"
pkgs_linux="cmake make gcc pkg-config libgpiod-dev libcmocka-dev"
# make compare only: OctoMap beside the firmware's mapper, both counted by callgrind.
pkgs_compare="cmake make gcc g++ liboctomap-dev valgrind python3 python3-numpy"
pkgs_fuzz="cmake make clang libclang-rt-dev libcmocka-dev python3 python3-hypothesis"

want=""
[ $# -eq 0 ] && set -- all
for group in "$@"; do
    case "$group" in
        test)     want="$want $pkgs_test" ;;
        sim)      want="$want $pkgs_sim" ;;
        firmware) want="$want $pkgs_firmware" ;;
        flash)    want="$want $pkgs_flash" ;;
        linux)    want="$want $pkgs_linux" ;;
        compare)  want="$want $pkgs_compare" ;;
        fuzz)     want="$want $pkgs_fuzz" ;;
        web)      want="$want $pkgs_web" ;;
        ros)      want="$want $pkgs_ros" ;;
        all)      want="$want $pkgs_test $pkgs_sim $pkgs_firmware $pkgs_flash $pkgs_linux $pkgs_compare $pkgs_fuzz $pkgs_web $pkgs_ros" ;;
        -h|--help) usage; exit 0 ;;
        *) echo "install-deps: unknown group '$group' (valid: test sim firmware flash linux compare fuzz web ros all)" >&2; exit 2 ;;
    esac
done

# A package is installed when dpkg says so; a plain name is tried for the native
# architecture first (libcmocka-dev may be present for amd64 and i386 at once).
installed() {
    case "$1" in
        *:*) names="$1" ;;
        *)   names="$1:$(dpkg --print-architecture) $1" ;;
    esac
    for n in $names; do
        [ "$(dpkg-query -W -f='${Status}' "$n" 2>/dev/null)" = "install ok installed" ] && return 0
    done
    return 1
}

missing=""
for p in $want; do
    case " $missing " in *" $p "*) continue ;; esac
    installed "$p" || missing="$missing $p"
done

if [ -z "$missing" ]; then
    echo "install-deps: all needed Debian packages are installed."
    exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
else
    echo "install-deps: need root (or sudo) to install:$missing" >&2
    exit 1
fi

# apt-get "$@", waited for while another program holds apt's or dpkg's lock: apt-get gives
# up at once then, and the message it gives ("Could not get lock") is the only sign.
apt_locked() {
    log=$(mktemp)
    waited=0
    told=""
    while :; do
        if $SUDO env DEBIAN_FRONTEND=noninteractive apt-get "$@" 2>"$log"; then
            cat "$log" >&2; rm -f "$log"; return 0
        fi
        if ! grep -q -e 'Could not get lock' -e 'Unable to acquire the dpkg frontend lock' \
                -e 'Unable to lock' "$log"; then
            cat "$log" >&2; rm -f "$log"; return 1
        fi
        # "It is held by process 1234 (unattended-upgr)"
        holder=$(sed -n 's/.*held by process \([0-9]*\).*/\1/p' "$log" | head -n 1)
        name=$(sed -n 's/.*held by process [0-9]* (\([^)]*\)).*/\1/p' "$log" | head -n 1)
        who="${name:-another program}"
        [ -n "$holder" ] && who="$who, process $holder"
        if [ "$waited" -ge "$LOCK_WAIT" ]; then
            echo "install-deps: apt is still busy after ${LOCK_WAIT} s (its lock is held by $who);" \
                 "try again when it is done, or set INSTALL_DEPS_LOCK_WAIT=SECONDS to wait longer" >&2
            rm -f "$log"; return 1
        fi
        if [ -z "$told" ]; then
            echo "install-deps: apt is busy (its lock is held by $who: often the daily" \
                 "unattended upgrade); waiting up to ${LOCK_WAIT} s..." >&2
            told=yes
        fi
        sleep "$LOCK_POLL"
        waited=$((waited + LOCK_POLL))
    done
}

case "$missing" in
    *":i386"*)
        if ! dpkg --print-foreign-architectures | grep -qx i386; then
            echo "install-deps: enabling the i386 architecture for the 32-bit test build"
            $SUDO dpkg --add-architecture i386
        fi
        ;;
esac

# An index that fails to download must not stop the install: judge by the install itself.
apt_locked update -q || echo "install-deps: apt-get update reported errors; trying the install anyway" >&2

# What the install brings, before it starts: the packages (those asked for and what they
# depend on) and their size, from the package index.
# shellcheck disable=SC2086
new=$(apt-get -s -q install --no-install-recommends $missing 2>/dev/null | sed -n 's/^Inst \([^ ]*\).*/\1/p' || true)
if [ -n "$new" ]; then
    # shellcheck disable=SC2086
    sizes=$(apt-cache show --no-all-versions $new 2>/dev/null |
            awk '/^Size:/ {d += $2} /^Installed-Size:/ {i += $2} END {printf "%.0f %.0f", d / 1e6, i * 1024 / 1e6}')
    count=$(echo "$new" | wc -l)
    echo "install-deps: installing$missing"
    echo "install-deps: that is $count packages with what they need: about ${sizes% *} MB to download, ${sizes#* } MB on disk"
else
    echo "install-deps: installing$missing"
fi
# shellcheck disable=SC2086
apt_locked install -y -q --no-install-recommends $missing || true

still=""
for p in $missing; do installed "$p" || still="$still $p"; done
if [ -n "$still" ]; then
    echo "install-deps: these packages are still missing:$still" >&2
    exit 1
fi
echo "install-deps: done."
