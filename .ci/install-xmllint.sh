#!/usr/bin/env bash
# Install libxml2's xmllint (Debian package `libxml2-utils`) and print the path of its binary.
# The tests validate the XML the tool writes (XES event logs) against the schemas in
# tests/schemas/ with it. Idempotent; see .ci/debian-tool.sh.
set -euo pipefail
source "$(dirname "$0")/debian-tool.sh"

# A binary "works" when it parses a one-element document.
works() {
    printf '<a/>\n' | "$1" --noout - >/dev/null 2>&1
}

debian_tool xmllint libxml2-utils works
