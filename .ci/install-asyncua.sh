#!/usr/bin/env bash
# Install asyncua (an OPC UA client and server library in pure Python, from PyPI), pinned, into
# a virtual environment in fbsynth's cache folder and print the environment's python (see
# .ci/python-venv.sh). The live-data tests start the simulated PLC of tests/opcua/plc_server.py
# with the printed path, read from $ASYNCUA_PYTHON.
set -euo pipefail
source "$(dirname "$0")/python-venv.sh"

python_venv asyncua 2.1.0 \
    'import importlib.metadata as m; print(m.version("asyncua"))' cryptography,cffi
