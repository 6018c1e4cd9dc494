#!/usr/bin/env bash
# Makes sure Xvfb (a virtual X server) and the X11 client libraries the viewer's window loads
# at run time are installed, so `make test` runs the `caustic view` window test
# (tests/viewer.rs) headless. Installs Debian/Ubuntu's packages otherwise; needs root or sudo.
set -euo pipefail
source "$(dirname "$0")/apt-install.sh"

PACKAGES=(xvfb libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0)

have_xvfb() {
    command -v Xvfb >/dev/null 2>&1 || return 1
    for lib in libX11.so.6 libX11-xcb.so.1 libXcursor.so.1 libXrandr.so.2 libXi.so.6 libxkbcommon-x11.so.0; do
        have_library "$lib" || return 1
    done
}

if ! have_xvfb; then
    apt_install "Xvfb or an X11 library" "${PACKAGES[@]}"
    have_xvfb || { echo "error: still no Xvfb after installing ${PACKAGES[*]}" >&2; exit 1; }
fi
