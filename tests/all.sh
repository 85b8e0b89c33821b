#!/usr/bin/env bash
# Every test: the Rust workspace, then the Python package's wheel, built with maturin and
# installed with pip into a virtual environment (target/venv, or $C3DFIX_VENV) as a user would
# install it, and its pytest suite (with Dask, for the run across worker processes).
# A fresh machine needs only cargo, python3 and the package registries.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
# Tests that skip for want of a corpus (or of Chromium) say so through testkit into this
# file; the harness would hide the message, so the count is printed at the end.
skiplog="$root/target/skipped-tests.txt"
mkdir -p "$root/target"
: > "$skiplog"
export C3DFIX_SKIP_LOG="$skiplog"
cargo test --workspace --release --locked
# Every command's outputs on the bundled trials, byte for byte against the committed digests.
cargo build --release --locked -p c3dfix-cli --bin c3dfix
bash tests/identity/check_samples.sh
venv="${C3DFIX_VENV:-$root/target/venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check numpy pytest ezc3d maturin opensim 'dask[distributed]'
# The wheel users get (abi3, release), built once into a fresh folder and installed as a user
# installs it; the installed package is tested, not the source tree.
wheels="$root/target/wheels-test"
rm -rf "$wheels"
"$venv/bin/maturin" build --release --locked -m crates/python/Cargo.toml --out "$wheels"
"$venv/bin/python" -m pip install -q --disable-pip-version-check --force-reinstall --no-deps "$wheels"/c3dfix-*.whl
cd crates/python/tests
C3DFIX_BIN="${C3DFIX_BIN:-$root/target/release/c3dfix}" "$venv/bin/python" -m pytest -q -p no:cacheprovider -rs .
skips=$(cut -f1 "$skiplog" | sort -u | grep -c . || true)
if [ "$skips" -gt 0 ]; then
  echo "Rust: $skips tests skipped some or all of their work for want of a corpus or tool:" >&2
  cut -f2 "$skiplog" | sort | uniq -c | sed 's/^/  /' >&2
else
  echo "Rust: no test skipped for want of a corpus or tool" >&2
fi
