#!/usr/bin/env bash
# Install asyncua (an OPC UA client and server library in pure Python, from PyPI) into a virtual
# environment in fbsynth's cache folder and print the environment's python.
#
# The environment lives at
#   ${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}/asyncua-venv
# and holds asyncua pinned to $VERSION, installed from wheels only for the packages with C code
# (cryptography, cffi), so nothing is compiled on CPython 3.11. The live-data tests start the
# simulated PLC of tests/opcua/plc_server.py with the printed path, read from $ASYNCUA_PYTHON.
#
# Idempotent: when the cached environment imports the pinned asyncua, nothing is done. Works as
# root on a fresh Debian 12 with no standard input (installs python3-venv with apt-get if the
# venv module is missing). stdout: exactly one line, the absolute path of the environment's
# python. Progress goes to stderr.
set -euo pipefail

readonly VERSION=2.1.0

log() { printf 'install-asyncua: %s\n' "$*" >&2; }
die() { log "error: $*"; exit 1; }

cache_root=${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}
mkdir -p "$cache_root"
cache_root=$(cd "$cache_root" && pwd -P)
venv=$cache_root/asyncua-venv
python=$venv/bin/python

# An environment "works" when it imports the pinned asyncua, not merely when python exists:
# this catches an interrupted pip run.
venv_works() {
    [[ -x $python ]] || return 1
    local got
    got=$("$python" -c 'import importlib.metadata as m; import asyncua; print(m.version("asyncua"))' 2>/dev/null) || return 1
    [[ $got == "$VERSION" ]]
}

if venv_works; then
    log "cached asyncua $VERSION works: $python"
    printf '%s\n' "$python"
    exit 0
fi

# Serialize concurrent installs: the second one waits and then finds the environment ready.
exec 9>"$cache_root/.asyncua-venv.lock"
flock 9
if venv_works; then
    log "asyncua $VERSION was installed meanwhile: $python"
    printf '%s\n' "$python"
    exit 0
fi

if command -v python3 >/dev/null; then
    host_python=$(command -v python3)
else
    die "python3 not found (asyncua needs CPython 3.9 or newer)"
fi
if ! "$host_python" -m venv --help >/dev/null 2>&1 || ! "$host_python" -c 'import ensurepip' 2>/dev/null; then
    command -v apt-get >/dev/null || die "python3 has no venv module and there is no apt-get"
    log "installing python3-venv with apt-get"
    export DEBIAN_FRONTEND=noninteractive
    apt-get install -y -q --no-install-recommends python3-venv </dev/null >&2 ||
        { apt-get update -q </dev/null >&2 &&
            apt-get install -y -q --no-install-recommends python3-venv </dev/null >&2; }
fi

# A half-built environment from an interrupted run is replaced, not patched.
rm -rf "$venv"
log "creating the environment with $host_python ($("$host_python" --version 2>&1))"
"$host_python" -m venv "$venv" </dev/null >&2

log "installing asyncua==$VERSION (under a minute)"
"$python" -m pip install --quiet --disable-pip-version-check --no-input \
    --only-binary cryptography,cffi \
    "asyncua==$VERSION" </dev/null >&2 || die "pip install asyncua==$VERSION failed"

venv_works || die "the new environment does not import asyncua $VERSION"
log "installed asyncua $VERSION: $python"
printf '%s\n' "$python"
