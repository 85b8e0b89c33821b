#!/usr/bin/env bash
# The fills' price, paired against a fixed earlier build (issue 35): builds `c3dfix` at
# BASE (f5d5b64 unless given) in a git worktree under target/price-base (cached once built),
# builds the current one, then runs `c3dfix repair` whole-process on every C3D file of the
# corpora, one file at a time, one thread (RAYON_NUM_THREADS=1), both binaries on each file
# in alternating order, and reports the CPU time (user + sys, /usr/bin/time) of each, their
# ratio, the slowest trials, and where the current build's time goes (C3DFIX_PROFILE=1,
# see repair::profile), summed over the folder.
#
# Usage: crates/cli/benches/price.sh [FOLDER...]
#   FOLDER defaults to the c3d-samples, c3d-more and c3d-fullbody corpora ($C3D_SAMPLES,
#   $C3D_MORE, $C3D_FULLBODY, else ../shared/...). Environment: BASE (a commit), ROUNDS
#   (runs per binary and file, 1; the smallest CPU time counts), OUT (where the per-file
#   table and profile go, target/price). Whole-process timing, so it is a script, not a
#   criterion bench: it measures what a user waits for, reading and writing included.
set -euo pipefail

root=$(cd "$(dirname "$0")/../../.." && pwd)
cd "$root"
base=${BASE:-f5d5b64}
rounds=${ROUNDS:-1}
out=${OUT:-$root/target/price}
shared=$root/../shared
if [ $# -eq 0 ]; then
    set -- "${C3D_SAMPLES:-$shared/c3d-samples}" "${C3D_MORE:-$shared/c3d-more}" \
        "${C3D_FULLBODY:-$shared/c3d-fullbody}"
fi
[ -x /usr/bin/time ] || { echo "price.sh: needs /usr/bin/time (GNU time)" >&2; exit 2; }

# The base build, in its own worktree and target folder (kept between runs).
bdir=$root/target/price-base
old=$bdir/c3dfix-$base
if [ ! -x "$old" ]; then
    if [ ! -d "$bdir/src" ]; then
        mkdir -p "$bdir"
        git worktree add --detach "$bdir/src" "$base" >&2
    fi
    # Seeding the base's target folder with the current one's dependencies saves building
    # them again (only the workspace's own crates differ).
    if [ ! -d "$bdir/target/release/deps" ] && [ -d "$root/target/release/deps" ]; then
        mkdir -p "$bdir/target/release"
        cp -a "$root/target/release/deps" "$root/target/release/build" \
            "$root/target/release/.fingerprint" "$bdir/target/release/"
    fi
    (cd "$bdir/src" && CARGO_TARGET_DIR=$bdir/target cargo build --release --locked \
        -p c3dfix-cli --bin c3dfix >&2)
    cp "$bdir/target/release/c3dfix" "$old"
fi
cargo build --release --locked -p c3dfix-cli --bin c3dfix >&2
new=$root/target/release/c3dfix
base_id=$(git -C "$root" rev-parse --short "$base")
head_id=$(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet HEAD || echo "+dirty")

mkdir -p "$out"
table=$out/trials.tsv
prof=$out/profile.tsv
: >"$prof"
printf 'file\told_s\tnew_s\tratio\told_exit\tnew_exit\n' >"$table"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# CPU seconds (user + sys) of one whole-process repair; prints "SECONDS EXIT".
run() {
    local bin=$1 file=$2 best="" code=0 r
    for ((r = 0; r < rounds; r++)); do
        code=0
        RAYON_NUM_THREADS=1 /usr/bin/time -f '%U %S' -o "$tmp/time" \
            "$bin" repair "$file" -o "$tmp/out.c3d" --force >/dev/null 2>"$tmp/err" || code=$?
        local s
        s=$(tail -1 "$tmp/time" | awk '{printf "%.3f", $1 + $2}')
        if [ -z "$best" ] || awk -v a="$s" -v b="$best" 'BEGIN{exit !(a < b)}'; then best=$s; fi
    done
    echo "$best $code"
}

n=0
while IFS= read -r -d '' f; do
    n=$((n + 1))
    # Alternate which binary runs first, so neither always finds the caches warm.
    if [ $((n % 2)) -eq 1 ]; then
        read -r so co < <(run "$old" "$f")
        read -r sn cn < <(run "$new" "$f")
    else
        read -r sn cn < <(run "$new" "$f")
        read -r so co < <(run "$old" "$f")
    fi
    # The profile, from one more run of the current build (not timed above).
    RAYON_NUM_THREADS=1 C3DFIX_PROFILE=1 "$new" repair "$f" -o "$tmp/out.c3d" --force \
        >/dev/null 2>"$tmp/prof" || true
    grep '^profile' "$tmp/prof" | awk -v f="$f" '{ print f "\t" $0 }' >>"$prof" || true
    ratio=$(awk -v a="$so" -v b="$sn" 'BEGIN{ if (a > 0) printf "%.2f", b / a; else print "-" }')
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$f" "$so" "$sn" "$ratio" "$co" "$cn" >>"$table"
    printf '%-90s %8s %8s %6s\n' "${f#"$root"/../}" "$so" "$sn" "$ratio" >&2
done < <(find "$@" -name '*.c3d' -type f -print0 | sort -z)

echo
echo "c3dfix repair, whole process, one thread: $base_id (old) against $head_id (new), $n files"
awk -F'\t' 'NR > 1 { o += $2; w += $3 } END {
    printf "CPU (user+sys): old %.2f s, new %.2f s, ratio %.2fx\n", o, w, (o > 0 ? w / o : 0) }' "$table"
echo
# (awk, not head: head closing the pipe early would end the script under pipefail.)
echo "Slowest trials (new build):"
tail -n +2 "$table" | sort -t$'\t' -k3,3 -g -r | awk 'NR <= 10' |
    awk -F'\t' '{ printf "  %7.2f s (old %6.2f s, %6sx)  %s\n", $3, $2, $4, $1 }' |
    sed "s|$root/../||"
echo
echo "Where the new build's time goes (summed over threads and files; C3DFIX_PROFILE=1):"
awk -F'\t' '$3 == "work" { c[$4] += $5; s[$4] += $6 } END {
    for (k in s) printf "  %9.3f s %9d calls  %s\n", s[k], c[k], k }' "$prof" | sort -g -r
echo "Per gap length (frames; first and second pass each count):"
awk -F'\t' '$3 == "gaps" { c[$4] += $5; s[$4] += $6 } END {
    for (k in s) printf "  %-8s %7d gap fills %9.3f s  %8.2f ms each\n", k, c[k], s[k], 1000 * s[k] / c[k] }' \
    "$prof" | sort -n
echo "Models and artificial gaps:"
awk -F'\t' '$3 == "count" { c[$4] += $5 } END { for (k in c) printf "  %9d  %s\n", c[k], k }' \
    "$prof" | sort -g -r
echo
echo "Per-file table: $table; per-file profile: $prof"
