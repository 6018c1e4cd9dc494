#!/usr/bin/env bash
# Shared by the ensure-*.sh scripts: `apt_install WHAT [APT-OPTION...] PACKAGE...` installs
# Debian/Ubuntu packages as root or with sudo, or explains what to run when neither is possible.

# True if `ldconfig` knows the shared library $1 (no pipe, so `set -o pipefail` is safe).
have_library() {
    local cache
    cache=$(ldconfig -p 2>/dev/null || true)
    [[ "$cache" == *"$1"* ]]
}

# True if this script can act as root (it is root, or sudo exists).
can_be_root() {
    [ "$(id -u)" -eq 0 ] || command -v sudo >/dev/null 2>&1
}

# Stops with `$1` (what to do as root) unless this script can act as root.
require_root() {
    can_be_root && return
    echo "error: this step needs root or sudo; run as root:" >&2
    echo "  $1" >&2
    exit 1
}

# Runs its arguments as root (directly, or with sudo); call require_root first.
as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

apt_install() {
    local what=$1
    shift
    require_root "apt-get update && apt-get install -y $*"
    echo "$what is missing: installing $*." >&2
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update -qq
    as_root apt-get install -y -qq "$@" >/dev/null
}
