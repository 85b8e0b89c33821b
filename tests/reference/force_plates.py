#!/usr/bin/env python3
"""Independent reference for force-platform outputs of C3D files.

Written from the C3D manual's pages (cited at each rule below) with its own reading of the
file (the header/parameter decoding of `c3d_validity.py` beside it, itself written from the
manual); no code is shared with c3dfix or any other C3D library.

Usage:
    force_plates.py [--zero-baseline] DIR... > force_plates.json

For every *.c3d below each DIR whose FORCE_PLATFORM:USED > 0 it prints, keyed by the path
relative to DIR's parent, the plates' force, moment, centre of pressure and free moment at a
deterministic set of analog samples (see `check_indices`), all in the LAB frame at the analog
rate. Numbers are rounded to 6 significant digits; NaN is written as null. Files that cannot
be read get {"error": "..."}.

The rules followed (each one with the page it comes from):

Analog values
    physical = (raw - OFFSET) * SCALE * GEN_SCALE, per channel.
    https://c3d.org/HTML/Documents/analogdataintegerformat.htm
    When ANALOG:FORMAT is "UNSIGNED" the stored samples (integer files) and ANALOG:OFFSET are
    unsigned 16-bit numbers 0..65535; otherwise both are signed.
    https://c3d.org/HTML/Documents/notesforprogrammersintegeranalogdata.htm
    http://www.c3d.org/HTML/format.htm , https://c3d.org/HTML/Documents/analogoffset.htm
    Analog samples per point frame: see "Analog layout" below; the analog rate is POINT:RATE
    times that (ANALOG:RATE is reported beside it).

Plate axes (CORNERS)
    CORNERS(3,4,USED) are lab coordinates of corners numbered by the quadrant of the plate's
    own x-y plane: 1 = +x+y, 2 = -x+y, 3 = -x-y, 4 = +x-y.
    https://c3d.org/HTML/Documents/forceplatformcorners.htm
    https://c3d.org/HTML/Documents/specifyingforceplatformparameters.htm
    Hence, in the lab: plate x ~ (c1 - c2) + (c4 - c3), plate y ~ (c1 - c4) + (c2 - c3),
    plate z = x cross y (right-handed, which the manual says ORIGIN assumes; with the corners
    seen counter-clockwise from above z points down into the floor, as the manual's plates do).
    y is re-made as z cross x so the rotation R = [x y z] (columns) is orthonormal.
    The centre of the working surface is the mean of the four corners.

ORIGIN
    Types 1, 2, 4: ORIGIN is the vector from the plate's origin (the point about which the
    transducer moments are measured) to the geometric centre of the working surface, expressed
    in the plate frame; with the plate's z down its z is negative.
    https://c3d.org/HTML/Documents/type24.htm , https://www.c3d.org/HTML/Documents/type43.htm
    https://c3d.org/HTML/Documents/forceplatformorigin.htm
    Type 3: ORIGIN(1) = a, ORIGIN(2) = b (half the inter-sensor distances along x and y),
    ORIGIN(3) = the distance from the sensor plane (the plate's origin) to the surface,
    normally negative.  https://c3d.org/HTML/Documents/type31.htm
    Correction: an ORIGIN z > 0 breaks the manual's rule (the plate origin lies below the
    surface, z down). The manual (type24.htm) explains it as the old AMTI convention that gives
    the offset "to" instead of "from" the surface centre, i.e. the same vector reversed; it
    adds that only the sign of Z changes, but the bytes say otherwise: the same plates of one
    lab are stored as ORIGIN (-4.4, 1.9, -21.6) / (-4.06, 3.81, -20.066) in
    c3d-samples/sample_01 and as (4.4, -1.9, 21.6) / (4.06, -3.81, 20.066) in sample_02, every
    component reversed. So for types 1, 2, 4 the whole vector is negated. For type 3, ORIGIN x
    and y are the distances a and b (positive by their definition) and only z is negated.
    The plate records "origin_corrected": true and "origin" as used. A z of 0 is kept.

Wrench about the centre of the working surface, in the plate frame
    Type 2 (https://c3d.org/HTML/Documents/forceplatformtype.htm): channels Fx Fy Fz Mx My Mz,
    the moments about the plate origin O. With r = ORIGIN (O -> surface centre C):
        M_C = M_O - r x F.
    Type 4: the same six outputs are CAL_MATRIX times the six scaled channels
    (https://c3d.org/HTML/Documents/additionalforceplatformparameters.htm: the calibration
    matrix is the inverse of the sensitivity matrix). Storage order: the manual's CAL_MATRIX
    page (https://c3d.org/HTML/Documents/forceplatformcalmatrix.htm) says
    "[CAL_MATRIX] Fmeasured = Fcorrected" with column vectors, "stored in column order":
    CAL_MATRIX(1,1,1) the first element, CAL_MATRIX(6,1,1) the last element of the first
    column, CAL_MATRIX(1,2,1) the first of the second column; rows 1-3 force/V, rows 4-6
    moment/V. So value number i + 6 j + 36 k (0-based, FORTRAN order,
    https://c3d.org/HTML/Documents/parameterarrays1.htm) is row i (output Fx Fy Fz Mx My Mz),
    column j (input channel): outputs = C @ (scaled channels), C[i, j] = value i + 6 j.
    The bytes agree: c3d-samples/sample_10 holds one recording as TYPE-2.C3D (diagonal only)
    and TYPE-4.C3D (full matrix), and TYPE-2a / TYPE-4a likewise (raw counts identical). Read
    this way TYPE-4a's forces agree with TYPE-2a's within 0.3 % of the peak; read transposed
    they differ by 321 N at a 521 N peak (TYPE-4 against TYPE-2: 513 N). The large (N.mm,
    x1000) entries then sit in the moment rows, and sample_24's matrix shows the M = r x F
    pattern (Fy -> Mx and Fx -> My of opposite sign). The channels are scaled by SCALE and
    GEN_SCALE first (the stored SCALE of a type-4 channel is its nominal, "unscaled" one:
    http://c3d.org/HTML/calmatrix.htm; that is what makes the sample_10 pairs agree).
    CAL_MATRIX is ignored for types other than 4 (same page).
    Type 3 (Kistler, https://c3d.org/HTML/Documents/type31.htm): channels fx12 fx34 fy14 fy23
    fz1 fz2 fz3 fz4, sensor i at quadrant i, i.e. at (+a,+b), (-a,+b), (-a,-b), (+a,-b) in the
    sensor plane. Summing forces and their moments about the sensor-plane centre O:
        F  = (fx12 + fx34, fy14 + fy23, fz1 + fz2 + fz3 + fz4)
        Mx = b (fz1 + fz2 - fz3 - fz4)
        My = a (-fz1 + fz2 + fz3 - fz4)
        Mz = b (fx34 - fx12) + a (fy14 - fy23)
    then M_C = M_O - r x F with r = (0, 0, ORIGIN z) (the surface centre above O).
    Type 1 (https://c3d.org/HTML/Documents/type14.htm): channels Fx Fy Fz Px Py Tz, Px Py the
    centre of pressure in the plate frame (measured from the plate origin, like ORIGIN) and Tz
    the free moment. The COP's offset from the surface centre is d = (Px - rx, Py - ry, 0) and
    M_C = d x F + (0, 0, Tz).
    Other types (5, 6, 7, 11, 12, 21, ...) are refused per plate.

Centre of pressure and free moment (from M_C and F, plate frame)
    The COP is the point P = C + d, d = (dx, dy, 0) on the working surface, about which the
    moment has no component in the surface's plane: M_P = M_C - d x F gives
        dx = -M_Cy / Fz,  dy = M_Cx / Fz,  Tz = M_Cz - (dx Fy - dy Fx).
    Null (NaN) where the push -Fz < 10 N (Fz = the plate-normal force); the free moment is NaN
    there too. The push: the plate's z points down into the floor
    (https://c3d.org/HTML/Documents/forceplatformorigin.htm: "the force plate coordinate system
    z-axis is directed downwards") and the channels carry the force on the body, which points
    up, so a foot pushing the plate down reads a negative Fz; a positive Fz is a pull, which no
    foot exerts on a floor plate (an offset or a drift), and has no COP.

Output frame and units
    force  = R F (N; the wrench as the plate reports it, no sign flip).
    moment = R M_C, in N x POINT:UNITS.
    cop    = C + R d (POINT:UNITS); free_moment = R (0, 0, Tz) (N x POINT:UNITS).
    Unit rule: every length in a C3D file is in POINT:UNITS
    (https://c3d.org/HTML/Documents/forceplatformorigin.htm: "All ORIGIN distance units must be
    recorded in POINT:UNITS"), and ANALOG:UNITS "only documents the units of the calculated
    results, changing the parameter does not affect the scaling calculations"
    (https://c3d.org/HTML/Documents/notesforprogrammersintegeranalogdata.htm, note 6), and
    POINT:UNITS "affects the scaling values stored in the CAL_MATRIX, and ANALOG:SCALE
    parameters" (https://c3d.org/HTML/Documents/pointunits.htm). So the
    moment channels are taken in N x POINT:UNITS and type 1's Px, Py in POINT:UNITS, as scaled,
    never converted by their ANALOG:UNITS. The bytes agree: c3d-samples/sample_03 labels its
    moment channels "Nm" with POINT:UNITS "mm", yet its values are N.mm (taken as N.m, every
    loaded COP would lie metres off the plate; taken as N.mm all lie on it). A plate whose
    moment (or COP) channel names a length other than POINT:UNITS gets a "warnings" entry.

ZERO (not applied by default; --zero-baseline applies it)
    FORCE_PLATFORM:ZERO holds a first and last point frame (1-based; [0, 0] = none) of a
    range whose mean of each plate channel is subtracted before the plate maths (the manual's
    index lists FORCE_PLATFORM:ZERO, https://www.c3d.org/HTML/C3D%20User%20Guide-toc.htm;
    its use as a baseline range: https://wiki.has-motion.com/doku.php?do=export_xhtml&id=visual3d%3Adocumentation%3Apipeline%3Aforce_commands%3Afp_baselines).
    Frame 1 is the first frame stored in the file; the range is clipped to the stored frames
    (a first frame of 0, as in [0, 10], is read as 1).

Kistler COP correction polynomial
    The C3D manual defines no parameter carrying it (FORCE_PLATFORM holds USED, TYPE, ZERO,
    CORNERS, ORIGIN, CHANNEL, CAL_MATRIX; https://c3d.org/HTML/Documents/forceplatformused1.htm
    and the manual's index https://www.c3d.org/HTML/C3D%20User%20Guide-indexlist.htm); the
    polynomial is Kistler's own (https://www.easymanua.ls/kistler/9287c-series/manual?p=39).
    (A user in https://github.com/pyomeca/ezc3d/issues/253 quotes the 2008 C3D User Guide as
    naming FORCE_PLATFORM:FPCOPPOLY, a 2 x 6 matrix of correction factors; the manual pages
    at hand do not, so it is not taken as the manual's rule.)
    One corpus file carries it in a vendor parameter: FORCE_PLATFORM:FPCOPPOLY (6, 2, USED) =
    P1..P6 for x then y, per plate (c3d-more/qualisys__...FunctionalKnee_GaitFB2.c3d; the values
    are the ones Kistler's manual lists for a 9281E). It is NOT applied to "cop"; where a plate
    has one, "cop_poly" gives the coefficients and the corrected COP at the checked samples.

Analog layout
    Analog samples per frame = header word 3 / ANALOG:USED; if ANALOG:RATE / POINT:RATE is a
    different integer and only that layout makes the data section end in the file's last
    512-byte block, that one is used ("layout_note" says so).

Samples checked (`check`): 24 evenly spaced over all samples plus 24 evenly spaced over the
samples where the push -Fz >= 100 N, sorted and unique.
"""

import json
import math
import os
import struct
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from c3d_validity import Codec, numbers, parameters  # noqa: E402

COP_MIN_FZ = 10.0
LOADED_FZ = 100.0
N_EVEN = 24
SIG = 6

# CAL_MATRIX(i, j, k) (value number i + 6 j + 36 k): "row_first" means i is the output row
# (Fx..Mz) and j the input channel, so value number i + 6 j multiplies channel j into output i.
# The manual's CAL_MATRIX page and the bytes of c3d-samples/sample_10 (see the module's
# docstring, Type 4).
# "col_first" is kept only so that the other reading can be shown to fail.
CAL_ORDER = "row_first"


def g6(v):
    if v is None:
        return None
    v = float(v)
    if not math.isfinite(v):
        return None
    if v == 0:
        return 0.0
    return float(f"{v:.{SIG}g}")


def vec_list(a):
    return [[g6(x) for x in row] for row in a]


def strings(p):
    """A character parameter as a list of stripped strings (first dimension = length)."""
    t, dims, raw = p
    if t != -1:
        return []
    s = raw.decode("latin-1").replace("\x00", " ")
    if not dims:
        return [s.strip()]
    n = dims[0]
    if n == 0:
        return []
    return [s[i : i + n].strip() for i in range(0, len(s), n)]


def length_of_unit(u):
    """Length unit in metres named by a unit string, or None."""
    u = u.strip().lower().replace(" ", "")
    if u.startswith("met"):  # "meters", "metres", or cut short ("mete")
        return 1.0
    if u.startswith("millim"):
        return 0.001
    if u in ("mm",) or u.endswith("mm"):
        return 0.001
    if u in ("cm",) or u.endswith("cm"):
        return 0.01
    if u in ("m",) or u.endswith("m"):
        # Nm, N.m, N*m, N-m, m
        return 1.0
    return None


def moment_unit_length(u):
    """Length in metres of a moment unit like 'Nmm', 'N.m', 'N*mm'; None if it names none."""
    s = u.strip().lower().replace(" ", "")
    if not s.startswith("n") or len(s) < 2:
        return None
    return length_of_unit(s[1:].lstrip(".*-·"))


class File:
    def __init__(self, path):
        with open(path, "rb") as fh:
            data = fh.read()
        if len(data) < 512 or data[1] != 0x50:
            raise ValueError("not a C3D file")
        pstart = (data[0] - 1) * 512
        if pstart + 4 > len(data):
            raise ValueError("parameter section beyond end of file")
        proc = data[pstart + 3]
        if proc not in (84, 85, 86):
            raise ValueError(f"unknown processor byte {proc}")
        c = Codec(proc)
        self.codec = c
        self.data = data
        self.npoints = c.u16(data, 2)
        self.analog_words = c.u16(data, 4)
        first, last = c.u16(data, 6), c.u16(data, 8)
        hscale = c.f32(data, 12)
        self.data_start = c.u16(data, 16)
        self.header_rate = c.f32(data, 20)
        self.p = parameters(data, c, pstart)
        scale = hscale
        s = self.num("POINT", "SCALE")
        if s and s[0] != 0:
            scale = s[0]
        self.is_float = scale < 0
        frames = last - first + 1 if last >= first and not (first == 0 and last == 0) else 0
        trial = [self.num("TRIAL", k) for k in ("ACTUAL_START_FIELD", "ACTUAL_END_FIELD")]
        if all(t and len(t) >= 2 for t in trial):
            st = (trial[0][0] & 0xFFFF) + ((trial[0][1] & 0xFFFF) << 16)
            en = (trial[1][0] & 0xFFFF) + ((trial[1][1] & 0xFFFF) << 16)
            if en - st + 1 > 65535:
                frames = en - st + 1
        lf = self.num("POINT", "LONG_FRAMES")
        if lf and lf[0] > 65535:
            frames = int(lf[0])
        self.frames = frames

    def num(self, g, n):
        p = self.p.get((g, n))
        return numbers(p, self.codec) if p else None

    def text(self, g, n):
        p = self.p.get((g, n))
        return strings(p) if p else None

    def analog(self):
        """(samples, channels) array of analog values in physical units, and info."""
        c = self.codec
        used_p = self.num("ANALOG", "USED")
        used = int(used_p[0]) if used_p else 0
        if used <= 0:
            raise ValueError("ANALOG:USED is 0 or missing")
        spf = self.analog_words // used if self.analog_words % used == 0 else 0
        # Header word 3 holds the analog words per frame; ANALOG:RATE / POINT:RATE says the same
        # thing. When they disagree, the one whose data section ends in the file's last
        # 512-byte block is taken (some writers put the channel count in word 3; the bytes then
        # show 7 samples of 16 channels per frame where word 3 says 16).
        prate = self.num("POINT", "RATE")
        prate = prate[0] if prate else self.header_rate
        arate = self.num("ANALOG", "RATE")
        self.layout_note = None
        if arate and prate and arate[0] > 0 and prate > 0:
            ratio = arate[0] / prate
            spf_p = int(round(ratio))
            if spf_p >= 1 and abs(ratio - spf_p) < 1e-6 and spf_p != spf:
                # (spf is 0 here when word 3 is not a multiple of ANALOG:USED)
                word = 4 if self.is_float else 2
                base = (self.data_start - 1) * 512

                def ends_in_last_block(n):
                    end = base + self.frames * (4 * self.npoints + n * used) * word
                    return 0 <= len(self.data) - end < 512

                if ends_in_last_block(spf_p) and (spf == 0 or not ends_in_last_block(spf)):
                    self.layout_note = (
                        f"header word 3 says {self.analog_words} analog words per frame; "
                        f"ANALOG:RATE/POINT:RATE = {spf_p} samples of {used} channels fit the file"
                    )
                    spf = spf_p
                    self.analog_words = spf * used
        if spf == 0:
            raise ValueError(
                f"header analog words per frame {self.analog_words} not a positive multiple of "
                f"ANALOG:USED {used}, and ANALOG:RATE / POINT:RATE does not fit the file either"
            )
        fmt = (self.text("ANALOG", "FORMAT") or [""])[0].upper()
        unsigned = fmt == "UNSIGNED"
        scale = self.num("ANALOG", "SCALE") or []
        offset = self.num("ANALOG", "OFFSET") or []
        gen = self.num("ANALOG", "GEN_SCALE")
        gen = gen[0] if gen else 1.0
        if len(scale) < used or len(offset) < used:
            raise ValueError(
                f"ANALOG:SCALE ({len(scale)}) or OFFSET ({len(offset)}) shorter than USED {used}"
            )
        scale = np.array(scale[:used], float)
        offset = np.array(offset[:used], float)
        if unsigned and self.p[("ANALOG", "OFFSET")][0] == 2:
            offset = np.where(offset < 0, offset + 65536, offset)
        word = 4 if self.is_float else 2
        frame_words = 4 * self.npoints + self.analog_words
        frame_bytes = frame_words * word
        base = (self.data_start - 1) * 512
        need = base + self.frames * frame_bytes
        if self.frames <= 0:
            raise ValueError("no frames")
        if need > len(self.data):
            raise ValueError(f"data section truncated: need {need} bytes, file has {len(self.data)}")
        block = self.data[base:need]
        end = ">" if self.codec.proc == 86 else "<"
        if word == 4:
            if c.proc == 85:
                b = np.frombuffer(block, dtype=np.uint8).reshape(-1, 4)
                sw = b[:, [2, 3, 0, 1]].copy()
                vals = sw.view("<f4").reshape(-1).astype(float) / 4.0
                zero = (b == 0).all(axis=1)
                vals[zero] = 0.0
            else:
                vals = np.frombuffer(block, dtype=end + "f4").astype(float)
        else:
            dt = end + ("u2" if unsigned else "i2")
            vals = np.frombuffer(block, dtype=dt).astype(float)
        vals = vals.reshape(self.frames, frame_words)[:, 4 * self.npoints :]
        vals = vals.reshape(self.frames * spf, used)
        phys = (vals - offset) * scale * gen
        info = {
            "analog_used": used,
            "samples_per_frame": spf,
            "analog_rate": g6(prate * spf),
            "analog_rate_param": g6(arate[0]) if arate else None,
            "analog_format": fmt or None,
            "gen_scale": g6(gen),
        }
        units = self.text("ANALOG", "UNITS") or []
        return phys, spf, info, units


def plate_axes(corners):
    c1, c2, c3, c4 = corners
    x = (c1 - c2) + (c4 - c3)
    y = (c1 - c4) + (c2 - c3)
    x = x / np.linalg.norm(x)
    z = np.cross(x, y)
    z = z / np.linalg.norm(z)
    y = np.cross(z, x)
    return np.column_stack([x, y, z])


def check_indices(fz):
    n = len(fz)
    idx = set(np.unique(np.round(np.linspace(0, n - 1, min(N_EVEN, n))).astype(int)).tolist())
    loaded = np.nonzero(-fz >= LOADED_FZ)[0]
    if len(loaded):
        pos = np.unique(np.round(np.linspace(0, len(loaded) - 1, min(N_EVEN, len(loaded)))))
        idx.update(loaded[pos.astype(int)].tolist())
    return sorted(idx)


def kistler_poly(f, k):
    """(name, P1x..P6x, P1y..P6y) of plate k from a FORCE_PLATFORM parameter shaped (6, 2, n)
    whose name holds COPPOLY or COP_POLY (a vendor parameter; the manual defines none)."""
    for (g, n), p in f.p.items():
        if g != "FORCE_PLATFORM" or ("COPPOLY" not in n and "COP_POLY" not in n):
            continue
        t, dims, _ = p
        if t != 4 or len(dims) < 2 or dims[0] != 6 or dims[1] != 2:
            continue
        v = numbers(p, f.codec)
        if len(v) < 12 * (k + 1):
            continue
        c = np.array(v[12 * k : 12 * k + 12], float)
        if not np.any(c):
            continue
        return n, c[:6], c[6:]
    return None


def kistler_correct(d, px, py):
    """Kistler's COP correction (plate manual, e.g.
    https://www.easymanua.ls/kistler/9287c-series/manual?p=39): with ax, ay the measured COP
    from the plate centre, ax -= ((P1x ay^4 + P2x ay^2 + P3x) ax^3 + (P4x ay^4 + P5x ay^2 + P6x) ax)
    and the same for ay with x and y swapped."""
    ax, ay = d[:, 0], d[:, 1]
    dax = (px[0] * ay**4 + px[1] * ay**2 + px[2]) * ax**3 + (px[3] * ay**4 + px[4] * ay**2 + px[5]) * ax
    day = (py[0] * ax**4 + py[1] * ax**2 + py[2]) * ay**3 + (py[3] * ax**4 + py[4] * ax**2 + py[5]) * ay
    return np.column_stack([ax - dax, ay - day, d[:, 2]])


def cop_and_free(F, Mc):
    """COP offset d (plate frame, from the surface centre) and free moment Tz, NaN where the
    push -Fz < 10 N."""
    fz = F[:, 2]
    with np.errstate(invalid="ignore"):
        ok = -fz >= COP_MIN_FZ
    with np.errstate(divide="ignore", invalid="ignore"):
        dx = np.where(ok, -Mc[:, 1] / fz, np.nan)
        dy = np.where(ok, Mc[:, 0] / fz, np.nan)
    tz = Mc[:, 2] - (dx * F[:, 1] - dy * F[:, 0])
    d = np.column_stack([dx, dy, np.zeros_like(dx)])
    d[~ok] = np.nan
    return d, tz


def compute_file(path, zero_baseline, full=False):
    """The file's plates as in the JSON; with full=True each plate also gets '_arrays'."""
    f = File(path)
    used_p = f.num("FORCE_PLATFORM", "USED")
    nplates = int(used_p[0]) if used_p else 0
    if nplates <= 0:
        return None
    pu = (f.text("POINT", "UNITS") or ["mm"])
    point_units = pu[0] if pu and pu[0] else "mm"
    point_len = length_of_unit(point_units)
    phys, spf, info, aunits = f.analog()
    nsamp, nch = phys.shape
    types = f.num("FORCE_PLATFORM", "TYPE") or []
    chan_p = f.p.get(("FORCE_PLATFORM", "CHANNEL"))
    chans = f.num("FORCE_PLATFORM", "CHANNEL") or []
    chan_rows = chan_p[1][0] if chan_p and chan_p[1] else 6
    corners = f.num("FORCE_PLATFORM", "CORNERS") or []
    origin = f.num("FORCE_PLATFORM", "ORIGIN") or []
    cal = f.num("FORCE_PLATFORM", "CAL_MATRIX") or []
    cal_p = f.p.get(("FORCE_PLATFORM", "CAL_MATRIX"))
    zero = f.num("FORCE_PLATFORM", "ZERO") or []
    cop_poly = sorted(
        n for (g, n) in f.p if g == "FORCE_PLATFORM" and ("POLY" in n or "COP" in n)
    )
    out = {
        "point_units": point_units,
        "analog_rate": info["analog_rate"],
        "analog_rate_param": info["analog_rate_param"],
        "samples_per_frame": spf,
        "analog_format": info["analog_format"],
        "layout_note": f.layout_note,
        "zero_baseline_applied": False,
        "zero": [int(z) for z in zero[:2]] if zero else None,
        "plates": [],
    }
    if cop_poly:
        out["cop_poly_params"] = cop_poly
    baseline = None
    if zero_baseline and len(zero) >= 2 and not (zero[0] == 0 and zero[1] == 0):
        z0 = max(int(zero[0]), 1)
        z1 = min(int(zero[1]), f.frames)
        if z1 >= z0:
            baseline = phys[(z0 - 1) * spf : z1 * spf].mean(axis=0)
            out["zero_baseline_applied"] = True
            out["zero_samples"] = [(z0 - 1) * spf, z1 * spf]
    data = phys - baseline if baseline is not None else phys
    for k in range(nplates):
        t = int(types[k]) if k < len(types) else None
        plate = {"index": k + 1, "type": t}
        nneed = {1: 6, 2: 6, 3: 8, 4: 6}.get(t)
        if nneed is None:
            plate["refused"] = f"plate type {t} is not one of the manual's types 1-4"
            out["plates"].append(plate)
            continue
        try:
            ch = [int(v) for v in chans[k * chan_rows : k * chan_rows + nneed]]
            if len(ch) < nneed or chan_rows < nneed:
                raise ValueError(f"FORCE_PLATFORM:CHANNEL has {chan_rows} rows, type {t} needs {nneed}")
            if any(c < 1 or c > nch for c in ch):
                raise ValueError(f"channel numbers {ch} outside 1..{nch}")
            cor = np.array(corners[k * 12 : k * 12 + 12], float)
            if len(cor) < 12:
                raise ValueError("FORCE_PLATFORM:CORNERS too short")
            cor = cor.reshape(4, 3)
            org = np.array(origin[k * 3 : k * 3 + 3], float)
            if len(org) < 3:
                raise ValueError("FORCE_PLATFORM:ORIGIN too short")
            if not np.all(np.isfinite(cor)) or not np.all(np.isfinite(org)):
                raise ValueError("non-finite CORNERS or ORIGIN")
            corrected = False
            if org[2] > 0:
                # See the module's docstring (ORIGIN): types 1, 2, 4 reverse the whole vector,
                # type 3 only the depth (a and b are distances).
                org = org.copy()
                if t == 3:
                    org[2] = -org[2]
                else:
                    org = -org
                corrected = True
            R = plate_axes(cor)
            if not np.all(np.isfinite(R)):
                raise ValueError("degenerate CORNERS")
            # The four corners must describe a plate: opposite sides equal (a parallelogram)
            # within 5 % of the longer side, all four corners in one plane within 5 %.
            s12, s43 = cor[0] - cor[1], cor[3] - cor[2]
            s14, s23 = cor[0] - cor[3], cor[1] - cor[2]
            side = max(np.linalg.norm(s12), np.linalg.norm(s14))
            flat = np.abs((cor - cor.mean(axis=0)) @ R[:, 2]).max()
            if (
                side <= 0
                or np.linalg.norm(s12 - s43) > 0.05 * side
                or np.linalg.norm(s14 - s23) > 0.05 * side
                or flat > 0.05 * side
            ):
                raise ValueError(f"FORCE_PLATFORM:CORNERS of plate {k + 1} do not describe a plate: {cor.tolist()}")
            warnings = []
            if t == 3 and (org[0] == 0 or org[1] == 0):
                warnings.append("type-3 ORIGIN a or b is 0: the sensor offsets are missing, moments vanish")
            center = cor.mean(axis=0)
            a = data[:, [c - 1 for c in ch]]
            units = [aunits[c - 1] if c - 1 < len(aunits) else "" for c in ch]

            def mconv(u):
                # ANALOG:UNITS documents, it does not scale (see the docstring's unit rule).
                L = moment_unit_length(u)
                if L is not None and point_len is not None and abs(L / point_len - 1) > 1e-9:
                    warnings.append(
                        f"ANALOG:UNITS {u!r} names a length other than POINT:UNITS "
                        f"{point_units!r}; not converted"
                    )
                return 1.0

            unit_note = {"channel_units": units}
            if t in (2, 4):
                if t == 4:
                    if not cal_p or len(cal_p[1]) < 2 or cal_p[1][0] != 6 or cal_p[1][1] != 6:
                        raise ValueError(f"CAL_MATRIX dims {cal_p[1] if cal_p else None} not (6,6,n)")
                    m = np.array(cal[k * 36 : k * 36 + 36], float)
                    if len(m) < 36:
                        raise ValueError("CAL_MATRIX too short")
                    m = m.reshape(6, 6)  # m[j, i] = value number i + 6 j
                    C = m.T if CAL_ORDER == "row_first" else m
                    plate["cal_matrix_rows"] = vec_list(C)
                    w = a @ C.T
                else:
                    w = a.copy()
                F = w[:, 0:3]
                conv = np.array([mconv(u) for u in units[3:6]])
                Mo = w[:, 3:6] * conv
                Mc = Mo - np.cross(org, F)
            elif t == 3:
                fx12, fx34, fy14, fy23, fz1, fz2, fz3, fz4 = a.T
                aa, bb, az = org
                F = np.column_stack([fx12 + fx34, fy14 + fy23, fz1 + fz2 + fz3 + fz4])
                Mo = np.column_stack(
                    [
                        bb * (fz1 + fz2 - fz3 - fz4),
                        aa * (-fz1 + fz2 + fz3 - fz4),
                        bb * (fx34 - fx12) + aa * (fy14 - fy23),
                    ]
                )
                Mc = Mo - np.cross(np.array([0.0, 0.0, az]), F)
            else:  # type 1
                F = a[:, 0:3]
                for u in units[3:5]:
                    L = length_of_unit(u) if u.strip().lower() in ("m", "mm", "cm") else None
                    if L is not None and point_len is not None and abs(L / point_len - 1) > 1e-9:
                        warnings.append(
                            f"ANALOG:UNITS {u!r} of a COP channel differs from POINT:UNITS "
                            f"{point_units!r}; not converted"
                        )
                pconv = np.ones(2)
                tconv = mconv(units[5])
                px = a[:, 3] * pconv[0] - org[0]
                py = a[:, 4] * pconv[1] - org[1]
                d = np.column_stack([px, py, np.zeros_like(px)])
                Mc = np.cross(d, F)
                Mc[:, 2] += a[:, 5] * tconv
            d, tz = cop_and_free(F, Mc)
            poly = kistler_poly(f, k)
            force = F @ R.T
            moment = Mc @ R.T
            cop = center + d @ R.T
            free = tz[:, None] * R[:, 2][None, :]
            free[~np.isfinite(tz)] = np.nan
            fz = F[:, 2]
            idx = check_indices(fz)
            # COP on the plate: within the corners' bounding box in the plate frame, 1 mm margin
            with np.errstate(invalid="ignore"):
                loaded = -fz >= LOADED_FZ
            half = np.abs((cor - center) @ R).max(axis=0)
            margin = 1.0 / (point_len * 1000.0) if point_len else 1.0
            off = (np.abs(d[:, 0]) > half[0] + margin) | (np.abs(d[:, 1]) > half[1] + margin)
            outside = np.maximum(np.abs(d[:, 0]) - half[0], np.abs(d[:, 1]) - half[1])
            worst = outside[loaded & off]
            plate.update(
                {
                    "channels": ch,
                    "corners": vec_list(cor),
                    "origin": [g6(v) for v in org],
                    "origin_corrected": corrected,
                    "axes_lab": vec_list(R.T),
                    "center": [g6(v) for v in center],
                    "samples": int(nsamp),
                    "units": unit_note,
                    "check": idx,
                    "force": vec_list(force[idx]),
                    "moment": vec_list(moment[idx]),
                    "cop": vec_list(cop[idx]),
                    "free_moment": vec_list(free[idx]),
                    "force_mean": [g6(v) for v in np.nanmean(force, axis=0)],
                    "peak_fz": g6(np.nanmax(np.abs(fz))) if np.isfinite(fz).any() else None,
                    "loaded_samples": int(loaded.sum()),
                    "loaded_cop_off_plate": int((off & loaded).sum()),
                    "loaded_cop_max_outside": g6(worst.max()) if worst.size else None,
                    "nan_samples": int((~np.isfinite(a)).any(axis=1).sum()),
                }
            )
            if poly is not None:
                name, px, py = poly
                dc = kistler_correct(d, px, py)
                plate["cop_poly"] = {
                    "param": f"FORCE_PLATFORM:{name}",
                    "px": [g6(v) for v in px],
                    "py": [g6(v) for v in py],
                    "cop_corrected": vec_list((center + dc @ R.T)[idx]),
                }
            if warnings:
                plate["warnings"] = sorted(set(warnings))
            if full:
                plate["_arrays"] = {
                    "force": force, "moment": moment, "cop": cop, "free_moment": free,
                    "F_plate": F, "M_center_plate": Mc, "R": R, "center": center,
                    "origin": org, "analog": a,
                }
        except (ValueError, IndexError) as e:
            plate["error"] = str(e)
        out["plates"].append(plate)
    return out


def main():
    args = sys.argv[1:]
    zero_baseline = "--zero-baseline" in args
    dirs = [a for a in args if not a.startswith("--")]
    out = {}
    for d in dirs:
        parent = os.path.dirname(os.path.abspath(d))
        for root, _, files in sorted(os.walk(d)):
            for name in sorted(files):
                if not name.lower().endswith(".c3d"):
                    continue
                path = os.path.join(root, name)
                rel = os.path.relpath(path, parent)
                try:
                    r = compute_file(path, zero_baseline)
                except (ValueError, IndexError, struct.error, KeyError) as e:
                    out[rel] = {"error": str(e)}
                    continue
                if r is not None:
                    out[rel] = r
    json.dump(out, sys.stdout, separators=(",", ":"), sort_keys=True)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
