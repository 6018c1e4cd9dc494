#!/usr/bin/env bash
# Makes sure a Vulkan driver is installed; otherwise installs Debian/Ubuntu's software driver
# (lavapipe, in mesa-vulkan-drivers) with the Vulkan loader. Needs root or sudo to install.
#
# On Debian 12 (bookworm) lavapipe comes from bookworm-backports (Mesa 25): the release's
# own Mesa 22.3 ran Caustic's BVH walk at less than half the speed (docs/PERFORMANCE.md,
# "Lavapipe from Mesa 25"), so an installed older mesa-vulkan-drivers there is upgraded too.
set -euo pipefail
source "$(dirname "$0")/apt-install.sh"

# The oldest Mesa whose lavapipe Caustic is tuned and measured on.
LAVAPIPE_MESA_MAJOR=25
BACKPORTS_LIST=/etc/apt/sources.list.d/caustic-bookworm-backports.sources

have_vulkan() {
    have_library libvulkan.so.1 || return 1
    compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null ||
        compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null ||
        compgen -G '/usr/local/share/vulkan/icd.d/*.json' >/dev/null
}

is_bookworm() {
    [ -r /etc/os-release ] && [ "$(. /etc/os-release && echo "${VERSION_CODENAME:-}")" = bookworm ]
}

# True if mesa-vulkan-drivers is installed and older than LAVAPIPE_MESA_MAJOR.
mesa_is_old() {
    local version
    version=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
    [ -n "$version" ] && dpkg --compare-versions "$version" lt "$LAVAPIPE_MESA_MAJOR"
}

# Adds Debian's bookworm-backports suite unless some apt source already names it.
add_backports() {
    if grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
        return
    fi
    require_root "echo 'deb http://deb.debian.org/debian bookworm-backports main' >/etc/apt/sources.list.d/backports.list && apt-get update && apt-get install -y -t bookworm-backports mesa-vulkan-drivers libvulkan1"
    echo "adding Debian's bookworm-backports suite ($BACKPORTS_LIST) for Mesa $LAVAPIPE_MESA_MAJOR." >&2
    as_root tee "$BACKPORTS_LIST" >/dev/null <<'EOF'
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm-backports
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
}

# A machine whose only Vulkan driver is another vendor's (no mesa-vulkan-drivers) is left alone.
if is_bookworm && { ! have_vulkan || mesa_is_old; }; then
    add_backports
    apt_install "lavapipe of Mesa $LAVAPIPE_MESA_MAJOR or newer" -t bookworm-backports mesa-vulkan-drivers libvulkan1
    if mesa_is_old; then
        echo "error: mesa-vulkan-drivers is still older than $LAVAPIPE_MESA_MAJOR after installing it from bookworm-backports" >&2
        exit 1
    fi
elif ! have_vulkan; then
    apt_install "a Vulkan driver" mesa-vulkan-drivers libvulkan1
fi
have_vulkan || { echo "error: still no Vulkan driver after installing mesa-vulkan-drivers" >&2; exit 1; }
