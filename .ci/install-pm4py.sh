#!/usr/bin/env bash
# Install pm4py (process mining for Python, from PyPI), pinned, into a virtual environment in
# fbsynth's cache folder and print the environment's python (see .ci/python-venv.sh). The
# interoperability test reads the printed path from $PM4PY_PYTHON.
set -euo pipefail
source "$(dirname "$0")/python-venv.sh"

python_venv pm4py 2.7.11.11 'print(pm4py.__version__)' \
    numpy,pandas,scipy,lxml,matplotlib,contourpy,kiwisolver,pillow,cvxopt
