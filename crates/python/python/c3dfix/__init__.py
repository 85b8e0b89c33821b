"""c3dfix: read, edit, repair and write C3D motion-capture files losslessly, from numpy.

    import c3dfix
    c = c3dfix.read("walk.c3d")
    xyz = c.points                      # (frames, points, 3), NaN where missing
    fixed, report = c3dfix.repair(c, fill="auto", lowpass="butterworth:4:6")
    fixed.write("walk_repaired.c3d")    # atomic; unchanged samples keep their bytes

To scale over many files (multiprocessing, joblib, Dask, Ray), send paths to the workers and
call repair_file / convert_file there: path in, path out, the command's bytes. Trials pickle
too (as the bytes they would write), and a process forked after c3dfix ran works normally.

The same library as the `c3dfix` command: the same rule for missing samples, the same
options and reports, the same errors (raised as C3dError, a ValueError).
"""

from ._c3dfix import (
    C3d,
    C3dError,
    __version__,
    convert_file,
    cycles,
    detect_events,
    evaluate,
    export_mot,
    export_opensim,
    export_trc,
    gait_parameters,
    gaps,
    info,
    lab_up,
    plot,
    plot_forces,
    read,
    reclaim,
    label,
    repair,
    repair_file,
    report,
    swaps,
    view,
)

__all__ = [
    "C3d",
    "C3dError",
    "convert_file",
    "cycles",
    "detect_events",
    "evaluate",
    "export_mot",
    "export_opensim",
    "export_trc",
    "gait_parameters",
    "gaps",
    "info",
    "lab_up",
    "plot",
    "plot_forces",
    "read",
    "reclaim",
    "label",
    "repair",
    "repair_file",
    "report",
    "swaps",
    "view",
    "__version__",
]
