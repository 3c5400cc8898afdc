# Sourced by the install scripts of tools that come from Debian packages (cadical,
# xmllint): `debian_tool BINARY PACKAGE CHECK` prints the path of BINARY when `CHECK PATH`
# says it works, installing PACKAGE with apt-get first when it is missing or broken.
# Progress goes to stderr; stdout gets exactly one line, the absolute path. Idempotent: a
# working binary on the PATH costs nothing. Works as root on a fresh Debian 12 with no
# standard input.

log() { printf '%s: %s\n' "$(basename "$0" .sh)" "$*" >&2; }
die() { log "error: $*"; exit 1; }

debian_tool() {
    local binary=$1 package=$2 check=$3 path
    if path=$(command -v "$binary" 2>/dev/null) && "$check" "$path"; then
        log "$binary works: $path"
        printf '%s\n' "$path"
        return 0
    fi
    command -v apt-get >/dev/null ||
        die "$binary is missing and apt-get is not available: install $binary and put it on the PATH"
    log "installing the Debian package $package"
    export DEBIAN_FRONTEND=noninteractive
    local sudo=()
    [[ $(id -u) -eq 0 ]] || sudo=(sudo -n)
    "${sudo[@]}" apt-get update -qq >&2 || log "apt-get update failed; trying the install anyway"
    "${sudo[@]}" apt-get install -y -qq "$package" >&2 || die "apt-get install $package failed"
    path=$(command -v "$binary") || die "$binary is not on the PATH after the install"
    "$check" "$path" || die "$path does not work after the install"
    log "installed: $path"
    printf '%s\n' "$path"
}
