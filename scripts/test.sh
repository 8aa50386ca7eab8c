#!/usr/bin/env bash
# Set up everything the test suite needs on a fresh Debian machine, then run it.
#  - LinuxCNC's standalone interpreter rs274 (Debian package linuxcnc-uspace), the
#    reference for the differential tests, installed with apt-get when missing;
#  - Debian's chromium (headless, software WebGL) for the view.html tests, likewise;
#  - a virtual environment .venv with millpath and its test extras (PyPI), and the
#    optional step-brep extra when the platform has a wheel for it.
# Extra arguments go to pytest (e.g. scripts/test.sh -k interpret).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v rs274 >/dev/null 2>&1; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "== installing linuxcnc-uspace (rs274) with apt-get"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends linuxcnc-uspace >/dev/null
fi
if ! command -v chromium >/dev/null 2>&1; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "== installing chromium (view.html tests) with apt-get"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  echo "== creating .venv"
  "$PY" -m venv .venv
fi
echo "== installing millpath[test] into .venv"
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e ".[test]"
# STEP B-rep surfaces (OpenCASCADE, about 70 MB): their tests skip with a reason
# when this optional extra cannot be installed on the platform
echo "== installing the optional extra step-brep (cadquery-ocp)"
.venv/bin/python -m pip install -q -e ".[step-brep]" \
  || echo "== warning: cadquery-ocp is not installable here; the STEP surface tests will skip"

echo "== running the test suite"
exec .venv/bin/python -m pytest -q "$@"
