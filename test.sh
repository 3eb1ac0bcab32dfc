#!/usr/bin/env bash
# The project's test command (README): every test, the GUI ones included.
set -euo pipefail
cd "$(dirname "$0")"
cargo test --release "$@"
# The Python package's tests (python/tests), where the package is installed for the interpreter
# $TSM_PYTHON (default python3): `pip install ./python[test]`, as .ci/run does.
py="${TSM_PYTHON:-python3}"
if "$py" -c "import tsm_contact, pytest" 2>/dev/null; then
    "$py" -m pytest -q python/tests
else
    echo "test.sh: the Python tests need the package: pip install './python[test]' (skipped)"
fi
