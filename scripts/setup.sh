#!/usr/bin/env bash
# Set up pedalrepro on a fresh machine with Python 3.11: a virtual environment from the hashed
# environment.lock, the package itself (editable), and the offline MathJax for the book (npm).
#   bash scripts/setup.sh            # environment only
#   bash scripts/setup.sh --browser  # also Debian's chromium + chromedriver (browser test; root)
#   bash scripts/setup.sh --cluster  # also Debian's slurm-wlm + munge (SLURM test; root)
#   (both flags may be given)
set -euo pipefail
cd "$(dirname "$0")/.."
BROWSER=0 CLUSTER=0
for arg in "$@"; do
  case "$arg" in
    --browser) BROWSER=1 ;;
    --cluster) CLUSTER=1 ;;
    *) echo "setup: unknown option $arg (use --browser, --cluster)" >&2; exit 2 ;;
  esac
done
APT_UPDATED=0
apt_install() {  # Debian packages, as root; apt-get update once
  if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null 2>&1; then
    echo "setup: cannot install $* (needs root and apt-get)" >&2
    return 0
  fi
  if [ "$APT_UPDATED" = 0 ]; then apt-get update -qq && APT_UPDATED=1; fi
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
}
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
if [ "$BROWSER" = 1 ] && ! command -v chromium >/dev/null 2>&1; then
  apt_install chromium chromium-driver
  command -v chromium >/dev/null 2>&1 \
    || echo "setup: chromium not found; install Debian's chromium for the browser test" >&2
fi
# SLURM for tests/workflow/test_cluster.py: daemons and clients only; the test writes its own slurm.conf
# and MUNGE key into a temporary folder and starts (and stops) the daemons itself.
if [ "$CLUSTER" = 1 ] && ! { [ -x /usr/sbin/slurmctld ] && [ -x /usr/sbin/munged ]; }; then
  apt_install slurm-wlm munge
  [ -x /usr/sbin/slurmctld ] \
    || echo "setup: SLURM not found; install Debian's slurm-wlm and munge for the cluster test" >&2
fi
echo "setup: done ($(.venv/bin/python --version))"
