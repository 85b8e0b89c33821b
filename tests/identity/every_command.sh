#!/usr/bin/env bash
# Every command of one `c3dfix` build on every given trial: what each printed (standard
# output and error), its exit status and every file it wrote, in one folder per trial and
# command. Two builds' folders compare with `diff -r` (identity_all.sh), and a build's
# folder on the bundled samples compares with the digests committed beside this script
# (check_samples.sh, run by CI): the proof that a change which should move no output moved
# none, for every front and not only `repair`.
#
# Usage: tests/identity/every_command.sh BINARY OUT FILE...
#   FILE: C3D or BVH files, or folders (walked for both). Each is linked into OUT/in/ under its own name, and every command
#   runs from OUT with that relative path, so two builds see the same paths and anything a
#   command prints about its input is the same text. One thread (RAYON_NUM_THREADS=1) so a
#   parallel reduction cannot reorder sums between runs.
set -uo pipefail

[ $# -ge 2 ] || { echo "usage: $0 BINARY OUT FILE..." >&2; exit 2; }
bin=$(realpath "$1")
out=$2
shift 2
[ -x "$bin" ] || { echo "every_command.sh: $bin is not an executable" >&2; exit 2; }
mkdir -p "$out/in" "$out/runs"
out=$(realpath "$out")
export RAYON_NUM_THREADS=1
files=()
for f in "$@"; do
    if [ -d "$f" ]; then
        while IFS= read -r -d '' g; do
            files+=("$(realpath "$g")")
        done < <(find "$f" -type f \( -iname '*.c3d' -o -iname '*.bvh' \) -print0 | sort -z)
    else
        files+=("$(realpath "$f")") || exit 2
    fi
done
set -- "${files[@]}"

# Runs one command of one trial in its own folder $1 (relative to runs/<trial>/), the
# command's arguments after it; records stdout, stderr, the exit status and leaves the
# files it wrote there. Output paths in arguments are written as @/NAME (inside the folder).
one() {
    local dir=$1
    shift
    local args=() a
    for a in "$@"; do
        args+=("${a//@\//$dir/}")
    done
    mkdir -p "$dir"
    "$bin" "${args[@]}" >"$dir/stdout" 2>"$dir/stderr" </dev/null
    echo $? >"$dir/status"
}

c3d_commands() {
    local f=$1 r=$2
    one "$r/info" info "$f"
    one "$r/info-json" info "$f" --json
    one "$r/gaps" gaps "$f" --json
    one "$r/swaps" swaps "$f" --json
    one "$r/forces" forces "$f"
    one "$r/forces-json" forces "$f" --json
    one "$r/forces-csv" forces "$f" -o @/forces.csv
    one "$r/events" events "$f" --json -o @/events.c3d
    one "$r/gait" gait "$f" --json
    one "$r/gait-detect" gait "$f" --detect --json
    one "$r/cycles" cycles "$f" --detect --forces -o @/cycles.csv
    one "$r/repair" repair "$f" -o @/repaired.c3d --report @/report.json --swaps fix --spikes hampel
    one "$r/repair-json" repair "$f" -o @/repaired.c3d --json
    one "$r/diff" diff "$f" "$r/repair/repaired.c3d" --json
    one "$r/convert" convert "$f" -o @/same.c3d
    one "$r/convert-dec-int" convert "$f" -o @/dec.c3d --processor dec --format int
    one "$r/convert-sgi-float" convert "$f" -o @/sgi.c3d --processor sgi --format float
    one "$r/export-csv" export "$f" --format csv -o @/points.csv
    one "$r/export-trc" export "$f" --format trc -o @/points.trc
    one "$r/export-json" export "$f" --format json -o @/points.json
    one "$r/export-mot" export "$f" --format mot -o @/grf.mot
    one "$r/export-opensim" export "$f" --format opensim --out-dir @/opensim
    # The first point's label, as `info --json` lists it (plot draws named markers).
    local first
    first=$(python3 -c 'import json,sys; m=json.load(sys.stdin).get("markers") or [{"label": ""}]; print(m[0]["label"])' \
        <"$r/info-json/stdout" 2>/dev/null)
    one "$r/plot" plot "$f" --marker "$first" -o @/plot.svg
    one "$r/plot-forces" plot "$f" --forces -o @/forces.svg
    one "$r/view" view "$f" -o @/view.html --detect-events
    one "$r/evaluate" evaluate "$f" --json --gaps-per-length 2 --seed 7
}

bvh_commands() {
    local f=$1 r=$2
    one "$r/info" info "$f"
    one "$r/info-json" info "$f" --json
    one "$r/keyframes" keyframes "$f" --keys 20 -o @/keys.bvh --json
    one "$r/view" view "$f" -o @/view.html
}

cd "$out" || exit 2
# Trials are kept apart by their folder's name too (two corpora may hold the same name).
for f in "$@"; do
    name=$(basename "$(dirname "$f")")/$(basename "$f")
    mkdir -p "in/$(dirname "$name")"
    ln -sf "$f" "in/$name"
    r=runs/$name
    rm -rf "$r"
    case "${name,,}" in
    *.bvh) bvh_commands "in/$name" "$r" ;;
    *) c3d_commands "in/$name" "$r" ;;
    esac
done
# The batch repair of every C3D trial given, with its JSON lines (named one by one: a folder
# walk does not follow the links in in/).
batch=()
for f in "$@"; do
    case "${f,,}" in *.c3d) batch+=("in/$(basename "$(dirname "$f")")/$(basename "$f")") ;; esac
done
rm -rf runs/batch
[ ${#batch[@]} -eq 0 ] || one runs/batch batch "${batch[@]}" --out-dir @/out --json --jobs 1
exit 0
