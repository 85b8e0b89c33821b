#!/usr/bin/env bash
# Proof of no change, every front: runs every command (every_command.sh) of a reference
# `c3dfix` and of the current build on every trial of the corpora, and compares everything
# they printed and wrote, byte for byte. Lists each command whose outputs differ on any trial.
#
# Usage: tests/identity/compare.sh REFERENCE_BINARY [FOLDER_OR_FILE...]
#   The default inputs are every corpus ($C3D_SAMPLES, $C3D_EXTRA, $C3D_FULLBODY, $C3D_MORE,
#   $C3D_LABS, $BVH_SAMPLES, else ../shared/...) and sample_c3d/. OUT: where both runs go
#   (target/identity-all). Exit status 1 when any output differs.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
[ $# -ge 1 ] || { echo "usage: $0 REFERENCE_BINARY [FOLDER_OR_FILE...]" >&2; exit 2; }
ref=$(realpath "$1")
shift
[ -x "$ref" ] || { echo "compare.sh: $ref is not an executable" >&2; exit 2; }
shared=$root/../shared
if [ $# -eq 0 ]; then
    set -- "${C3D_SAMPLES:-$shared/c3d-samples}" "${C3D_EXTRA:-$shared/c3d-extra}" \
        "${C3D_FULLBODY:-$shared/c3d-fullbody}" "${C3D_MORE:-$shared/c3d-more}" \
        "${C3D_LABS:-$shared/c3d-labs}" "${BVH_SAMPLES:-$shared/bvh-samples}" "$root/sample_c3d"
fi
(cd "$root" && cargo build --release --locked -p c3dfix-cli --bin c3dfix >&2)
new=$root/target/release/c3dfix
out=${OUT:-$root/target/identity-all}
rm -rf "$out"
"$root/tests/identity/every_command.sh" "$ref" "$out/ref" "$@"
"$root/tests/identity/every_command.sh" "$new" "$out/new" "$@"

# Per command, the trials where anything it printed or wrote differs (or exists on one side).
python3 - "$out" <<'PY'
import filecmp, pathlib, sys
out = pathlib.Path(sys.argv[1])
ref, new = out / "ref/runs", out / "new/runs"
def files(root):
    return {p.relative_to(root) for p in root.rglob("*") if p.is_file()}
a, b = files(ref), files(new)
differ = sorted(p for p in a | b if p not in a or p not in b or not filecmp.cmp(ref / p, new / p, shallow=False))
runs = sum(1 for p in a if p.name == "status")
by = {}
for p in differ:
    parts = p.parts
    # runs/batch/... is one command over every trial; the rest are TRIAL_FOLDER/TRIAL/COMMAND/FILE.
    cmd, trial = ("batch", "(all)") if parts[0] == "batch" else (parts[2], "/".join(parts[:2]))
    by.setdefault(cmd, set()).add(trial)
(out / "differences.txt").write_text("".join(f"{p}\n" for p in differ))
if not differ:
    print(f"{runs} command runs: every output identical")
    sys.exit(0)
for cmd, trials in sorted(by.items()):
    print(f"{len(trials):5d} trials differ in {cmd}")
print(f"{runs} command runs; the differing files are listed in {out / 'differences.txt'}")
sys.exit(1)
PY
