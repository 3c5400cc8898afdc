#!/usr/bin/env bash
# Install libxml2's xmllint (Debian package `libxml2-utils`) and print the path of its binary.
# The tests validate the XML the tool writes (XES event logs) against the schemas in
# tests/schemas/ with it.
#
# Idempotent: when `xmllint` on the PATH validates a one-element document, nothing is done.
# Works as root on a fresh Debian 12 with no standard input. stdout: exactly one line, the
# absolute path of the binary. Progress goes to stderr.
set -euo pipefail

log() { printf 'install-xmllint: %s\n' "$*" >&2; }
die() { log "error: $*"; exit 1; }

works() {
    printf '<a/>\n' | "$1" --noout - >/dev/null 2>&1
}

if path=$(command -v xmllint 2>/dev/null) && works "$path"; then
    log "xmllint works: $path"
    printf '%s\n' "$path"
    exit 0
fi

command -v apt-get >/dev/null || die "xmllint is missing and apt-get is not available: install libxml2's xmllint and put it on the PATH"
log "installing the Debian package libxml2-utils"
export DEBIAN_FRONTEND=noninteractive
if [[ $(id -u) -eq 0 ]]; then sudo=(); else sudo=(sudo -n); fi
"${sudo[@]}" apt-get update -qq >&2 || log "apt-get update failed; trying the install anyway"
"${sudo[@]}" apt-get install -y -qq libxml2-utils >&2 || die "apt-get install libxml2-utils failed"
path=$(command -v xmllint) || die "xmllint is not on the PATH after the install"
works "$path" || die "$path does not parse a one-element document"
log "installed: $path"
printf '%s\n' "$path"
