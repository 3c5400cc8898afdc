#!/usr/bin/env bash
# Install CaDiCaL (a SAT solver, Debian package `cadical`) and print the path of its binary.
# The tests solve the CNF files `synth infer --dump-cnf` writes with it, to check varisat's
# verdicts with an independent solver.
#
# Idempotent: when `cadical` on the PATH answers a one-clause formula, nothing is done. Works
# as root on a fresh Debian 12 with no standard input. stdout: exactly one line, the absolute
# path of the binary. Progress goes to stderr.
set -euo pipefail

log() { printf 'install-cadical: %s\n' "$*" >&2; }
die() { log "error: $*"; exit 1; }

# A binary "works" when it says a satisfiable one-clause formula is satisfiable (exit 10).
works() {
    local status=0
    printf 'p cnf 1 1\n1 0\n' | "$1" -q >/dev/null 2>&1 || status=$?
    [[ $status -eq 10 ]]
}

if path=$(command -v cadical 2>/dev/null) && works "$path"; then
    log "cadical works: $path"
    printf '%s\n' "$path"
    exit 0
fi

command -v apt-get >/dev/null || die "cadical is missing and apt-get is not available: install CaDiCaL and put it on the PATH"
log "installing the Debian package cadical"
export DEBIAN_FRONTEND=noninteractive
if [[ $(id -u) -eq 0 ]]; then sudo=(); else sudo=(sudo -n); fi
"${sudo[@]}" apt-get update -qq >&2 || log "apt-get update failed; trying the install anyway"
"${sudo[@]}" apt-get install -y -qq cadical >&2 || die "apt-get install cadical failed"
path=$(command -v cadical) || die "cadical is not on the PATH after the install"
works "$path" || die "$path does not solve a one-clause formula"
log "installed: $path"
printf '%s\n' "$path"
