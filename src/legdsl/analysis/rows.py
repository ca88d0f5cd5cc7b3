"""The averaged rows of the gait metrics (Table 2's quantities): means over strides,
stances and steps, and the friction maxima."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from legdsl.analysis import averages
from legdsl.analysis.friction import friction_rows
from legdsl.analysis.results import Flight, Friction, Stance, Summary
from legdsl.analysis.strides import Unit
from legdsl.sim.trajectory import Trajectory


def stat(
    key: str, label: str, values: Sequence[float], weights: Sequence[float] | None = None
) -> Summary:
    """The mean of the finite ``values`` (weighted by ``weights`` where given) and their
    spread from one to the next (the sample standard deviation, unweighted)."""
    kept = [i for i, v in enumerate(values) if math.isfinite(v)]
    x = np.asarray([values[i] for i in kept], dtype=float)
    w = None if weights is None else np.asarray([weights[i] for i in kept], dtype=float)
    mean, std = averages.mean(x, w), averages.spread(x)  # finite for any finite values
    how = "mean" if weights is None else "weighted mean"
    return Summary(key, label, mean, std, int(x.size), how)


def summary_rows(
    tr: Trajectory,
    units: list[Unit],
    per_stride: dict[str, list[float]],
    stances: list[Stance],
    flights: list[Flight],
    friction: list[Friction],
    joint: str | None,
    against: str | None,
    joint_slides: bool = False,
) -> list[Summary]:
    ps = per_stride
    legs = [u for u in units if u.kind in ("leg", "contact")]
    groups = [u for u in units if u.kind == "group"]
    rows = [
        stat("stride_duration", "stride duration (s)", ps["duration"]),
        stat("stride_length", "stride length (m)", ps["length"]),
        stat("flight_duration", "flight duration (s)", [f.duration for f in flights]),
    ]
    landings = sorted({f.before for f in flights})
    for name in landings if len(landings) > 1 else []:  # one kind of flight: the row above
        rows.append(
            stat(
                f"flight_duration_before_{name}",
                f"flight duration before {name} (s)",
                [f.duration for f in flights if f.before == name],
            )
        )
    rows.append(stat("flight_time", "flight time per stride (s)", ps["flight_time"]))
    # the same kinds of flight per stride, 0 in a stride without one: a phase of the stride as
    # Table 2 has it (the bound's extended flight was 0.027 s over the 20 strides of 38 that
    # had one, 0.015 s a stride)
    for name in landings if len(landings) > 1 else []:
        each = [0.0] * len(ps["duration"])
        for flight in flights:
            if flight.before == name and flight.stride >= 0:
                each[flight.stride] += flight.duration
        rows.append(
            stat(f"flight_time_before_{name}", f"flight before {name} per stride (s)", each)
        )
    rows.append(
        stat("apex_height", "apex height of the centre of mass (m)", apex_heights(tr, flights))
    )
    leg_stances = [s for s in stances if s.kind != "group"]
    rows.append(stat("stance_duration", "stance duration (s)", [s.duration for s in leg_stances]))
    for u in (legs if len(legs) > 1 else []) + groups:
        rows.append(
            stat(
                f"stance_duration_{u.name}",
                f"stance duration, {u.name} (s)",
                [s.duration for s in stances if s.unit == u.name],
            )
        )
    if tr.leg_names:
        changes = [s.leg_length_change for s in stances if s.kind == "leg"]
        rows.append(stat("leg_length_change", "change of leg length during support (m)", changes))
        for u in legs if len(legs) > 1 else []:
            rows.append(
                stat(
                    f"leg_length_change_{u.name}",
                    f"change of leg length during support, {u.name} (m)",
                    [s.leg_length_change for s in stances if s.unit == u.name],
                )
            )
    rows += [
        stat("pitch_magnitude", "pitch magnitude (deg)", ps["pitch_magnitude"]),
        stat("roll_magnitude", "roll magnitude (deg)", ps["roll_magnitude"]),
        # weighted by the strides' durations: the distance run over the strides' time (a
        # stumbling gait's short and long strides made a plain mean read 1.035 m/s where it
        # ran 0.962)
        stat("running_speed", "running speed (m/s)", ps["speed"], ps["duration"]),
        stat("desired_speed", "desired running speed (m/s)", ps["speed_command"], ps["duration"]),
        stat("speed_error", "error in running speed (m/s)", ps["speed_error"], ps["duration"]),
        stat(
            "peak_vertical_acceleration",
            "peak vertical acceleration (g)",
            ps["peak_vertical_acceleration"],
        ),
    ]
    if tr.planar:  # a planar run has no roll
        rows = [r for r in rows if r.key != "roll_magnitude"]
    if joint is not None:
        unit = "m" if joint_slides else "deg"
        rows.append(
            stat("joint_magnitude", f"magnitude of {joint} ({unit})", ps["joint_magnitude"])
        )
    if against is not None:
        rows.append(
            stat(
                "joint_correlation",
                f"correlation of {joint} with {against} (-)",
                ps["joint_correlation"],
            )
        )
    if tr.leg_names:
        taken = ps["energy_taken_up"]
        rows += [
            stat("stored_energy", "elastic energy stored per stride (J)", ps["stored_energy"]),
            stat(
                "energy_fluctuation",
                "external energy fluctuation per stride (J)",
                ps["energy_fluctuation"],
            ),
            stat("energy_taken_up", "external energy taken up per stride (J)", taken),
            # weighted by what each stride took up: the window's stored over its taken up
            stat(
                "energy_recirculated",
                "elastic energy recirculated per step (-)",
                ps["energy_recirculated"],
                taken,
            ),
        ]
    for f in friction:
        rows += friction_rows(f)
    return rows


def apex_heights(tr: Trajectory, flights: Sequence[Flight]) -> list[float]:
    """The highest the centre of mass rises in each flight (its z, in the world frame)."""
    out = []
    for f in flights:
        inside = (tr.t >= f.t_start) & (tr.t <= f.t_end)
        if inside.any():
            out.append(float(tr.com[inside, 2].max()))
    return out
