#!/usr/bin/env bash
# Set up everything the test suite needs on a fresh Debian machine, then run it.
#  - LinuxCNC's standalone interpreter rs274 (Debian package linuxcnc-uspace), the
#    reference for the differential tests, installed with apt-get when missing;
#  - Debian's chromium (headless, software WebGL) for the view.html tests, likewise;
#  - node and npm, likewise: the tests install the npm package gcode-toolpath (a GRBL
#    program reader) into ~/.cache/millpath-tests on first use;
#  - a virtual environment .venv (the demo command's, when it exists) with millpath
#    installed editable and its test extras from PyPI, OpenCASCADE (cadquery-ocp)
#    included.
# Under CI=true every test must run: a skip is a failure (tests/conftest.py).
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

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "== installing nodejs and npm (the GRBL reader gcode-toolpath) with apt-get"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  echo "== creating .venv"
  "$PY" -m venv .venv
fi
echo "== installing millpath[test] into .venv"
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e ".[test]"
# the editable install must be the millpath every folder sees (no stale copy left in
# site-packages by an earlier install shadows it)
here=$(pwd)
(cd / && "$here/.venv/bin/python" -c "import millpath, sys; sys.exit(0 if millpath.__file__ else 1)") \
  || { echo "== error: .venv imports a broken millpath from outside the checkout"; exit 1; }

echo "== running the test suite"
# two workers (CI has 2 cores); a module's tests stay on one worker, so its fixtures
# (planned examples) are built once; the slowest tests are listed at the end. A worker
# that dies (killed for memory, a native crash) is not replaced: the run reports the
# test it was running and ends (xdist's module scheduler can wait forever for a
# replaced worker).
exec .venv/bin/python -m pytest -q -n "${MILLPATH_TEST_WORKERS:-2}" --dist loadscope \
    --max-worker-restart=0 --durations=15 "$@"
