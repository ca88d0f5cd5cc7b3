"""A recorded run: the arrays the simulator writes and every later tool reads.

A run directory holds ``trajectory.npz`` (this dataclass, one row per recorded
sample), ``trajectory.csv`` (the same samples for people, to 9 significant digits, with
units in the column names but for the coordinates, whose unit is their joint's; without
``root_pos`` and ``leg_spring_energy``) and ``run.json`` (inputs, parameters, events, status).

Shapes: N samples, NQ/NV coordinates, NC contacts, NL legs, NA actuators.

The actuators' work is recorded as running sums since the start (``work_positive``,
``work_negative``: the integrals of max(0, tau qd) and min(0, tau qd), summed at every
integration step, not only at the recorded ones), so the work between two samples is a
difference of two rows.
"""

from __future__ import annotations

import csv
import json
import math
import os
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, BinaryIO, TextIO

import numpy as np

from legdsl.files import atomic_path
from legdsl.lang.errors import UsageError

ARRAYS = (
    "t", "q", "v", "contact", "force", "com", "com_vel", "root_pos", "root_rpy",
    "leg_length", "leg_spring_energy", "kinetic", "potential", "elastic", "state", "speed_command",
    "work_positive", "work_negative",
)  # fmt: skip
LATER = ("work_positive", "work_negative")  # arrays a run of an older legdsl lacks (empty then)
FLOAT32_MAX = float(np.finfo(np.float32).max)
COMPUTABLE = 1e150  # past this a value's square overflows a double


@dataclass
class Trajectory:
    t: np.ndarray  # (N,) s
    q: np.ndarray  # (N, NQ) generalized positions (m, rad; quaternion for a 3D root)
    v: np.ndarray  # (N, NV) generalized velocities
    contact: np.ndarray  # (N, NC) int8: 1 while the contact touches the ground
    force: np.ndarray  # (N, NC, 3) N: world ground-reaction force on each contact
    com: np.ndarray  # (N, 3) m: centre of mass
    com_vel: np.ndarray  # (N, 3) m/s
    root_pos: np.ndarray  # (N, 3) m: origin of the root body frame
    root_rpy: np.ndarray  # (N, 3) rad: roll, pitch, yaw of the root body (planar: pitch only)
    leg_length: np.ndarray  # (N, NL) m: hip point (first leg joint) to foot contact
    leg_spring_energy: np.ndarray  # (N, NL) J: elastic energy in each leg's spring actuators
    kinetic: np.ndarray  # (N,) J
    potential: np.ndarray  # (N,) J: gravitational, zero at z = 0
    elastic: np.ndarray  # (N,) J: all actuator springs and ground springs
    state: np.ndarray  # (N,) int16: index into state_names, -1 without a controller
    speed_command: np.ndarray  # (N,) m/s: commanded forward speed, NaN without one
    work_positive: np.ndarray  # (N, NA) J: each actuator's positive work since the start
    work_negative: np.ndarray  # (N, NA) J: its negative work (<= 0) since the start
    q_names: tuple[str, ...] = ()
    v_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()
    leg_names: tuple[str, ...] = ()
    leg_feet: tuple[int, ...] = ()  # for each leg, the index of its foot in contact_names
    # for each leg, the indices of all its soles (its foot first); () when each leg has only
    # its foot (a run directory written before legs had several soles reads so, too)
    leg_soles: tuple[tuple[int, ...], ...] = ()
    state_names: tuple[str, ...] = ()
    actuator_names: tuple[str, ...] = ()
    total_mass: float = 0.0
    gravity: float = 9.81  # magnitude, m/s^2
    planar: bool = True
    extra: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def soles_of(self, leg: int) -> tuple[int, ...]:
        """The contacts leg ``leg`` stands on: its foot first."""
        return self.leg_soles[leg] if self.leg_soles else (self.leg_feet[leg],)

    def leg_touching(self, leg: int) -> np.ndarray:
        """(N,) bool: whether the leg touches the ground, i.e. any of its soles does."""
        return np.asarray(self.contact[:, list(self.soles_of(leg))].any(axis=1), dtype=bool)

    def row_bytes(self) -> int:
        """The memory one sample takes (a row of every array)."""
        arrays = (getattr(self, name) for name in ARRAYS)
        return sum(a.itemsize * int(np.prod(a.shape[1:])) for a in arrays)

    def head(self, n: int) -> Trajectory:
        """The first ``n`` samples (used to keep what was recorded when a run stops early)."""
        return self.rows(0, n)

    def rows(self, start: int, stop: int) -> Trajectory:
        """Samples ``start`` to ``stop`` (views of these arrays: one copy's of a batch's)."""
        cut = {f.name: getattr(self, f.name)[start:stop] for f in fields(self) if f.name in ARRAYS}
        meta = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in ARRAYS}
        return Trajectory(**cut, **meta)

    def grown(self, capacity: int) -> Trajectory:
        """The same samples in arrays of ``capacity`` rows (the recorder grows as it goes,
        never sized by the duration asked for); new rows hold ``empty``'s fill values."""
        n = len(self)
        fill = empty(1, self.q.shape[1], self.v.shape[1], self.contact.shape[1],
                     self.leg_length.shape[1], self.work_positive.shape[1])  # fmt: skip
        cut: dict[str, Any] = {}
        for name in ARRAYS:  # an array at a time: the old rows and the new arrays at most
            old = getattr(self, name)
            new = np.empty((capacity, *old.shape[1:]), dtype=old.dtype)
            new[:n] = old
            new[n:] = getattr(fill, name)[0]
            cut[name] = new
        meta = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in ARRAYS}
        return Trajectory(**cut, **meta)

    # ------------------------------------------------------------ files
    def save(self, directory: Path) -> None:
        """Write trajectory.npz and trajectory.csv into ``directory`` (byte-identical for equal data)."""
        directory.mkdir(parents=True, exist_ok=True)
        arrays = {name: getattr(self, name) for name in ARRAYS}
        meta = {
            "q_names": list(self.q_names),
            "v_names": list(self.v_names),
            "contact_names": list(self.contact_names),
            "leg_names": list(self.leg_names),
            "leg_feet": list(self.leg_feet),
            "state_names": list(self.state_names),
            "actuator_names": list(self.actuator_names),
            "total_mass": self.total_mass,
            "gravity": self.gravity,
            "planar": self.planar,
        }
        if any(len(soles) > 1 for soles in self.leg_soles):  # else each leg's foot alone
            meta["leg_soles"] = [list(soles) for soles in self.leg_soles]
        arrays["meta"] = np.frombuffer(json.dumps(meta, sort_keys=True).encode(), dtype=np.uint8)
        with atomic_path(directory / "trajectory.npz") as tmp, open(tmp, "wb") as f:
            _write_npz(f, arrays)  # into the file: its bytes whole in memory took as much again
            f.flush()
            os.fsync(f.fileno())
        with (
            atomic_path(directory / "trajectory.csv") as tmp,
            open(tmp, "w", encoding="utf-8", newline="") as f,
        ):
            self.write_csv(f)  # a row at a time: the whole text of a long run may not fit
            f.flush()
            os.fsync(f.fileno())

    @classmethod
    def load(cls, directory: Path) -> Trajectory:
        """Read ``directory/trajectory.npz``; a missing, truncated or foreign file (not one
        ``save`` wrote) raises ``UsageError`` saying which, and what to do."""
        path = Path(directory) / "trajectory.npz"
        if not path.is_file():
            raise UsageError(
                f"no trajectory.npz in {directory}: give the directory a run wrote "
                "(legdsl run FILE.leg --out DIR)"
            )
        again = "; run the creature again (legdsl run FILE.leg --out DIR)"
        _refuse_incomplete(Path(directory), again)
        _refuse_foreign(path, again)
        try:
            with np.load(path, allow_pickle=False) as data:
                missing = [k for k in (*ARRAYS, "meta") if k not in data.files and k not in LATER]
                if missing:
                    raise UsageError(
                        f"{path} is not a legdsl trajectory: it lacks {', '.join(missing)}{again}"
                    )
                arrays = {name: data[name] for name in ARRAYS if name in data.files}
                meta = json.loads(bytes(data["meta"]).decode())
        except (UsageError, MemoryError):  # too little memory to read it is not a damaged file
            raise
        except Exception as e:  # a truncated zip, a damaged entry, bad JSON in meta, ...
            if "pickle" in str(e):  # numpy's advice to load it unsafely: never to be passed on
                raise UsageError(
                    f"{path} is not a legdsl trajectory: it holds Python objects, where a run's "
                    f"trajectory holds arrays of numbers{again}"
                ) from None
            raise UsageError(f"cannot read {path} ({type(e).__name__}: {e}){again}") from None
        try:
            if not isinstance(meta, dict):
                raise TypeError("it is not an object")
            names = ("q_names", "v_names", "contact_names", "leg_names", "state_names")
            for key in (*names, "actuator_names"):
                if not all(isinstance(n, str) for n in meta.get(key, [])):
                    raise TypeError(f"{key} is not a list of names")
            feet = meta["leg_feet"]
            if not isinstance(feet, list) or not all(
                isinstance(i, int) and 0 <= i < len(meta["contact_names"]) for i in feet
            ):
                raise TypeError("leg_feet is not a list of contact indices")
            soles = meta.get("leg_soles", [])
            if not isinstance(soles, list) or not all(
                isinstance(row, list)
                and row
                and all(isinstance(i, int) and 0 <= i < len(meta["contact_names"]) for i in row)
                for row in soles
            ):
                raise TypeError("leg_soles is not a list of contact indices per leg")
            meta["leg_soles"] = tuple(tuple(row) for row in soles)
            for key in ("total_mass", "gravity"):
                value = meta.get(key, 0.0)
                if isinstance(value, bool) or not isinstance(value, int | float):
                    raise TypeError(f"{key} is not a number")
                if not math.isfinite(value) or value < 0:
                    raise ValueError(f"{key} is {value}")
            if not isinstance(meta.get("planar", True), bool):
                raise TypeError("planar is not true or false")
            for key in ("q_names", "v_names", "contact_names", "leg_names", "leg_feet"):
                meta[key] = tuple(meta[key])
            meta["state_names"] = tuple(meta.get("state_names", ()))
            meta["actuator_names"] = tuple(meta.get("actuator_names", ()))
            unknown = set(meta) - {f.name for f in fields(cls)}
            if unknown:
                raise KeyError(", ".join(sorted(unknown)))
            older = [name for name in LATER if name not in arrays]  # a run from before them
            for name in older:
                arrays[name] = np.zeros((len(arrays["t"]), 0))
                meta["actuator_names"] = ()
            trajectory = cls(**arrays, **meta, extra={"unrecorded": older} if older else {})
        except (KeyError, TypeError, ValueError) as e:
            raise UsageError(f"{path}: its meta data is damaged ({e}){again}") from None
        trajectory._check_shapes(path, again)
        return trajectory

    def _check_shapes(self, path: Path, again: str) -> None:
        n = len(self.t) if self.t.ndim == 1 else -1
        want = {
            "q": 2, "v": 2, "contact": 2, "force": 3, "com": 2, "com_vel": 2, "root_pos": 2,
            "root_rpy": 2, "leg_length": 2, "leg_spring_energy": 2, "kinetic": 1,
            "potential": 1, "elastic": 1, "state": 1, "speed_command": 1, "work_positive": 2,
            "work_negative": 2,
        }  # fmt: skip
        for name, ndim in want.items():
            a = getattr(self, name)
            if n < 0 or a.ndim != ndim or a.shape[0] != n:
                raise UsageError(f"{path}: the array {name} has the wrong shape {a.shape}{again}")
        if n == 0:  # a run records its start, even one that falls at t = 0
            raise UsageError(f"{path}: the run recorded no samples{again}")
        # real numbers only (complex or text would fail later in the readers), indices integers
        for name in ("t", *want):
            a, kinds = getattr(self, name), "iu" if name in ("state", "contact") else "iuf"
            if a.dtype.kind not in kinds and not (name == "contact" and a.dtype.kind == "b"):
                raise UsageError(
                    f"{path}: the array {name} holds {a.dtype} values, not "
                    f"{'integers' if len(kinds) == 2 else 'real numbers'}{again}"
                )
        t = self.t
        if not np.issubdtype(t.dtype, np.number) or not (
            np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)
        ):
            raise UsageError(f"{path}: its times are not finite and increasing{again}")
        for name in ("q", "v", "com", "root_pos", "root_rpy"):  # a run records finite states only
            a = getattr(self, name)
            if not np.issubdtype(a.dtype, np.number) or not np.all(np.isfinite(a)):
                raise UsageError(f"{path}: the array {name} is not all finite numbers{again}")
        # the exports write times and positions as float32; positions past it are a
        # divergence's last sample (5 steps between its checks flung a stiff rig to 1e40 m),
        # which the exports refuse (``legdsl.export.motion``) and metrics and plots read;
        # past COMPUTABLE their squares overflow
        for name, most in (("t", FLOAT32_MAX), ("q", COMPUTABLE), ("com", COMPUTABLE),
                           ("root_pos", COMPUTABLE)):  # fmt: skip
            a = getattr(self, name)
            if a.size and np.max(np.abs(a)) >= most:  # a welded creature has no q
                raise UsageError(f"{path}: the array {name} holds values too large{again}")
        if self.q.shape[1] != len(self.q_names) or self.v.shape[1] != len(self.v_names):
            raise UsageError(f"{path}: q or v does not match its coordinate names{again}")
        if self.contact.shape[1] != len(self.contact_names) or self.force.shape[1:] != (
            len(self.contact_names),
            3,
        ):
            raise UsageError(f"{path}: contact or force does not match its contact names{again}")
        legs = len(self.leg_names)
        if not (self.leg_length.shape[1] == self.leg_spring_energy.shape[1] == legs
                == len(self.leg_feet)) or (self.leg_soles and (
                len(self.leg_soles) != legs
                or any(row[0] != f for row, f in zip(self.leg_soles, self.leg_feet, strict=True))
            )):  # fmt: skip
            raise UsageError(f"{path}: the leg arrays do not match its leg names{again}")
        if not (self.work_positive.shape[1] == self.work_negative.shape[1]
                == len(self.actuator_names)):  # fmt: skip
            raise UsageError(f"{path}: the work arrays do not match its actuator names{again}")
        if self.state.size and (self.state.max() >= max(len(self.state_names), 1)
                                or self.state.min() < -1):  # fmt: skip
            raise UsageError(f"{path}: a controller state index is out of range{again}")

    def _state_name(self, index: int) -> str:
        """The controller state's name ('' before the controller or without one)."""
        return self.state_names[index] if 0 <= index < len(self.state_names) else ""

    def write_csv(self, out: TextIO) -> None:
        """One row per sample into ``out``; column names carry their units, but ``q.*`` and
        ``v.*`` (m or rad by joint: the arrays do not say which, ``analysis.series_units``)."""
        cols: list[tuple[str, np.ndarray]] = [("t [s]", self.t)]
        for i, name in enumerate(self.q_names):
            cols.append((f"q.{name}", self.q[:, i]))
        for i, name in enumerate(self.v_names):
            cols.append((f"v.{name}", self.v[:, i]))
        for i, name in enumerate(self.contact_names):
            cols.append((f"{name}.contact", self.contact[:, i]))
            for j, axis in enumerate("xyz"):
                cols.append((f"{name}.f{axis} [N]", self.force[:, i, j]))
        for j, axis in enumerate("xyz"):
            cols.append((f"com.{axis} [m]", self.com[:, j]))
        for j, axis in enumerate("xyz"):
            cols.append((f"com.v{axis} [m/s]", self.com_vel[:, j]))
        for j, name in enumerate(("roll", "pitch", "yaw")):
            cols.append((f"root.{name} [rad]", self.root_rpy[:, j]))
        for i, name in enumerate(self.leg_names):
            cols.append((f"{name}.length [m]", self.leg_length[:, i]))
        cols += [
            ("kinetic [J]", self.kinetic),
            ("potential [J]", self.potential),
            ("elastic [J]", self.elastic),
            ("state", self.state),
            ("state_name", np.array([self._state_name(i) for i in self.state], dtype=object)),
            ("speed_command [m/s]", self.speed_command),
        ]
        for i, name in enumerate(self.actuator_names):  # last: the columns before keep their place
            cols.append((f"{name}.work_positive [J]", self.work_positive[:, i]))
            cols.append((f"{name}.work_negative [J]", self.work_negative[:, i]))
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow([c[0] for c in cols])
        for row in range(len(self)):
            writer.writerow([_fmt(c[1][row]) for c in cols])


def _refuse_foreign(path: Path, again: str) -> None:
    """A trajectory.npz that is no zip archive (a text file, a bare .npy array, an empty
    file) is not a legdsl trajectory: said so, where numpy's own words were passed on (for a
    text file: "load it unsafely using the allow_pickle= keyword argument")."""
    try:
        with open(path, "rb") as f:
            head = f.read(512)
    except OSError:
        return  # numpy's reading says what is wrong
    if head.startswith(b"PK\x03\x04"):
        return
    if not head:
        what = "it is empty"
    elif head.startswith(b"\x93NUMPY"):
        what = "it is a single numpy array (.npy), where a run's trajectory.npz is a zip of arrays"
    elif _looks_like_text(head):
        what = "it is text, where a run's trajectory.npz is a zip of arrays"
    else:
        what = "it is not a zip of arrays, as a run's trajectory.npz is"
    raise UsageError(f"{path} is not a legdsl trajectory: {what}{again}")


def _looks_like_text(head: bytes) -> bool:
    """Whether the first bytes of a file are UTF-8 text (a character cut at their end too)."""
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError as e:
        if e.start < len(head) - 3:
            return False
        text = head[: e.start].decode("utf-8")
    return all(c.isprintable() or c in "\n\r\t" for c in text)


def _refuse_incomplete(directory: Path, again: str) -> None:
    """A run directory whose writing was cut short (a kill, a full disk) has its run.json
    marked ``incomplete`` and may hold an older run's trajectory.npz, which would be measured
    and drawn without a word."""
    try:
        status = json.loads((directory / "run.json").read_bytes()).get("status")
    except (OSError, ValueError, AttributeError, RecursionError):
        return  # none, or damaged: the readers of run.json say so
    if status == "incomplete":
        raise UsageError(
            f"{directory}/run.json says the run was still being written when it stopped "
            f"(killed, or the disk refused it), so its trajectory.npz may be an older run's{again}"
        )


def load_run_info(directory: Path) -> dict[str, Any]:
    """``directory/run.json`` as a dict; missing, not JSON or not an object raises ``UsageError``."""
    path = Path(directory) / "run.json"
    if not path.is_file():
        raise UsageError(
            f"no run.json in {directory}: give the directory a run wrote "
            "(legdsl run FILE.leg --out DIR)"
        )
    try:
        info = json.loads(path.read_bytes().decode("utf-8"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as e:
        raise UsageError(
            f"cannot read {path}: it is not JSON ({e}); run the creature again"
        ) from None
    if not isinstance(info, dict):
        raise UsageError(f"{path} is not a run's record (a JSON object); run the creature again")
    again = "; run the creature again (legdsl run FILE.leg --out DIR)"
    kinds: dict[str, Any] = {
        "source": str, "creature": str, "status": str, "message": str, "controller": (str, type(None)),
        "options": dict, "settings": dict, "inputs": dict, "params": dict, "paths": (list, type(None)),
        "path_reports": list, "events": list, "samples": int, "steps": int,
        "sim_time": (int, float),
    }  # fmt: skip
    for key, kind in kinds.items():
        if key in info and (not isinstance(info[key], kind) or isinstance(info[key], bool)):
            raise UsageError(f"{path}: '{key}' has the wrong type{again}")
    scale = info.get("scale")  # legdsl run --scale L: the factor the outputs were scaled by
    if scale is not None and not (
        isinstance(scale, int | float) and not isinstance(scale, bool) and 0 < scale < math.inf
    ):
        raise UsageError(f"{path}: 'scale' is not a positive number ({str(scale)[:20]}){again}")
    for event in info.get("events", []):
        if not (
            isinstance(event, dict)
            and isinstance(event.get("t"), int | float)
            and math.isfinite(event["t"])
            and isinstance(event.get("kind"), str)
        ):
            raise UsageError(f"{path}: an event is damaged ({str(event)[:60]}){again}")
    for spec in info.get("paths") or []:
        if not _sound_path(spec):
            raise UsageError(f"{path}: a path is damaged ({str(spec)[:60]}){again}")
    return info


def _sound_path(spec: object) -> bool:
    """Whether ``spec`` (a path in run.json) reads back as a path the readers can follow."""
    from legdsl.ir.paths import SHAPES, PathSpec
    from legdsl.sim.path_tracking import PathGeometry

    if not isinstance(spec, dict):
        return False
    try:
        checked = PathSpec.from_json(spec)
        numbers = [*checked.center, checked.radius, checked.lookahead]
        numbers += [x for point in checked.points for x in point]
        if checked.shape not in SHAPES or not all(math.isfinite(x) for x in numbers):
            return False
        if checked.shape == "circle" and not (checked.radius > 0 and checked.turn in (1, -1)):
            return False
        geometry = PathGeometry(checked)
        return math.isfinite(geometry.length) and geometry.length > 0
    except (AssertionError, KeyError, TypeError, ValueError, IndexError, OverflowError):
        return False


def _fmt(value: Any) -> str:
    if isinstance(value, str):
        return value
    x = float(value)
    if math.isnan(x):
        return ""
    return repr(int(x)) if x.is_integer() and abs(x) < 1e15 else f"{x:.9g}"


def _write_npz(f: BinaryIO, arrays: dict[str, np.ndarray]) -> None:
    # deflated (a 20 s run's samples shrink to about a third), a chunk at a time; the zip
    # entries carry a fixed 1980 date and zlib is deterministic: equal data, equal bytes
    np.savez_compressed(f, **arrays)  # type: ignore[arg-type]


def empty(n: int, nq: int, nv: int, nc: int, nl: int, na: int = 0, **meta: Any) -> Trajectory:
    """Arrays for ``n`` samples (the recorder fills them, ``grown`` when full, cut with ``head``)."""
    return Trajectory(
        t=np.zeros(n),
        q=np.zeros((n, nq)),
        v=np.zeros((n, nv)),
        contact=np.zeros((n, nc), dtype=np.int8),
        force=np.zeros((n, nc, 3)),
        com=np.zeros((n, 3)),
        com_vel=np.zeros((n, 3)),
        root_pos=np.zeros((n, 3)),
        root_rpy=np.zeros((n, 3)),
        leg_length=np.zeros((n, nl)),
        leg_spring_energy=np.zeros((n, nl)),
        kinetic=np.zeros(n),
        potential=np.zeros(n),
        elastic=np.zeros(n),
        state=np.full(n, -1, dtype=np.int16),
        speed_command=np.full(n, np.nan),
        work_positive=np.zeros((n, na)),
        work_negative=np.zeros((n, na)),
        **meta,
    )
