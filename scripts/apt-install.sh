#!/usr/bin/env bash
# Shared by the ensure-*.sh scripts: `apt_install WHAT [APT-OPTION...] PACKAGE...` installs
# Debian/Ubuntu packages as root or with sudo, or explains what to run when neither is possible.

# True if `ldconfig` knows the shared library $1 (no pipe, so `set -o pipefail` is safe).
have_library() {
    local cache
    cache=$(ldconfig -p 2>/dev/null || true)
    [[ "$cache" == *"$1"* ]]
}

# Runs its arguments as root: directly, with sudo, or not at all (explaining what to run).
as_root() {
    if [ "$(id -u)" -eq 0 ]; then
        "$@"
    elif command -v sudo >/dev/null 2>&1; then
        sudo "$@"
    else
        echo "error: this step needs root or sudo; run as root:" >&2
        echo "  $*" >&2
        exit 1
    fi
}

apt_install() {
    local what=$1
    shift
    echo "$what is missing: installing $*." >&2
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update -qq
    as_root apt-get install -y -qq "$@" >/dev/null
}
