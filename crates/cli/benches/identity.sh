#!/usr/bin/env bash
# Proof that a speed-up changed no output byte: repairs every C3D file of the corpora with a
# reference `c3dfix` and with the current build, one file at a time, one thread each
# (RAYON_NUM_THREADS=1), compares the repaired files (cmp) and the full reports (JSON, with
# the output folder's name made the same), and reports the CPU time (user + sys) of each
# and their ratio.
#
# Usage: crates/cli/benches/identity.sh REFERENCE_BINARY [FOLDER...]
#   FOLDER defaults to c3d-samples, c3d-extra, c3d-more and c3d-fullbody ($C3D_SAMPLES,
#   $C3D_EXTRA, $C3D_MORE, $C3D_FULLBODY, else ../shared/...). OUT: where the outputs go
#   (target/identity). Exit status 1 when any output differs.
set -euo pipefail

root=$(cd "$(dirname "$0")/../../.." && pwd)
cd "$root"
[ $# -ge 1 ] || { echo "usage: $0 REFERENCE_BINARY [FOLDER...]" >&2; exit 2; }
ref=$(realpath "$1")
shift
[ -x "$ref" ] || { echo "identity.sh: $ref is not an executable" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "identity.sh: needs /usr/bin/time (GNU time)" >&2; exit 2; }
shared=$root/../shared
if [ $# -eq 0 ]; then
    set -- "${C3D_SAMPLES:-$shared/c3d-samples}" "${C3D_EXTRA:-$shared/c3d-extra}" \
        "${C3D_MORE:-$shared/c3d-more}" "${C3D_FULLBODY:-$shared/c3d-fullbody}"
fi
cargo build --release --locked -p c3dfix-cli --bin c3dfix >&2
new=$root/target/release/c3dfix
out=${OUT:-$root/target/identity}
rm -rf "$out"
mkdir -p "$out/ref" "$out/new"

# Runs one binary on one file into folder $3; prints "CPU_SECONDS EXIT".
run() {
    local bin=$1 file=$2 dir=$3 code=0
    RAYON_NUM_THREADS=1 /usr/bin/time -f '%U %S' -o "$dir/time" "$bin" repair "$file" \
        -o "$dir/out.c3d" --report "$dir/report.json" --force >"$dir/stdout" 2>"$dir/stderr" ||
        code=$?
    echo "$(tail -1 "$dir/time" | awk '{printf "%.3f", $1 + $2}') $code"
}

n=0 same=0 differ=0 tr=0 tn=0
while IFS= read -r -d '' f; do
    n=$((n + 1))
    # Alternate which binary runs first.
    if [ $((n % 2)) -eq 1 ]; then
        read -r sr cr < <(run "$ref" "$f" "$out/ref")
        read -r sn cn < <(run "$new" "$f" "$out/new")
    else
        read -r sn cn < <(run "$new" "$f" "$out/new")
        read -r sr cr < <(run "$ref" "$f" "$out/ref")
    fi
    tr=$(awk -v a="$tr" -v b="$sr" 'BEGIN{print a + b}')
    tn=$(awk -v a="$tn" -v b="$sn" 'BEGIN{print a + b}')
    problems=()
    if [ "$cr" != "$cn" ]; then
        problems+=("exit $cr against $cn")
    elif [ "$cr" = 0 ]; then
        cmp -s "$out/ref/out.c3d" "$out/new/out.c3d" || problems+=("repaired C3D differs")
        cmp -s <(sed "s|$out/ref|OUT|g" "$out/ref/report.json") \
            <(sed "s|$out/new|OUT|g" "$out/new/report.json") || problems+=("report differs")
    else
        cmp -s "$out/ref/stderr" "$out/new/stderr" || problems+=("error message differs")
    fi
    if [ ${#problems[@]} -eq 0 ]; then
        same=$((same + 1))
        verdict=same
    else
        differ=$((differ + 1))
        verdict=DIFFERS
    fi
    printf '%-8s %7s %7s  %s  %s\n' "$verdict" "$sr" "$sn" "${f#"$root"/../}" "${problems[*]:-}"
done < <(find "$@" -name '*.c3d' -type f -print0 | sort -z)

echo
echo "$n files: $same identical (repaired C3D and report), $differ differ"
awk -v a="$tr" -v b="$tn" 'BEGIN { printf "CPU (user+sys): reference %.2f s, current %.2f s, ratio %.2fx\n", a, b, (a > 0 ? b / a : 0) }'
[ "$differ" -eq 0 ]
