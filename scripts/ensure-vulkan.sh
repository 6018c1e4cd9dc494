#!/usr/bin/env bash
# Makes sure a Vulkan driver is installed; otherwise installs Debian/Ubuntu's software driver
# (lavapipe, in mesa-vulkan-drivers) with the Vulkan loader. Needs root or sudo to install.
set -euo pipefail
source "$(dirname "$0")/apt-install.sh"

have_vulkan() {
    have_library libvulkan.so.1 || return 1
    compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null ||
        compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null ||
        compgen -G '/usr/local/share/vulkan/icd.d/*.json' >/dev/null
}

if ! have_vulkan; then
    apt_install "a Vulkan driver" mesa-vulkan-drivers libvulkan1
    have_vulkan || { echo "error: still no Vulkan driver after installing mesa-vulkan-drivers" >&2; exit 1; }
fi
