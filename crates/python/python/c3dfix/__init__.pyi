"""Type stubs of the c3dfix extension module."""

from os import PathLike
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, "PathLike[str]"]

class C3dError(ValueError):
    """A file that cannot be read or written, or options that make no sense."""

class C3d:
    """A C3D file in memory, written back losslessly. Pickles and copies (copy.copy,
    copy.deepcopy) as the bytes it would write, so a copy writes exactly what it would."""

    def __init__(self, data: bytes, path: Optional[_Path] = None) -> None:
        """A trial read from the bytes of a C3D file; path names it in messages."""
    def __reduce__(self) -> Tuple[Any, Tuple[bytes, Optional[str]]]: ...
    def __copy__(self) -> "C3d": ...
    def __deepcopy__(self, memo: Any) -> "C3d": ...
    def __eq__(self, other: object) -> bool:
        """Equal when both would write the same bytes."""

    @property
    def points(self) -> npt.NDArray[np.float64]:
        """(frames, points, 3) in POINT:UNITS; NaN where a sample is missing."""
    @points.setter
    def points(self, value: npt.NDArray[np.float64]) -> None: ...
    @property
    def residuals(self) -> npt.NDArray[np.float64]:
        """(frames, points); -1 where missing, 0 where computed."""
    @property
    def camera_masks(self) -> npt.NDArray[np.uint8]:
        """(frames, points); bit n set when camera n+1 saw the point."""
    @property
    def labels(self) -> List[str]: ...
    @property
    def point_rate(self) -> float: ...
    @property
    def point_units(self) -> str: ...
    @property
    def first_frame(self) -> int: ...
    @property
    def analog(self) -> npt.NDArray[np.float64]:
        """(samples, channels), scaled as the C3D manual says."""
    @property
    def analog_labels(self) -> List[str]: ...
    @property
    def analog_rate(self) -> float: ...
    @property
    def parameters(self) -> Dict[str, Dict[str, Union[npt.NDArray[np.float64], str, List[str]]]]: ...
    @property
    def events(self) -> List[Dict[str, Any]]:
        """The EVENT group: dicts with label, context, time (s, frame 1 of the capture at
        0 s), frame (round(time x rate) + 1, the file's numbering; None without a rate) and
        description."""
    @property
    def warnings(self) -> List[str]: ...
    def force_platforms(
        self,
        threshold: float = 10.0,
        zero_baseline: bool = True,
        lowpass: Optional[str] = None,
    ) -> List[Dict[str, Any]]:
        """Every force plate (types 1-4), lab frame, at the analog rate: `force` (N),
        `moment` about the working surface's centre (N x POINT:UNITS), `cop` (POINT:UNITS,
        NaN where the push < threshold N), `free_moment`, each (samples, 3) float64, and
        `push` (samples,): -Fz of the plate's frame, how hard a foot presses it down; with
        `index`, `type`, `rate`, `channels`, `corners` (4, 3), `centre`, `origin`,
        `origin_corrected`, `peak_force`, `contacts` (samples, frames, times on the
        events' time base), `baseline` (the unloaded level subtracted, or None; pass
        zero_baseline=False for raw values), `filtered` and `units` {force, moment,
        position}. Plates that cannot be computed are left out
        with a UserWarning naming the plate and the parameter."""
        ...
    def write(self, path: _Path) -> None:
        """Write atomically; byte-identical when nothing changed."""

def read(path: _Path) -> C3d:
    """Read a C3D file; raises C3dError naming the file, section and byte offset."""

def gaps(path: _Path, zero_invalid: bool = False) -> List[Dict[str, Any]]:
    """Every gap of every marker (label, first_frame, last_frame, length, at_start, at_end),
    as `c3dfix gaps --json` lists them; the file is scanned without being decoded into memory."""

def repair(
    c3d: C3d,
    fill: str = "auto",
    spikes: Optional[str] = None,
    lowpass: Optional[str] = None,
    max_gap: int = 200,
    max_expected_error: Optional[float] = 20.0,
    spike_mode: str = "gap",
    spike_min_mm: float = 5.0,
    spike_classic: bool = False,
    markers: Optional[Sequence[str]] = None,
    zero_invalid: bool = False,
    swaps: Literal["fix", "report", "off"] = "report",
    reclaim: Literal["on", "report", "off"] = "report",
    unlabelled: Optional[str] = None,
) -> Tuple[C3d, Dict[str, Any]]:
    """Swaps -> reclaim -> spikes -> fill -> filter on a copy; the repaired copy and the report."""

def reclaim(
    c3d: C3d, unlabelled: Optional[str] = None, zero_invalid: bool = False
) -> Dict[str, Any]:
    """The unlabelled samples that are a labelled marker's, as `c3dfix reclaim --json` lists
    them ("settled", "unsettled"); changes nothing."""

def label(
    input: _Path,
    template: _Path,
    output: Optional[_Path] = None,
    *,
    in_place: bool = False,
    backup: bool = False,
    force: bool = False,
    unlabelled: Optional[str] = None,
    zero_invalid: bool = False,
) -> Dict[str, Any]:
    """`c3dfix label INPUT --template TEMPLATE -o OUTPUT` (or in place): the unlabelled
    trajectories labelled from a labelled trial of the same marker set, written as an
    ordinary labelled C3D; the report `--json` prints."""

def swaps(c3d: C3d) -> Dict[str, Any]:
    """Label swaps and jumps as `c3dfix swaps --json` lists them (frames in the file's numbering)."""

def evaluate(
    files: Sequence[_Path],
    gap_lengths: Sequence[int] = (5, 10, 20, 40, 80),
    markers: Optional[Sequence[str]] = None,
    methods: Optional[Sequence[str]] = None,
    gaps_per_length: int = 40,
    group: int = 1,
    seed: int = 1,
) -> Dict[str, Any]:
    """Fill accuracy on knocked-out known data, per file and pooled (mm)."""

def repair_file(
    input: _Path,
    output: Optional[_Path] = None,
    *,
    in_place: bool = False,
    backup: bool = False,
    force: bool = False,
    report: Optional[_Path] = None,
    fill: str = "auto",
    spikes: Optional[str] = None,
    lowpass: Optional[str] = None,
    max_gap: int = 200,
    max_expected_error: Optional[float] = 20.0,
    spike_mode: str = "gap",
    spike_min_mm: float = 5.0,
    spike_classic: bool = False,
    markers: Optional[Sequence[str]] = None,
    zero_invalid: bool = False,
    swaps: Literal["fix", "report", "off"] = "report",
    reclaim: Literal["on", "report", "off"] = "report",
    unlabelled: Optional[str] = None,
) -> Dict[str, Any]:
    """`c3dfix repair` on one file, path in and path out: the command's bytes, written
    atomically (no overwrite without force, never over a device); returns the report."""

def convert_file(
    input: _Path,
    output: Optional[_Path] = None,
    *,
    in_place: bool = False,
    backup: bool = False,
    force: bool = False,
    processor: Optional[str] = None,
    format: Optional[str] = None,
    scale: Optional[float] = None,
) -> Dict[str, Any]:
    """`c3dfix convert` on one file (processor "intel", "dec" or "sgi"; format "int" or
    "float"): the command's bytes, written atomically; returns what was done."""

def export_trc(
    c3d: C3d,
    path: _Path,
    markers: Optional[Sequence[str]] = None,
    all_points: bool = False,
    axes: Optional[str] = None,
    force: bool = False,
) -> None:
    """Write the trial's markers as TRC (`c3dfix export --format trc`), atomically: Frame#
    the file's frame numbers, Time on its time base, NaN for missing samples, model outputs
    left out unless all_points or named in markers; axes a rotation such as "x,z,-y"."""

def export_mot(
    c3d: C3d,
    path: _Path,
    axes: Optional[str] = None,
    threshold: float = 10.0,
    zero_baseline: bool = True,
    lowpass: Optional[str] = None,
    force: bool = False,
) -> None:
    """Write the force plates' ground reaction as OpenSim's MOT (`c3dfix export --format
    mot`), atomically: per plate force (N), point (m) and free torque (N·m) per analog
    sample, on the file's time base."""

def export_opensim(
    c3d: C3d,
    out_dir: _Path,
    markers: Optional[Sequence[str]] = None,
    all_points: bool = False,
    axes: Optional[str] = None,
    threshold: float = 10.0,
    zero_baseline: bool = True,
    lowpass: Optional[str] = None,
    force: bool = False,
) -> Dict[str, Any]:
    """Write NAME.trc and (with force plates) NAME.mot into out_dir on one time base, in
    OpenSim's frame (the lab's up as Y, the direction of travel as X when there is one, or
    the rotation axes). Returns {trc, mot, axes, up, up_source, forward}."""

def lab_up(c3d: C3d) -> Optional[Tuple[str, str]]:
    """The lab's up as `c3dfix info` reports it: ("+z", "plates") from the force plates'
    corners, else from the markers; None when neither tells."""

def gait_parameters(
    c3d: C3d, detect: bool = False, belt_speed: Optional[float] = None
) -> List[Dict[str, Any]]:
    """The gait-cycle parameters per side as Vicon Nexus names them (`c3dfix gait --json`):
    dicts with context ("Left"/"Right"), name, value and unit; from the file's own Foot
    Strike / Foot Off events, or detected ones with detect=True. Lengths come from the toe
    markers (left out when missing). Raises C3dError when no side has a complete cycle."""
def detect_events(
    c3d: C3d,
    source: str = "auto",
    markers: Optional[Sequence[str]] = None,
    calibrate_from: Optional[Sequence[_Path]] = None,
    calibrate_truth: str = "auto",
) -> List[Dict[str, Any]]:
    """Foot strikes and foot offs as `c3dfix events --json` finds them: context, label,
    time (s on the EVENT group's base), frame (the file's numbering), source ("plate" or
    "kinematics") and plate. source: "plates", "kinematics" or "auto"; markers as
    ["lheel=LHEEL", "pelvis=LPSI+RPSI"]. Raises C3dError without walking or foot markers.
    calibrate_from: files or folders of the same session (`--calibrate-from`): kinematic
    events shifted by the median lag their markers showed at those trials' plate contacts
    or own events (calibrate_truth "plates", "events" or "auto"); each event then carries
    shift_ms, the offset added to it (None where none was)."""

def cycles(
    c3d: C3d,
    side: str = "both",
    markers: Optional[Sequence[str]] = None,
    analog: Optional[Sequence[str]] = None,
    forces: bool = False,
    detect: bool = False,
    source: str = "auto",
) -> Dict[str, Any]:
    """Gait cycles (foot strike to the next of the same foot) time-normalised to 0-100 %
    in 101 samples (linear, both ends included; NaN where the signal is missing): `data`
    float64 (cycles, 101, columns), `columns`, `units`, `percent`, and per cycle `side`,
    `number`, `start_time`, `end_time` (s, the file's base), `start_frame`, `end_frame`;
    `events` "file" or "detected" (detect=True, source as in detect_events). markers in mm
    (model outputs in their units), analog channels in physical units, forces per plate
    (N, lab frame); none named: every marker."""

def info(c3d: Union[C3d, _Path]) -> Dict[str, Any]:
    """What the trial holds and what is wrong with it, as `c3dfix info --json` prints it
    (file, bytes, processor, format, header, frames, rates, up and up_source, markers with
    their gaps, groups, events, force_platforms, warnings, ...). c3d: a C3d or a path."""

def view(
    c3d: Union[C3d, _Path],
    path: _Path,
    against: Optional[Union[C3d, _Path]] = None,
    sticks: Optional[Sequence[Tuple[str, str]]] = None,
    detect_events: bool = False,
    force: bool = False,
) -> List[str]:
    """Write the self-contained HTML page that plays the trial in 3D (what `c3dfix view`
    writes, byte for byte), atomically; against: the original drawn beside it; sticks:
    [marker, marker] label pairs (default: Plug-in Gait segments). Returns the force
    plates' warnings. A .bvh path is a skeleton (against: a .bvh path of the same one)."""

def plot(
    c3d: Union[C3d, _Path],
    path: _Path,
    markers: Sequence[str],
    against: Optional[Union[C3d, _Path]] = None,
    analog: Optional[str] = None,
    detect_events: bool = False,
    force: bool = False,
) -> None:
    """Draw the markers' x, y, z against time as SVG or PNG by the extension (what `c3dfix
    plot --marker` draws, byte for byte), atomically; against: the original, its gaps shaded
    and the repairs marked; analog: a channel (label or 1-based number) drawn below."""

def plot_forces(
    c3d: Union[C3d, _Path],
    path: _Path,
    threshold: float = 10.0,
    zero_baseline: bool = True,
    lowpass: Optional[str] = None,
    detect_events: bool = False,
    force: bool = False,
) -> List[str]:
    """Draw the force plates as SVG or PNG by the extension (what `c3dfix plot --forces`
    draws, byte for byte), atomically; the plate options as for C3d.force_platforms.
    Returns the plates' warnings."""

def report(
    paths: Sequence[_Path],
    out: Optional[_Path] = None,
    repaired: Optional[_Path] = None,
    views: bool = False,
    force: bool = False,
) -> Dict[str, Any]:
    """One row per trial of the files and folders in paths, with their repaired copies in
    the folder repaired, and the session's summary: what `c3dfix report --json` prints
    (keys summary and trials). out: also write the self-contained page (atomically);
    views: with out, each trial's view page beside it, linked from its row. A trial that
    cannot be read is a row with its error."""
