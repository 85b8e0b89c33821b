#!/usr/bin/env python3
"""Check that the workspace's rust-version is honest about what it builds with.

Our own code is checked by clippy's `incompatible_msrv` lint (it reads rust-version, so every
member must declare it). What clippy cannot see is the dependencies: each declares the
rust-version it needs, and none may need more than we claim. Run from the repository root.
"""

import json
import subprocess
import sys


def version(v):
    return tuple(int(x) for x in v.split("."))


def main():
    meta = json.loads(
        subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--locked"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    )
    members = set(meta["workspace_members"])
    ours = {p["name"]: p["rust_version"] for p in meta["packages"] if p["id"] in members}
    missing = [n for n, v in ours.items() if not v]
    if missing:
        sys.exit(f"rust-version: not declared by {', '.join(sorted(missing))}")
    if len(set(ours.values())) != 1:
        sys.exit(f"rust-version: members disagree: {ours}")
    msrv = next(iter(ours.values()))
    resolved = {n["id"] for n in meta["resolve"]["nodes"]}
    needs = sorted(
        (version(p["rust_version"]), p["name"], p["version"])
        for p in meta["packages"]
        if p["id"] in resolved and p["id"] not in members and p["rust_version"]
    )
    over = [n for n in needs if n[0] > version(msrv)]
    if over:
        lines = "\n".join(f"  {n} {v} needs {'.'.join(map(str, r))}" for r, n, v in over)
        sys.exit(f"rust-version {msrv} is lower than the dependencies need:\n{lines}")
    top = needs[-1] if needs else None
    print(
        f"rust-version {msrv}: every member declares it; the most any dependency needs is "
        + (f"{'.'.join(map(str, top[0]))} ({top[1]} {top[2]})" if top else "nothing")
    )


if __name__ == "__main__":
    main()
