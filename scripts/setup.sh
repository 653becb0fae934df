#!/usr/bin/env bash
# Set up pedalrepro on a fresh machine with Python 3.11: a virtual environment from the hashed
# environment.lock, the package itself (editable), and the offline MathJax for the book (npm).
#   bash scripts/setup.sh            # environment only
#   bash scripts/setup.sh --browser  # also Debian's chromium + chromedriver (browser test; root)
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3.11}
command -v "$PY" >/dev/null 2>&1 || PY=python3
if [ ! -x .venv/bin/python ]; then
  "$PY" -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check --upgrade "pip>=24"
.venv/bin/python -m pip install --quiet --disable-pip-version-check --require-hashes -r environment.lock
.venv/bin/python -m pip install --quiet --disable-pip-version-check --no-deps -e .
if [ -f package-lock.json ]; then
  npm ci --no-audit --no-fund --loglevel=error
fi
if [ "${1:-}" = "--browser" ] && ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null
  else
    echo "setup: chromium not found; install Debian's chromium for the browser test" >&2
  fi
fi
echo "setup: done ($(.venv/bin/python --version))"
