#!/usr/bin/env python3
"""Independent reading of which point samples of a C3D file are missing.

Written from the C3D manual alone (no code shared with c3dfix), so that c3dfix's reading of
validity is checked against a second decoder. The rule:

    A point sample is missing when its fourth word, taken as a 16-bit signed integer, is
    negative, or when any of its coordinates is not finite. In a float file the fourth word
    is a float: its integral value is read as a 16-bit word, so -1.0 and 65535.0 (the word
    0xFFFF written as an unsigned number) are both missing. A float fourth word that is not an
    integer in -32768..65535 is not a 16-bit word at all: it is missing when negative or not
    finite, otherwise valid.

Layout, from the header alone (the manual: the header describes what is stored): word 2
points per frame, word 3 analog words per frame, word 9 the data's first block, words 4-5
the frame range; the number format from the sign of POINT:SCALE (else the header's scale);
more than 65535 frames from TRIAL:ACTUAL_START_FIELD/END_FIELD or POINT:LONG_FRAMES.

Usage: c3d_validity.py DIR... > validity.json
Prints {relative path: [valid frame count of point 0, point 1, ...]} for every *.c3d below
each DIR (paths relative to that DIR's parent), and {"error": ...} for files it cannot read.
"""

import json
import math
import os
import struct
import sys


def dec_f32(b):
    """A DEC (VAX F) float: 16-bit words swapped relative to IEEE, exponent bias 2 more."""
    if b[0] == 0 and b[1] == 0 and b[2] == 0 and b[3] == 0:
        return 0.0
    v = struct.unpack("<f", bytes([b[2], b[3], b[0], b[1]]))[0]
    return v / 4.0


class Codec:
    def __init__(self, proc):
        self.proc = proc
        self.end = ">" if proc == 86 else "<"

    def i16(self, b, o):
        return struct.unpack_from(self.end + "h", b, o)[0]

    def u16(self, b, o):
        return struct.unpack_from(self.end + "H", b, o)[0]

    def f32(self, b, o):
        if self.proc == 85:
            return dec_f32(b[o : o + 4])
        return struct.unpack_from(self.end + "f", b, o)[0]


def parameters(data, codec, start):
    """{(GROUP, NAME): (type, dims, raw bytes)} from the parameter section at byte `start`."""
    groups, params = {}, {}
    pos = start + 4
    while pos + 2 <= len(data):
        nlen = struct.unpack_from("b", data, pos)[0]
        gid = struct.unpack_from("b", data, pos + 1)[0]
        n = abs(nlen)
        if n == 0:
            break
        name = data[pos + 2 : pos + 2 + n].decode("latin-1").upper()
        off_at = pos + 2 + n
        if off_at + 2 > len(data):
            break
        nxt = codec.u16(data, off_at)
        body = off_at + 2
        if gid < 0:
            groups[-gid] = name
        else:
            try:
                t = struct.unpack_from("b", data, body)[0]
                nd = data[body + 1]
                dims = list(data[body + 2 : body + 2 + nd])
                size = abs(t)
                for d in dims:
                    size *= d
                raw = data[body + 2 + nd : body + 2 + nd + size]
                params[(gid, name)] = (t, dims, raw)
            except (IndexError, struct.error):
                pass
        if nxt == 0:
            break
        pos = off_at + nxt
    out = {}
    for (gid, name), v in params.items():
        if gid in groups:
            out[(groups[gid], name)] = v
    return out


def numbers(p, codec):
    t, dims, raw = p
    if t == 2:
        return [codec.i16(raw, i) for i in range(0, len(raw) - 1, 2)]
    if t == 4:
        return [codec.f32(raw, i) for i in range(0, len(raw) - 3, 4)]
    if t == 1:
        return list(raw)
    return []


def fourth_missing(w):
    """The manual's rule for a float fourth word (see the module's docstring)."""
    if not math.isfinite(w):
        return True
    if w == int(w) and -32768 <= w <= 65535:
        word = int(w) & 0xFFFF
        return word >= 0x8000
    return w < 0


def valid_counts(path):
    return [sum(v) for v in valid_mask(path)]


def valid_mask(path):
    """Per point, per frame: whether the sample is valid (the rule in the module's docstring)."""
    with open(path, "rb") as fh:
        data = fh.read()
    if len(data) < 512 or data[1] != 0x50:
        raise ValueError("not a C3D file")
    pstart = (data[0] - 1) * 512
    proc = data[pstart + 3]
    if proc not in (84, 85, 86):
        raise ValueError("unknown processor")
    c = Codec(proc)
    npoints = c.u16(data, 2)
    analog_words = c.u16(data, 4)
    first, last = c.u16(data, 6), c.u16(data, 8)
    hscale = c.f32(data, 12)
    data_start = c.u16(data, 16)
    ps = parameters(data, c, pstart)
    scale = hscale
    if ("POINT", "SCALE") in ps:
        s = numbers(ps[("POINT", "SCALE")], c)
        if s and s[0] != 0:
            scale = s[0]
    frames = last - first + 1 if last >= first and not (first == 0 and last == 0) else 0
    trial = [
        numbers(ps[k], c) if k in ps else None
        for k in (("TRIAL", "ACTUAL_START_FIELD"), ("TRIAL", "ACTUAL_END_FIELD"))
    ]
    if all(t and len(t) >= 2 for t in trial):
        s = (trial[0][0] & 0xFFFF) + ((trial[0][1] & 0xFFFF) << 16)
        e = (trial[1][0] & 0xFFFF) + ((trial[1][1] & 0xFFFF) << 16)
        if e - s + 1 > 65535:
            frames = e - s + 1
    if ("POINT", "LONG_FRAMES") in ps:
        lf = numbers(ps[("POINT", "LONG_FRAMES")], c)
        if lf and lf[0] > 65535:
            frames = int(lf[0])
    word = 4 if scale < 0 else 2
    frame_bytes = (4 * npoints + analog_words) * word
    base = (data_start - 1) * 512
    mask = [[False] * frames for _ in range(npoints)]
    for f in range(frames):
        at = base + f * frame_bytes
        if at + frame_bytes > len(data):
            raise ValueError(f"truncated at frame {f}")
        for p in range(npoints):
            o = at + p * 4 * word
            if word == 4:
                xyz = [c.f32(data, o + 4 * k) for k in range(3)]
                missing = fourth_missing(c.f32(data, o + 12))
            else:
                xyz = [float(c.i16(data, o + 2 * k)) for k in range(3)]
                missing = c.i16(data, o + 6) < 0
            mask[p][f] = not missing and all(math.isfinite(v) for v in xyz)
    return mask


def main():
    out = {}
    for d in sys.argv[1:]:
        parent = os.path.dirname(os.path.abspath(d))
        for root, _, files in os.walk(d):
            for name in sorted(files):
                if not name.lower().endswith(".c3d"):
                    continue
                path = os.path.join(root, name)
                rel = os.path.relpath(path, parent)
                try:
                    out[rel] = valid_counts(path)
                except (ValueError, IndexError, struct.error) as e:
                    out[rel] = {"error": str(e)}
    json.dump(out, sys.stdout, indent=0, sort_keys=True)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
