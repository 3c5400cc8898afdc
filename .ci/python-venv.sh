#!/usr/bin/env bash
# Sourced by the install scripts of the Python tools (install-pm4py.sh, install-asyncua.sh):
#   python_venv PACKAGE VERSION VERSION_EXPR ONLY_BINARY
# installs PACKAGE==VERSION from PyPI into a virtual environment in fbsynth's cache folder,
#   ${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}/PACKAGE-venv
# and prints the environment's python. VERSION_EXPR is Python code, run after `import PACKAGE`,
# that prints the installed version; ONLY_BINARY lists the packages with C code taken from
# wheels only, so nothing is compiled on CPython 3.11.
#
# Idempotent: when the cached environment imports the pinned version, nothing is done. Works as
# root on a fresh Debian 12 with no standard input (installs python3-venv with apt-get if the
# venv module is missing). stdout: exactly one line, the absolute path of the environment's
# python. Progress goes to stderr.

python_venv() {
    local package=$1 version=$2 version_expr=$3 only_binary=$4
    log() { printf 'install-%s: %s\n' "$package" "$*" >&2; }
    die() { log "error: $*"; exit 1; }

    local cache_root
    cache_root=${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}
    mkdir -p "$cache_root"
    cache_root=$(cd "$cache_root" && pwd -P)
    local venv=$cache_root/$package-venv
    local python=$venv/bin/python

    # An environment "works" when it imports the pinned version, not merely when python
    # exists: this catches an interrupted pip run.
    venv_works() {
        [[ -x $python ]] || return 1
        local got
        got=$("$python" -c "import $package; $version_expr" 2>/dev/null) || return 1
        [[ $got == "$version" ]]
    }

    if venv_works; then
        log "cached $package $version works: $python"
        printf '%s\n' "$python"
        return 0
    fi

    # Serialize concurrent installs: the second one waits and then finds the environment ready.
    exec 9>"$cache_root/.$package-venv.lock"
    flock 9
    if venv_works; then
        log "$package $version was installed meanwhile: $python"
        printf '%s\n' "$python"
        return 0
    fi

    local host_python
    host_python=$(command -v python3) || die "python3 not found ($package needs CPython 3.9 or newer)"
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

    log "installing $package==$version (about a minute)"
    "$python" -m pip install --quiet --disable-pip-version-check --no-input \
        --only-binary "$only_binary" \
        "$package==$version" </dev/null >&2 || die "pip install $package==$version failed"

    venv_works || die "the new environment does not import $package $version"
    log "installed $package $version: $python"
    printf '%s\n' "$python"
}
