#!/usr/bin/env bash
# CI's proof of no change on a sample: every command of the current build on the bundled
# trials (sample_c3d/) and one BVH skeleton, digested file by file, against the digests
# committed in samples.sha256. A change meant to move an output regenerates them with
# --update, and the commit says which outputs moved and why; any other difference fails.
#
# Usage: tests/identity/check_samples.sh [--update] [BINARY]   (BINARY: target/release/c3dfix)
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
update=0
if [ "${1:-}" = --update ]; then
    update=1
    shift
fi
bin=${1:-$root/target/release/c3dfix}
bvh=${BVH_SAMPLES:-$root/../shared/bvh-samples}/fairmotion_sinusoidal.bvh
inputs=("$root"/sample_c3d/*.c3d)
if [ -f "$bvh" ]; then
    inputs+=("$bvh")
elif [ -n "${CI:-}" ]; then
    echo "check_samples.sh: $bvh is missing and CI requires it" >&2
    exit 1
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$root/tests/identity/every_command.sh" "$bin" "$out" "${inputs[@]}"
(cd "$out/runs" && find . -type f -print0 | sort -z | xargs -0 sha256sum) >"$out/digests"
expected=$root/tests/identity/samples.sha256
if [ "$update" = 1 ]; then
    cp "$out/digests" "$expected"
    echo "check_samples.sh: $(wc -l <"$expected") digests written to $expected"
    exit 0
fi
if ! diff -u "$expected" "$out/digests" >"$out/diff"; then
    echo "check_samples.sh: outputs differ from tests/identity/samples.sha256:" >&2
    grep -E '^[-+][0-9a-f]' "$out/diff" | awk '{print $1 " " $2}' | sed 's/^\(.\)[0-9a-f]* /\1 /' | sort -u -k2 >&2
    exit 1
fi
echo "check_samples.sh: every output of $(find "$out/runs" -name status | wc -l) command runs identical to the committed digests"
