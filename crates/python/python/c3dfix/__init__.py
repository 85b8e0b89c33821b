"""c3dfix: read, edit, repair and write C3D motion-capture files losslessly, from numpy.

    import c3dfix
    c = c3dfix.read("walk.c3d")
    xyz = c.points                      # (frames, points, 3), NaN where missing
    fixed, report = c3dfix.repair(c, fill="auto", lowpass="butterworth:4:6")
    fixed.write("walk_repaired.c3d")    # atomic; unchanged samples keep their bytes

The same library as the `c3dfix` command: the same rule for missing samples, the same
options and reports, the same errors (raised as C3dError, a ValueError).
"""

from ._c3dfix import C3d, C3dError, __version__, evaluate, gaps, read, repair

__all__ = ["C3d", "C3dError", "evaluate", "gaps", "read", "repair", "__version__"]
