#!/usr/bin/env bash
# Makes sure Xvfb (a virtual X server) and the X11 client libraries the viewer's window loads
# at run time are installed, so `make test` runs the `caustic view` window test
# (tests/viewer.rs) headless. Installs Debian/Ubuntu's packages otherwise; needs root or sudo.
set -euo pipefail

PACKAGES="xvfb libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0"

have_xvfb() {
    command -v Xvfb >/dev/null 2>&1 || return 1
    for lib in libX11.so.6 libX11-xcb.so.1 libXcursor.so.1 libXrandr.so.2 libXi.so.6 libxkbcommon-x11.so.0; do
        ldconfig -p 2>/dev/null | grep -q "$lib" || return 1
    done
}

if have_xvfb; then
    exit 0
fi

echo "Xvfb or an X11 library is missing: installing $PACKAGES." >&2
if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
else
    echo "error: installing Xvfb needs root or sudo; run as root:" >&2
    echo "  apt-get update && apt-get install -y $PACKAGES" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086 # the package list is meant to split into words
$SUDO apt-get install -y -qq $PACKAGES >/dev/null
have_xvfb || { echo "error: still no Xvfb after installing $PACKAGES" >&2; exit 1; }
