#!/usr/bin/env bash
# Makes sure a Vulkan driver is installed; otherwise installs Debian/Ubuntu's software driver
# (lavapipe, in mesa-vulkan-drivers) with the Vulkan loader. Needs root or sudo to install.
set -euo pipefail

have_vulkan() {
    ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1' || return 1
    ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json /usr/local/share/vulkan/icd.d/*.json 2>/dev/null | grep -q .
}

if have_vulkan; then
    exit 0
fi

echo "No Vulkan driver found: installing mesa-vulkan-drivers (lavapipe) and libvulkan1." >&2
if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
else
    echo "error: installing the Vulkan driver needs root or sudo; run as root:" >&2
    echo "  apt-get update && apt-get install -y mesa-vulkan-drivers libvulkan1" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
have_vulkan || { echo "error: still no Vulkan driver after installing mesa-vulkan-drivers" >&2; exit 1; }
