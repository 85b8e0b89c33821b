#!/usr/bin/env python3
"""Prints the import graph of one folder of a Rust crate: per module, the modules of the
same folder (and of the crate) its non-test code imports with `use super::` / `use crate::`.
An import of an item `mod.rs` re-exports counts as an import of `mod`, which is what a
reader has to open.

Usage: scripts/imports.py [FOLDER]   (default: crates/repair/src/fill)
"""
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent
folder = root / (sys.argv[1] if len(sys.argv) > 1 else "crates/repair/src/fill")
src = next(p for p in [folder, *folder.parents] if p.name == "src")


def module_path(f):
    """`fill::auto::holes` for src/fill/auto/holes.rs (`fill` for src/fill/mod.rs)."""
    parts = list(f.relative_to(src).with_suffix("").parts)
    if parts[-1] == "mod":
        parts.pop()
    return parts


def reexports(mod, public_only=False):
    """Items the module's file imports, by name: the path they come from. Its children see
    its private imports too (`super::linear` in auto/steps.rs is what auto/mod.rs imports
    as `linear`); `public_only` keeps its re-exports (`pub use`, `pub(crate) use`)."""
    f = src.joinpath(*mod).with_suffix(".rs")
    if not f.exists():
        f = src.joinpath(*mod, "mod.rs")
    if not f.exists():
        return {}
    text = code(f.read_text())
    out = {}
    vis = r"pub(?:\([^)]*\))?\s+" if public_only else r"(?:pub(?:\([^)]*\))?\s+)?"
    for m in re.finditer(r"^\s*" + vis + r"use\s+([^;]+);", text, re.M):
        for q in expand(re.sub(r"\s+", "", m.group(1))):
            name = q.split(" as ")[-1].split("::")[-1]
            out[name] = q
    return out


def resolve(here, path, seen=0):
    """The module an import path names: `super::super::anchor::Raw` from fill::auto::holes
    is fill::anchor; a name a module imports is followed to where it is defined.
    Anything not a module file is taken as an item of the module before it."""
    found = resolve_modules(here, path)
    if found is None:
        return None
    mod, rest = found
    again = reexports(mod).get(rest[0]) if rest else None
    if again and seen < 8 and mod != here:
        if not again.startswith(("crate", "super", "self")):
            again = "self::" + again
        deeper = resolve(mod, "::".join([again, *rest[1:]]), seen + 1)
        if deeper is not None:
            return deeper
    return mod


def resolve_modules(here, path):
    """The longest module path `path` starts with, and the names after it."""
    parts = path.split("::")
    if parts[0] == "crate":
        base, rest = [], parts[1:]
    elif parts[0] in ("super", "self"):
        base = list(here)
        rest = parts
        while rest and rest[0] in ("super", "self"):
            if rest[0] == "super":
                base.pop()
            rest = rest[1:]
    else:
        # A path from a child module (`use holes::score;` in auto/mod.rs).
        child = src.joinpath(*here, parts[0])
        if not (child.with_suffix(".rs").exists() or (child / "mod.rs").exists()):
            return None
        base, rest = list(here), parts
    mod = list(base)
    for i, p in enumerate(rest):
        cand = src.joinpath(*mod, p)
        if cand.with_suffix(".rs").exists() or (cand / "mod.rs").exists():
            mod.append(p)
        else:
            return mod, rest[i:]
    return mod, []


def code(text):
    """The file's code without its test modules (from the first `#[cfg(test)] mod x {`)
    and without imports made for the documentation only (`#[cfg(doc)] use`)."""
    text = re.split(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{", text)[0]
    return re.sub(r"#\[cfg\(doc\)\]\s*use[^;]+;", "", text)


def uses(text):
    """Import paths of the file's code, braces expanded."""
    text = code(text)
    out = []
    for m in re.finditer(r"^\s*(?:pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", text, re.M):
        body = re.sub(r"\s+", "", m.group(1))
        out.extend(expand(body))
    return out


def expand(body):
    if "{" not in body:
        return [body]
    i = body.index("{")
    prefix, inner = body[:i], body[i + 1 : body.rindex("}")]
    items, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
            continue
        depth += ch == "{"
        depth -= ch == "}"
        cur += ch
    if cur:
        items.append(cur)
    return [q for it in items if it for q in expand(prefix + it)]


def inline_paths(text, here, is_mod):
    """Paths written in the code rather than imported: `crate::profile::gap(..)`,
    `super::super::x`, and in a `mod.rs` its own child modules (`auto::fill(..)`)."""
    body = re.sub(r"^\s*(?:pub(?:\([^)]*\))?\s+)?use\s+[^;]+;", "", code(text), flags=re.M)
    body = "\n".join(l.split("//")[0] for l in body.splitlines())
    found = re.findall(r"\b((?:crate|super)(?:::\w+)+)", body)
    if is_mod:
        here_dir = src.joinpath(*here)
        for m in re.finditer(r"(?<![:\w])(\w+)::", body):
            c = here_dir / m.group(1)
            if c.with_suffix(".rs").exists() or (c / "mod.rs").exists():
                found.append("self::" + m.group(1))
    return found


graph = {}
files = sorted(folder.rglob("*.rs"))
for f in files:
    here = module_path(f)
    text = f.read_text()
    edges = set()
    own = set(reexports(here, public_only=True).values()) if f.name == "mod.rs" else set()
    for u in uses(text) + inline_paths(text, here, f.name == "mod.rs"):
        if u in own:
            continue  # a re-export: what the module shows, not what it depends on
        # In a mod.rs `super` is the parent folder's module, as for any file in it.
        mod = resolve(here, u)
        if mod is None or mod == here:
            continue
        edges.add("::".join(mod) or "crate")
    name = "::".join(here)
    lines = len(f.read_text().splitlines())
    print(f"{name} ({f.relative_to(src)}, {lines} lines) -> {', '.join(sorted(edges)) or '-'}")
    graph[name] = edges

# Import circles: the strongly connected components of more than one module (Tarjan).
index, low, stack, on, circles = {}, {}, [], set(), []


def visit(v):
    index[v] = low[v] = len(index)
    stack.append(v)
    on.add(v)
    for w in graph.get(v, ()):
        if w not in graph:
            continue
        if w not in index:
            visit(w)
            low[v] = min(low[v], low[w])
        elif w in on:
            low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        comp = []
        while True:
            w = stack.pop()
            on.discard(w)
            comp.append(w)
            if w == v:
                break
        if len(comp) > 1:
            circles.append(sorted(comp))


for v in sorted(graph):
    if v not in index:
        visit(v)
print()
print("import circles:", "; ".join(" <-> ".join(c) for c in circles) or "none")
