#!/usr/bin/env bash
# Install NuSMV 2.5.4 (BDD engine only) into fbsynth's cache folder and print its path.
#
# NuSMV is not packaged by Debian. Its 2.5.4 source tree (LGPL 2.1) ships inside the PyPI
# source distribution pynusmv==1.0rc8, so this script fetches that sdist with pip, builds
# NuSMV from it and copies the binary to
#   ${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}/nusmv-2.5.4/bin/NuSMV
# which is one of the places `synth` looks for it (after --nusmv, $NUSMV and PATH).
#
# Idempotent: when the cached binary exists and runs, nothing is done. Works as root on a
# fresh Debian 12 with no standard input (installs bison and flex with apt-get if missing).
# stdout: exactly one line, the absolute path of the binary. Progress goes to stderr.
set -euo pipefail

readonly VERSION=2.5.4
readonly SDIST=pynusmv==1.0rc8
readonly TARBALL_IN_SDIST=pynusmv-1.0rc8/dependencies/NuSMV/NuSMV-${VERSION}.tar.gz

log() { printf 'install-nusmv: %s\n' "$*" >&2; }
die() { log "error: $*"; exit 1; }

cache_root=${FBSYNTH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/fbsynth}
mkdir -p "$cache_root"
cache_root=$(cd "$cache_root" && pwd -P)
bin_dir=$cache_root/nusmv-$VERSION/bin
binary=$bin_dir/NuSMV

# A binary "runs" when it checks a one-line model: this catches truncated copies and
# missing shared libraries, which `-h` alone would not (NuSMV -h exits nonzero anyway).
binary_works() {
    [[ -x $1 ]] || return 1
    local out
    out=$(printf 'MODULE main\nVAR b : boolean;\nLTLSPEC G (b | !b)\n' |
        "$1" /dev/stdin 2>/dev/null) || return 1
    [[ $out == *"is true"* ]]
}

if binary_works "$binary"; then
    log "cached NuSMV $VERSION works: $binary"
    printf '%s\n' "$binary"
    exit 0
fi

# Serialize concurrent installs (parallel CI jobs, two terminals): the second one waits
# and then finds the binary in place.
mkdir -p "$bin_dir"
exec 9>"$cache_root/nusmv-$VERSION/.install.lock"
flock 9
if binary_works "$binary"; then
    log "NuSMV $VERSION was installed meanwhile: $binary"
    printf '%s\n' "$binary"
    exit 0
fi

export DEBIAN_FRONTEND=noninteractive
apt_updated=no
apt_install() {
    local missing=() pkg
    for pkg in "$@"; do
        dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed' ||
            missing+=("$pkg")
    done
    if ((${#missing[@]} == 0)); then
        return 0
    fi
    if ! command -v apt-get >/dev/null; then
        die "missing ${missing[*]} and no apt-get to install them"
    fi
    log "installing ${missing[*]} with apt-get"
    # Update the package lists only when they cannot serve the install (fresh image).
    if ! apt-get install -y -q --no-install-recommends "${missing[@]}" </dev/null >&2; then
        if [[ $apt_updated == no ]]; then
            apt_updated=yes
            apt-get update -q </dev/null >&2
            apt-get install -y -q --no-install-recommends "${missing[@]}" </dev/null >&2
        else
            die "apt-get install ${missing[*]} failed"
        fi
    fi
}

# Build tools, by the command each package provides; one apt-get call for all that are missing.
needed=()
for pair in bison:bison flex:flex make:make gcc:gcc g++:g++; do
    command -v "${pair%%:*}" >/dev/null || needed+=("${pair#*:}")
done
if ((${#needed[@]} > 0)); then
    apt_install "${needed[@]}"
fi

if command -v pip3 >/dev/null; then
    pip=(pip3)
elif command -v python3 >/dev/null && python3 -m pip --version >/dev/null 2>&1; then
    pip=(python3 -m pip)
else
    apt_install python3-pip
    pip=(python3 -m pip)
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/install-nusmv.XXXXXX")
trap 'rm -rf "$work"' EXIT

log "downloading $SDIST"
"${pip[@]}" download --quiet --no-deps --no-binary :all: --disable-pip-version-check \
    -d "$work/sdist" "$SDIST" </dev/null >&2
sdist=$(find "$work/sdist" -maxdepth 1 -name 'pynusmv-*.tar.gz' | head -n 1)
[[ -n $sdist ]] || die "pip did not produce the pynusmv sdist"

log "unpacking NuSMV $VERSION"
tar -xzf "$sdist" -C "$work" "$TARBALL_IN_SDIST"
tar -xzf "$work/$TARBALL_IN_SDIST" -C "$work"
src=$work/NuSMV-$VERSION
[[ -d $src/nusmv && -d $src/cudd-2.4.1.1 ]] || die "unexpected layout in NuSMV-$VERSION.tar.gz"

# glibc dropped `union wait` long ago; the variable only receives waitpid's status word.
pipefork=$src/cudd-2.4.1.1/util/pipefork.c
grep -q 'union wait status;' "$pipefork" || die "source fix target not found in $pipefork"
sed -i 's/union wait status;/int status;/' "$pipefork"

log "configuring (readline and expat disabled)"
cd "$src/nusmv"
./configure CFLAGS="-O2 -w" --disable-readline --disable-expat </dev/null >"$work/configure.log" 2>&1 ||
    { tail -n 40 "$work/configure.log" >&2; die "configure failed (log above)"; }

log "building (about a minute on 2 cores)"
make -j2 </dev/null >"$work/make.log" 2>&1 ||
    { tail -n 40 "$work/make.log" >&2; die "make failed (log above)"; }
[[ -x $src/nusmv/NuSMV ]] || die "build finished without nusmv/NuSMV"
binary_works "$src/nusmv/NuSMV" || die "the freshly built NuSMV does not check a trivial model"

# Copy under a temporary name in the target folder, then rename: readers see either no
# binary or a complete one.
tmp_bin=$(mktemp "$bin_dir/.NuSMV.XXXXXX")
cp "$src/nusmv/NuSMV" "$tmp_bin"
chmod 755 "$tmp_bin"
mv -f "$tmp_bin" "$binary"

log "installed NuSMV $VERSION: $binary"
printf '%s\n' "$binary"
