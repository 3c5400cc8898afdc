#!/usr/bin/env bash
# Install CaDiCaL (a SAT solver, Debian package `cadical`) and print the path of its binary.
# The tests solve the CNF files `synth infer --dump-cnf` writes with it, to check varisat's
# verdicts with an independent solver. Idempotent; see .ci/debian-tool.sh.
set -euo pipefail
source "$(dirname "$0")/debian-tool.sh"

# A binary "works" when it says a satisfiable one-clause formula is satisfiable (exit 10).
works() {
    local status=0
    printf 'p cnf 1 1\n1 0\n' | "$1" -q >/dev/null 2>&1 || status=$?
    [[ $status -eq 10 ]]
}

debian_tool cadical cadical works
