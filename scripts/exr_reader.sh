#!/usr/bin/env bash
# A Python with a third-party EXR reader, the OpenEXR project's own bindings (PyPI `OpenEXR`, with
# numpy), for scripts/check_exr.py and the test that runs it (tests/suite/exr_third_party.rs), and
# the reference JSON Schema validator (PyPI `jsonschema`) for scripts/check_schema.py, which the
# tests run on every report.json they make; and the Python package's build and tests (issue 60:
# maturin builds `wavetrace` into this venv, pytest runs python/tests, matplotlib and pandas for
# the README's example and `to_pandas()`): a venv under the target directory, made once.
# Installs python3 and python3-venv (Debian) where they are missing. Prints the venv's python;
# scripts/test.sh exports it as WAVETRACE_EXR_PYTHON.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${CARGO_TARGET_DIR:-target}/exr-venv"
py="$venv/bin/python"
modules='import OpenEXR, numpy, jsonschema, maturin, pytest, matplotlib, pandas'
if "$py" -c "$modules" 2>/dev/null; then
  echo "$(cd "$(dirname "$py")" && pwd)/python"
  exit 0
fi
if ! { command -v python3 >/dev/null && python3 -m venv --help >/dev/null 2>&1 && python3 -c 'import ensurepip' 2>/dev/null; }; then
  echo "exr_reader: installing python3 and python3-venv" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq >&2
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv >/dev/null
fi
rm -rf "$venv"
python3 -m venv "$venv" >&2
"$venv/bin/pip" install --quiet --disable-pip-version-check 'OpenEXR==3.5.3' 'numpy>=1.26' 'jsonschema==4.25.1' \
  'maturin==1.16.0' 'pytest==9.2.0' 'matplotlib==3.11.2' 'pandas==3.1.1' >&2
"$py" -c "$modules" >&2
echo "$(cd "$(dirname "$py")" && pwd)/python"
