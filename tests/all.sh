#!/usr/bin/env bash
# Every test: the Rust workspace, then the Python package, installed with pip into a virtual
# environment (target/venv, or $C3DFIX_VENV) as a user would install it, and its pytest suite.
# A fresh machine needs only cargo, python3 and the package registries.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
cargo test --workspace --release --locked
venv="${C3DFIX_VENV:-$root/target/venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check numpy pytest ezc3d
"$venv/bin/python" -m pip install -q --disable-pip-version-check --force-reinstall --no-deps ./crates/python
# The installed package is tested, not the source tree.
cd crates/python/tests
C3DFIX_BIN="${C3DFIX_BIN:-$root/target/release/c3dfix}" "$venv/bin/python" -m pytest -q -p no:cacheprovider .
