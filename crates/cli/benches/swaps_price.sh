#!/usr/bin/env bash
# The swap stage's price in `repair` (issue 34: with swaps on, within 1.2x of without): runs
# `c3dfix repair` whole-process on every C3D file of the corpora, one file at a time, one
# thread (RAYON_NUM_THREADS=1), with `--swaps off` and `--swaps fix` in alternating order,
# and reports the CPU time (user + sys, /usr/bin/time) of each summed over the files, their
# ratio, and the files where the stage costs most. Other repair options are the defaults.
#
# Usage: crates/cli/benches/swaps_price.sh [FOLDER...]
#   FOLDER defaults to the c3d-samples, c3d-more and c3d-fullbody corpora ($C3D_SAMPLES,
#   $C3D_MORE, $C3D_FULLBODY, else ../shared/...). OUT: where the per-file table goes
#   (target/swaps_price). ON: the mode measured against `--swaps off`, `fix` (the default:
#   the settled finds undone, jumps refilled, so the fill's work on them counts) or
#   `report` (finding alone: the default of `repair`). BIN: a `c3dfix` binary to measure
#   instead of building this tree's (to measure an earlier commit's build the same way).
set -euo pipefail

root=$(cd "$(dirname "$0")/../../.." && pwd)
cd "$root"
out=${OUT:-$root/target/swaps_price}
shared=$root/../shared
if [ $# -eq 0 ]; then
    set -- "${C3D_SAMPLES:-$shared/c3d-samples}" "${C3D_MORE:-$shared/c3d-more}" \
        "${C3D_FULLBODY:-$shared/c3d-fullbody}"
fi
[ -x /usr/bin/time ] || { echo "swaps_price.sh: needs /usr/bin/time (GNU time)" >&2; exit 2; }
if [ -n "${BIN:-}" ]; then
    bin=$BIN
else
    cargo build --release --locked -p c3dfix-cli --bin c3dfix >&2
    bin=$root/target/release/c3dfix
fi
on=${ON:-fix}
load0=$(cut -d' ' -f1-3 /proc/loadavg)
mkdir -p "$out"
table=$out/trials.tsv
printf 'file\toff_s\tfix_s\tratio\n' >"$table"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# CPU seconds of one repair, or nothing when it fails (a file that cannot be repaired is
# left out of both sums).
cpu() {
    local mode=$1 file=$2
    if RAYON_NUM_THREADS=1 /usr/bin/time -f '%U %S' -o "$tmp/t" \
        "$bin" repair "$file" -o "$tmp/out.c3d" --force --swaps "$mode" >/dev/null 2>&1; then
        awk '{printf "%.3f", $1 + $2}' "$tmp/t"
    fi
}

n=0
while IFS= read -r -d '' f; do
    if [ $((n % 2)) -eq 0 ]; then
        a=$(cpu off "$f"); b=$(cpu "$on" "$f")
    else
        b=$(cpu "$on" "$f"); a=$(cpu off "$f")
    fi
    n=$((n + 1))
    [ -n "$a" ] && [ -n "$b" ] || continue
    printf '%s\t%s\t%s\t%s\n' "${f#"$shared"/}" "$a" "$b" \
        "$(awk -v a="$a" -v b="$b" 'BEGIN{printf "%.2f", (a > 0 ? b / a : 0)}')" >>"$table"
done < <(find "$@" -name '*.c3d' -print0 | sort -z)

awk -F'\t' 'NR > 1 { off += $2; fix += $3; k++ }
    END { printf "%d files: --swaps off %.2f s CPU, --swaps %s %.2f s CPU, ratio %.3f\n", k, off, on, fix, fix / off }' on="$on" "$table"
echo "where the stage costs most (fix - off, s):"
awk -F'\t' 'NR > 1 { printf "%.3f\t%s\t%s\t%s\n", $3 - $2, $1, $2, $3 }' "$table" | sort -rn | head -5
echo "per-file table: $table"
echo "load average (1, 5, 15 min): at the start $load0, at the end $(cut -d' ' -f1-3 /proc/loadavg)"
