#!/usr/bin/env bash
# The project's test command (README): every test, the GUI ones included.
set -euo pipefail
cd "$(dirname "$0")"
cargo test --release "$@"
