#!/usr/bin/env bash
# Shared by the ensure-*.sh scripts: `apt_install WHAT PACKAGE...` installs Debian/Ubuntu
# packages as root or with sudo, or explains what to run when neither is possible.

# True if `ldconfig` knows the shared library $1 (no pipe, so `set -o pipefail` is safe).
have_library() {
    local cache
    cache=$(ldconfig -p 2>/dev/null || true)
    [[ "$cache" == *"$1"* ]]
}

apt_install() {
    local what=$1
    shift
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null 2>&1; then
            sudo="sudo"
        else
            echo "error: installing $what needs root or sudo; run as root:" >&2
            echo "  apt-get update && apt-get install -y $*" >&2
            exit 1
        fi
    fi
    echo "$what is missing: installing $*." >&2
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq "$@" >/dev/null
}
