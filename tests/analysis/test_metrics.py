"""Gait metrics on synthetic runs whose answers are known in closed form.

Every run is sampled at 1 kHz, so an event time is off by less than one
sample: durations are checked to 1 ms, and quantities read at a sampled peak
to the error a 1 ms sampling makes there.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics, parse_groups
from legdsl.analysis.results import MetricsError
from legdsl.analysis.support import support_phases
from legdsl.analysis.table2 import TABLE2, compare_table
from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory, empty

DT = 0.001
M, G = 17.0, 9.81
MS = DT + 1e-9  # one sample, with room for floating point


def _blank(n: int, contacts: tuple[str, ...], legs: tuple[str, ...], planar: bool) -> Trajectory:
    names = ("x", "z", "pitch", "tail_base", "hip")
    tr = empty(
        n, len(names), len(names), len(contacts), len(legs),
        q_names=names, v_names=names, contact_names=contacts, leg_names=legs,
        leg_feet=tuple(range(len(legs))), total_mass=M, gravity=G, planar=planar,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * DT
    return tr


# ---------------------------------------------------------------- a bouncing point mass


@dataclass
class Hopper:
    """A point mass bouncing vertically on a lossless linear leg spring k = M w^2 while it
    travels forward at u: stance and flight durations are closed-form."""

    w: float = 33.0  # rad/s
    v0: float = 1.2  # m/s: vertical speed at touchdown and liftoff
    u: float = 4.3  # m/s
    z_td: float = 1.0  # m: height at touchdown
    first_touchdown: float = 0.0  # s: set in __post_init__ unless given

    def __post_init__(self) -> None:
        self.stance = (math.pi + 2 * math.atan(G / (self.w * self.v0))) / self.w
        self.flight = 2 * self.v0 / G
        self.period = self.stance + self.flight
        self.first_touchdown = self.first_touchdown or self.flight / 2  # start at the apex
        self.max_compression = G / self.w**2 + math.hypot(G / self.w**2, self.v0 / self.w)

    def touchdowns(self, end: float) -> np.ndarray:
        k = np.arange(int(end / self.period) + 2)
        times = self.first_touchdown + k * self.period
        return times[(times >= 0) & (times <= end)]

    def run(self, duration: float, command: float = 5.0) -> Trajectory:
        n = round(duration / DT) + 1
        tr = _blank(n, ("toe",), ("main",), planar=True)
        t = tr.t
        p = np.mod(t - self.first_touchdown, self.period)  # time since the last touchdown
        on = p < self.stance
        a, b = G / self.w**2, self.v0 / self.w
        q = p - self.stance  # time since liftoff
        z = np.where(
            on, self.z_td - a + a * np.cos(self.w * p) - b * np.sin(self.w * p),
            self.z_td + self.v0 * q - G * q**2 / 2,
        )  # fmt: skip
        vz = np.where(
            on, -a * self.w * np.sin(self.w * p) - self.v0 * np.cos(self.w * p), self.v0 - G * q
        )
        squeeze = np.where(on, self.z_td - z, 0.0)
        tr.contact[:, 0] = on
        tr.force[:, 0, 2] = M * self.w**2 * squeeze
        tr.com[:, 0], tr.com[:, 2] = self.u * t, z
        tr.com_vel[:, 0], tr.com_vel[:, 2] = self.u, vz
        tr.leg_length[:, 0] = 0.5 - squeeze
        tr.leg_spring_energy[:, 0] = 0.5 * M * self.w**2 * squeeze**2
        phase = 2 * np.pi * t / self.period
        tr.root_rpy[:, 1] = np.radians(6.0) * np.sin(phase) + 0.1
        tr.q[:, 3] = np.radians(15.0) * np.sin(phase)  # tail_base
        tr.q[:, 4] = -0.4 * np.sin(phase) + 0.3  # hip, in anti-phase
        tr.speed_command[:] = command
        return tr


def test_hopper_strides_stances_and_flights() -> None:
    h = Hopper()
    m = compute_metrics(h.run(4.0))
    assert m.n_strides == len(h.touchdowns(4.0)) - 1 >= 8
    assert m.reference == "main"
    assert m.value("stride_duration") == pytest.approx(h.period, abs=MS)
    assert m.value("stance_duration") == pytest.approx(h.stance, abs=MS)
    assert m.value("flight_duration") == pytest.approx(h.flight, abs=MS)
    assert m.value("flight_time") == pytest.approx(h.flight, abs=MS)
    assert m.per_stride["flight_count"] == [1.0] * m.n_strides
    assert m.value("stride_length") == pytest.approx(h.u * h.period, abs=h.u * MS)
    # every stride is exactly as long as its duration times the forward speed
    assert np.allclose(m.per_stride["length"], h.u * np.array(m.per_stride["duration"]))
    assert [f.before for f in m.flights] == ["main"] * len(m.flights)


def test_hopper_speed_accelerations_and_leg_length() -> None:
    h = Hopper()
    m = compute_metrics(h.run(4.0, command=5.0))
    assert m.value("running_speed") == pytest.approx(h.u)
    assert m.value("desired_speed") == pytest.approx(5.0)
    assert m.value("speed_error") == pytest.approx(h.u - 5.0)
    # the spring force k * squeeze at its peak, less gravity, in g
    peak_g = h.w**2 * h.max_compression / G - 1
    assert m.value("peak_vertical_acceleration") == pytest.approx(peak_g, abs=2e-3)
    # the first stance sample may already be squeezed by up to v0 * dt
    assert m.value("leg_length_change") == pytest.approx(h.max_compression, abs=h.v0 * MS)
    assert m.value("pitch_magnitude") == pytest.approx(12.0, abs=1e-2)
    assert "roll_magnitude" not in {s.key for s in m.summaries}  # planar: no roll


def test_hopper_recirculates_all_its_external_energy_swing() -> None:
    # Lossless: whatever external energy the mass loses in stance is in the spring.
    h = Hopper()
    m = compute_metrics(h.run(4.0))
    # the spring is read a sample before the least length: short by (w dt)^2 of its peak at
    # most, and of what it took up since touchdown (a little less than the peak) a bit more
    short = 1.5 * (h.w * DT) ** 2
    assert m.value("energy_recirculated") == pytest.approx(1.0, abs=short)
    stored = 0.5 * M * h.w**2 * h.max_compression**2
    assert m.value("stored_energy") == pytest.approx(stored, rel=short)
    assert m.value("energy_fluctuation") == pytest.approx(stored, rel=1e-3)
    assert m.value("energy_taken_up") == pytest.approx(stored, rel=1e-3)  # one fall a stride


def test_joint_magnitude_and_anti_phase_correlation() -> None:
    m = compute_metrics(Hopper().run(3.0), joint="tail_base", against="hip")
    assert m.value("joint_magnitude") == pytest.approx(30.0, abs=1e-2)
    assert m.value("joint_correlation") == pytest.approx(-1.0, abs=1e-9)
    assert m.summary("joint_magnitude").label == "magnitude of tail_base (deg)"


def test_a_command_near_the_largest_double_is_averaged_without_overflow() -> None:
    """set speed=1e308m/s (finite, accepted): numpy's mean overflowed ('overflow encountered
    in reduce' leaked), and desired speed and its error were NaN with n = 0 over strides that
    had a command; each is the command's now, without a warning."""
    import warnings

    h = Hopper()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = compute_metrics(h.run(4.0, command=1e308))
    strides = m.n_strides
    assert m.value("desired_speed") == 1e308 and m.summary("desired_speed").n == strides > 0
    assert m.value("speed_error") == pytest.approx(-1e308) and m.summary("speed_error").std == 0


def test_without_a_speed_command_the_error_is_nan_and_json_null() -> None:
    m = compute_metrics(Hopper().run(2.0, command=math.nan))
    assert math.isnan(m.value("speed_error"))
    data = m.to_dict()
    assert data["summary"]["speed_error"]["value"] is None
    json.dumps(data, allow_nan=False)


def test_window_counts_only_complete_strides_inside_it() -> None:
    h = Hopper()
    lo, hi = 3.0, 7.0
    tds = h.touchdowns(10.0)
    assert np.min(np.abs(tds[:, None] - [lo, hi])) > 0.002  # no touchdown on an edge
    inside = tds[(tds >= lo) & (tds <= hi)]
    m = compute_metrics(h.run(10.0), t_from=lo, t_to=hi)
    assert m.n_strides == len(inside) - 1
    assert m.per_stride["t_start"][0] == pytest.approx(inside[0], abs=MS)
    assert m.per_stride["t_end"][-1] == pytest.approx(inside[-1], abs=MS)
    assert all(lo <= s.t_touchdown and s.t_liftoff <= hi for s in m.stances)
    assert all(lo <= f.t_start and f.t_end <= hi for f in m.flights)


def test_run_that_ends_mid_stance_drops_the_open_stance() -> None:
    h = Hopper()
    tds = h.touchdowns(3.0)
    cut = tds[5] + h.stance / 2  # in the middle of the sixth stance
    tr = h.run(3.0).head(round(cut / DT))
    m = compute_metrics(tr)
    assert m.n_strides == 5
    assert len(m.stances) == 5  # the sixth has no liftoff yet
    assert all(s.duration == pytest.approx(h.stance, abs=MS) for s in m.stances)


def test_run_that_starts_in_stance_skips_the_stance_it_did_not_see_begin() -> None:
    h = Hopper(first_touchdown=-0.05)  # t = 0 is 50 ms into a stance
    m = compute_metrics(h.run(2.0))
    first = -0.05 + h.period
    assert m.per_stride["t_start"][0] == pytest.approx(first, abs=MS)
    assert m.stances[0].t_touchdown == pytest.approx(first, abs=MS)
    assert all(s.duration == pytest.approx(h.stance, abs=MS) for s in m.stances)


# ---------------------------------------------------------------- gaits from contact patterns


def _pattern(n: int, period: int, shift: int, spans: list[tuple[int, int]]) -> np.ndarray:
    """1 where ``(i + shift) % period`` falls in one of the half-open sample spans."""
    phase = (np.arange(n) + shift) % period
    return np.any([(phase >= a) & (phase < b) for a, b in spans], axis=0).astype(np.int8)


def biped_run(n: int = 4001) -> Trajectory:
    """3D two-leg run, 400-sample stride: left stance [0, 120), right [200, 320), flights of
    80 samples between; heading 30 deg, swaying sideways, rolling and pitching."""
    tr = _blank(n, ("foot_l", "foot_r"), ("left", "right"), planar=False)
    shift = 150  # the run opens in flight
    tr.contact[:, 0] = _pattern(n, 400, shift, [(0, 120)])
    tr.contact[:, 1] = _pattern(n, 400, shift, [(200, 320)])
    phase = 2 * np.pi * (np.arange(n) + shift) / 400
    heading = math.radians(30)
    along = np.array([math.cos(heading), math.sin(heading), 0.0])
    side = np.array([-math.sin(heading), math.cos(heading), 0.0])
    t = tr.t
    tr.com[:] = np.outer(2.0 * t, along) + np.outer(0.03 * np.sin(phase), side)
    tr.com_vel[:] = 2.0 * along + np.outer(0.03 * 2 * np.pi / 0.4 * np.cos(phase), side)
    tr.com[:, 2] = 0.9
    tr.root_rpy[:, 0] = np.radians(5.0) * np.sin(phase)  # roll: 10 deg peak to peak
    tr.root_rpy[:, 1] = np.radians(1.5) * np.sin(2 * phase)  # pitch: 3 deg
    tr.root_rpy[:, 2] = heading
    for leg, depth in ((0, 0.04), (1, 0.02)):
        tau = (np.arange(n) + shift - 200 * leg) % 400
        tr.leg_length[:, leg] = 0.8 - depth * np.where(tau < 120, np.sin(np.pi * tau / 120), 0)
    tr.speed_command[:] = 1.8
    return tr


def test_biped_run_two_flights_per_stride_and_per_leg_rows() -> None:
    m = compute_metrics(biped_run())
    # left touchdowns at samples 250, 650, ..., 3850: ten of them, nine strides
    assert m.n_strides == 9
    assert m.value("stride_duration") == pytest.approx(0.400, abs=1e-9)
    assert m.per_stride["flight_count"] == [2.0] * 9
    assert m.value("flight_time") == pytest.approx(0.160, abs=1e-9)
    assert m.value("flight_duration_before_left") == pytest.approx(0.080, abs=1e-9)
    assert m.value("flight_duration_before_right") == pytest.approx(0.080, abs=1e-9)
    assert m.value("stance_duration_left") == pytest.approx(0.120, abs=1e-9)
    assert m.value("stance_duration_right") == pytest.approx(0.120, abs=1e-9)
    assert m.value("leg_length_change_left") == pytest.approx(0.04, abs=1e-9)
    assert m.value("leg_length_change_right") == pytest.approx(0.02, abs=1e-9)
    assert m.value("leg_length_change") == pytest.approx(0.03, abs=1e-3)


def gallop_run(n: int = 4001) -> Trajectory:
    """A biped gallop, 400-sample stride: left stance [0, 140), right [60, 200): single
    support on the left for 60 samples, double support 80, single on the right 60, then a
    flight of 200."""
    tr = biped_run(n)
    shift = 150
    tr.contact[:, 0] = _pattern(n, 400, shift, [(0, 140)])
    tr.contact[:, 1] = _pattern(n, 400, shift, [(60, 200)])
    return tr


def test_gallop_single_and_double_support_rows() -> None:
    m = compute_metrics(gallop_run())
    assert m.value("single_support_duration") == pytest.approx(0.060, abs=1e-9)
    assert m.value("single_support_duration_left") == pytest.approx(0.060, abs=1e-9)
    assert m.value("single_support_duration_right") == pytest.approx(0.060, abs=1e-9)
    assert m.value("double_support_duration") == pytest.approx(0.080, abs=1e-9)
    assert m.summary("double_support_duration").n == 10  # every complete one in the run
    assert m.value("double_support_fraction") == pytest.approx(0.2, abs=2e-3)
    assert m.value("flight_duration") == pytest.approx(0.200, abs=1e-9)
    assert "double support duration (s)" in m.table()


def test_a_run_without_double_support_has_no_support_rows() -> None:
    m = compute_metrics(biped_run())  # the feet never touch together
    keys = {s.key for s in m.summaries}
    assert not keys & {"single_support_duration", "double_support_duration"}


def test_support_phases_split_by_the_feet_down_and_drop_open_ends() -> None:
    t = np.arange(12) * DT
    down = np.array(
        [[1, 0]] * 2 + [[1, 1]] * 3 + [[0, 1]] * 2 + [[0, 0]] * 3 + [[1, 0]] * 2, dtype=bool
    )
    phases = support_phases(t, down, ["left", "right"], 0.0, 1.0)
    # the first (left) and last (left) runs are open: one of their ends is not seen
    assert [(p.kind, p.feet) for p in phases] == [
        ("double", ("left", "right")),
        ("single", ("right",)),
        ("flight", ()),
    ]
    assert [round(p.duration / DT) for p in phases] == [3, 2, 3]
    # a window leaves out the phases that do not lie inside it
    assert [p.kind for p in support_phases(t, down, ["left", "right"], 0.004, 1.0)] == [
        "single",
        "flight",
    ]


def test_biped_run_heading_speed_length_roll_and_pitch() -> None:
    m = compute_metrics(biped_run())
    # the sideways sway neither lengthens the stride nor adds to the speed along the heading
    assert m.value("stride_length") == pytest.approx(0.8, abs=1e-9)
    assert m.value("running_speed") == pytest.approx(2.0, abs=1e-9)
    assert m.value("speed_error") == pytest.approx(0.2, abs=1e-9)
    assert m.value("roll_magnitude") == pytest.approx(10.0, abs=1e-9)
    assert m.value("pitch_magnitude") == pytest.approx(3.0, abs=1e-9)


def test_reference_leg_can_be_chosen() -> None:
    m = compute_metrics(biped_run(), leg="right")
    assert m.reference == "right"
    assert m.per_stride["t_start"][0] == pytest.approx(0.050, abs=1e-9)  # first right touchdown
    assert m.n_strides == 9  # right touchdowns at 50, 450, ..., 3650: ten of them


def bound(n: int = 3001) -> Trajectory:
    """Quadruped bound, 434-sample stride: fl [0, 100), fr [2, 102) -> front [0, 102);
    gathered flight [102, 322); rl [322, 402), rr [324, 404) -> rear [322, 404);
    extended flight [404, 434)."""
    tr = _blank(n, ("toe_fl", "toe_fr", "toe_rl", "toe_rr"), ("fl", "fr", "rl", "rr"), False)
    spans = [(0, 100), (2, 102), (322, 402), (324, 404)]
    for c, span in enumerate(spans):
        tr.contact[:, c] = _pattern(n, 434, 200, [span])
    return tr


def test_bound_virtual_legs_and_gathered_extended_flights() -> None:
    groups = {"front": ["fl", "fr"], "rear": ["rl", "rr"]}
    m = compute_metrics(bound(), groups=groups, leg="front")
    assert m.reference == "front"
    assert m.value("stride_duration") == pytest.approx(0.434, abs=1e-9)
    assert m.value("stance_duration_front") == pytest.approx(0.102, abs=1e-9)
    assert m.value("stance_duration_rear") == pytest.approx(0.082, abs=1e-9)
    assert m.value("stance_duration_fl") == pytest.approx(0.100, abs=1e-9)
    assert m.value("stance_duration_rl") == pytest.approx(0.080, abs=1e-9)
    assert m.value("flight_duration_before_rear") == pytest.approx(0.220, abs=1e-9)  # gathered
    assert m.value("flight_duration_before_front") == pytest.approx(0.030, abs=1e-9)  # extended
    assert m.per_stride["flight_count"] == [2.0] * m.n_strides
    # without groups a flight is named after the leg that lands first
    plain = compute_metrics(bound())
    assert {f.before for f in plain.flights} == {"fl", "rl"}


def test_no_flight_phase() -> None:
    n = 5001  # a walk: left [0, 600), right [500, 1100) of a 1000-sample stride
    tr = _blank(n, ("foot_l", "foot_r"), ("left", "right"), planar=True)
    tr.contact[:, 0] = _pattern(n, 1000, 0, [(0, 600)])
    tr.contact[:, 1] = _pattern(n, 1000, 0, [(500, 1000), (0, 100)])
    assert tr.contact.any(axis=1).all()
    m = compute_metrics(tr)
    assert m.n_strides == 4  # left touchdowns at 1000 ... 5000; the one at 0 is not seen
    assert m.flights == []
    assert m.per_stride["flight_time"] == [0.0] * 4
    assert math.isnan(m.value("flight_duration"))
    assert m.summary("flight_duration").n == 0
    assert m.value("stance_duration") == pytest.approx(0.600, abs=1e-9)
    assert m.value("stride_duration") == pytest.approx(1.000, abs=1e-9)


def test_single_step_has_no_stride_but_keeps_its_stance() -> None:
    n = 601
    tr = _blank(n, ("toe",), ("main",), planar=True)
    tr.contact[200:300, 0] = 1
    tr.force[200:300, 0, 2] = M * G
    tr.force[200:300, 0, 0] = 0.25 * M * G
    m = compute_metrics(tr)
    assert m.n_strides == 0
    assert "touches down 1 time(s)" in m.note
    assert [s.duration for s in m.stances] == [pytest.approx(0.100, abs=1e-9)]
    assert m.flights == []  # the one before the step began unseen, the one after never ends
    assert m.value("stance_duration") == pytest.approx(0.100, abs=1e-9)
    assert m.value("friction_toe") == pytest.approx(0.25)
    assert math.isnan(m.value("stride_duration"))
    assert m.summary("energy_recirculated").n == 0  # no stride, no external energy swing
    assert "no strides" in m.table()
    json.dumps(m.to_dict(), allow_nan=False)


@pytest.mark.parametrize("case", ["always in flight", "always in stance", "no contacts"])
def test_run_without_touchdowns_reports_no_strides(case: str) -> None:
    contacts = () if case == "no contacts" else ("toe",)
    legs = () if case == "no contacts" else ("main",)
    tr = _blank(500, contacts, legs, planar=True)
    if case == "always in stance":
        tr.contact[:] = 1
    m = compute_metrics(tr)
    assert m.n_strides == 0
    assert m.stances == [] and m.flights == []
    if case == "no contacts":
        assert m.note == "the creature has no contacts, so it takes none (only the work rows apply)"
    else:
        assert "touches down 0 time(s)" in m.note
    text = m.table()
    assert "no strides" in text and "stride duration (s)" in text
    json.dumps(m.to_dict(), allow_nan=False)


def test_a_leg_without_a_recorded_foot_has_no_stances() -> None:
    tr = biped_run()
    tr.leg_feet = (0, -1)  # the right leg's foot is not in contact_names
    m = compute_metrics(tr)
    assert m.n_strides == 9
    assert m.summary("stance_duration_right").n == 0
    assert m.value("stance_duration_left") == pytest.approx(0.120, abs=1e-9)
    with pytest.raises(MetricsError, match="no leg, group or contact named .nobody."):
        compute_metrics(tr, leg="nobody")


# ---------------------------------------------------------------- friction and elastic energy


def _friction_run(spike_at: int = 4) -> Trajectory:
    """One contact, 100-sample stances every 300 samples. Inside a stance the needed friction
    is 0.3 + 0.22 sin(pi tau / 100) (peak 0.52 at tau = 50), with spikes of 1.9 at ``spike_at``
    and 1.7 at tau = 95, a near-zero normal force at tau = 0 and a pulling one at tau = 99."""
    n = 1501
    tr = _blank(n, ("toe",), ("main",), planar=True)
    tau = (np.arange(n) - 100) % 300
    on = tau < 100
    fn = np.where(on, 3 * M * G * np.sin(np.pi * (tau + 1) / 101), 0.0)
    mu = 0.3 + 0.22 * np.sin(np.pi * tau / 100)
    mu[tau == spike_at] = 1.9
    mu[tau == 95] = 1.7
    fn[on & (tau == 0)] = 1e-4  # a brush of the ground: the ratio would be 5e4
    mu[on & (tau == 0)] = 5.0 / 1e-4
    fn[on & (tau == 99)] = -2.0  # a ground damper pulling down: no friction cone at all
    mu[on & (tau == 99)] = 0.5
    ft = np.where(on, mu * np.abs(fn), 0.0)
    angle = math.radians(40)  # both tangential axes carry force
    tr.contact[:, 0] = on
    tr.force[:, 0, 0], tr.force[:, 0, 1] = ft * math.cos(angle), ft * math.sin(angle)
    tr.force[:, 0, 2] = fn
    return tr


def test_friction_needed_peak_and_peak_away_from_touchdown_and_liftoff() -> None:
    m = compute_metrics(_friction_run())
    (f,) = m.friction
    assert len(f.stance_peaks) == 5
    assert f.peak == pytest.approx(1.9)
    assert f.peak_interior == pytest.approx(0.52)
    assert f.skipped == 2 * 5  # the brush and the pull in every stance
    assert f.samples == 98 * 5
    assert m.value("friction_toe") == pytest.approx(1.9)
    assert m.value("friction_interior_toe") == pytest.approx(0.52)
    assert m.summary("friction_toe").n == 5


def test_friction_of_a_contact_that_never_pushes_is_not_a_number() -> None:
    tr = _friction_run()
    tr.force[:] = 0.0
    m = compute_metrics(tr)
    (f,) = m.friction
    assert math.isnan(f.peak) and math.isnan(f.peak_interior)
    assert f.samples == 0 and f.skipped == 100 * 5
    assert m.summary("friction_toe").n == 0


def test_friction_edge_is_exactly_ten_samples_at_one_khz() -> None:
    # the support starts at tau = 1 (the brush at tau = 0 pushes below the floor): tau = 11 is
    # the first sample past its first 10 ms and counts in the interior peak, tau = 10 not
    assert compute_metrics(_friction_run(spike_at=11)).friction[0].peak_interior == pytest.approx(
        1.9
    )
    assert compute_metrics(_friction_run(spike_at=10)).friction[0].peak_interior == pytest.approx(
        0.52
    )


def test_the_edges_are_measured_from_the_support_not_the_contact() -> None:
    """A contact outlasting its push: the flag on 12 ms after the force fell below 1% of the
    weight (the quadruped's 11 ms). The last 10 ms of support were counted as interior."""
    tr = _friction_run(spike_at=4)
    tau = (np.arange(len(tr.t)) - 100) % 300
    fading = (tau >= 86) & (tau < 100)
    tr.force[fading, 0, :] *= 1e-6  # support ends at tau = 86: the flag stays on to tau = 99
    tr.force[(tau == 80), 0, 0] *= 1.9 / 0.3  # a slip 6 ms before the support ends
    (f,) = compute_metrics(tr).friction
    assert f.peak_interior == pytest.approx(0.52)


def test_recirculated_energy_leaves_out_the_spring_preload() -> None:
    n = 3001  # stances [0, 100) every 300 samples
    tr = _blank(n, ("toe",), ("main",), planar=True)
    tau = np.arange(n) % 300
    bump = np.where(tau < 100, np.sin(np.pi * tau / 100), 0.0)
    preload, peak, drop = 2.0, 3.0, 0.05
    tr.contact[:, 0] = tau < 100
    tr.leg_spring_energy[:, 0] = preload + peak * bump
    tr.leg_length[:, 0] = 0.5 - 0.01 * bump  # shortest at the bump's top
    tr.com[:, 2] = 1.0 - drop * bump
    tr.com_vel[:, 0] = 3.0  # constant: only the height moves the external energy
    m = compute_metrics(tr)
    assert m.n_strides == 9
    assert m.value("stored_energy") == pytest.approx(peak, rel=1e-3)  # a sample before the top
    assert m.value("energy_fluctuation") == pytest.approx(M * G * drop)
    assert m.value("energy_recirculated") == pytest.approx(peak / (M * G * drop), rel=1e-3)


# ---------------------------------------------------------------- text, options, errors


def test_table_and_compare_table() -> None:
    m = compute_metrics(Hopper().run(3.0), joint="tail_base")
    text = m.table()
    assert "stride duration (s)" in text and "peak vertical acceleration (g)" in text
    assert "friction coefficient needed, toe, past first/last 10 ms (-)" in text
    rows = dict(TABLE2["kangaroo hop"]) | {"a quantity nobody measured (s)": (1.0, 2.0)}
    cmp = compare_table(m, rows)
    line = next(x for x in cmp.splitlines() if x.startswith("stride duration (s)"))
    assert f"{m.value('stride_duration'):.3f}" in line and "0.35" in line
    tail = next(x for x in cmp.splitlines() if x.startswith("magnitude of tail_base (deg)"))
    assert "30.000" in tail and "31" in tail
    nobody = next(x for x in cmp.splitlines() if x.startswith("a quantity nobody"))
    assert "n/a" in nobody
    assert compare_table(m, {"stride_duration": (0.35, 0.35)}).count("n/a") == 0


def test_parse_groups() -> None:
    assert parse_groups(["front=fl,fr", "rear = rl, rr"]) == {
        "front": ["fl", "fr"],
        "rear": ["rl", "rr"],
    }
    for bad in (["front"], ["=fl"], ["front="], ["a=fl", "a=fr"]):
        with pytest.raises(MetricsError):
            parse_groups(bad)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"leg": "tail"}, "no leg, group or contact named 'tail'"),
        ({"joint": "wing"}, "no coordinate named 'wing'"),
        ({"against": "hip"}, "--against needs --joint"),
        ({"groups": {"both": ["main", "other"]}}, "no leg named other"),
        ({"groups": {"main": ["main"]}}, "has the name of a leg"),
        ({"t_from": 2.0, "t_to": 1.0}, "before it starts"),
    ],
)
def test_bad_requests_are_user_errors(options: dict, message: str) -> None:
    with pytest.raises(MetricsError, match=message):
        compute_metrics(Hopper().run(1.0), **options)


def test_cli_prints_the_table_and_writes_metrics_json(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    h = Hopper()
    run = tmp_path / "run"
    h.run(3.0).save(run)
    (run / "run.json").write_text(json.dumps({"events": [], "inputs": {}, "status": "ok"}))
    args = ["metrics", str(run), "--from", "1", "--joint", "tail_base", "--against", "hip"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert out.startswith("gait metrics from 1.000 s to 3.000 s")
    assert "magnitude of tail_base (deg)" in out
    saved = json.loads((run / "metrics.json").read_text())
    assert saved["window"] == {"from": 1.0, "to": 3.0}
    assert saved["summary"]["stride_duration"]["value"] == pytest.approx(h.period, abs=MS)
    assert saved["summary"]["joint_correlation"]["value"] == pytest.approx(-1.0)
    assert all(t >= 1.0 for t in saved["strides"]["t_start"])

    assert main([*args, "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == saved


def test_cli_prints_the_run_beside_table_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    h = Hopper()
    h.run(3.0).save(tmp_path)
    args = ["metrics", str(tmp_path), "--from", "1"]
    assert main([*args, "--table2", "kangaroo hop"]) == 0
    out = capsys.readouterr().out
    beside = out[out.index("beside Table 2 of the paper, kangaroo hop:") :].splitlines()
    stride = next(line for line in beside if line.startswith("stride duration (s)"))
    assert float(stride.split()[3]) == pytest.approx(h.period, abs=MS)  # this run, then the paper
    assert stride.split()[-2:] == ["0.35", "0.35"]
    assert main([*args, "--table2", "kangaroo hops"]) == 2
    err = capsys.readouterr().err
    assert "--table2 'kangaroo hops'" in err and "'kangaroo hop'" in err


def test_cli_groups_and_reference_leg(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bound().save(tmp_path)
    args = ["metrics", str(tmp_path), "--group", "front=fl,fr", "--group", "rear=rl,rr"]
    assert main([*args, "--leg", "rear", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["reference"] == "rear"
    assert data["summary"]["flight_duration_before_rear"]["value"] == pytest.approx(0.220)
    assert data["options"]["groups"] == {"front": ["fl", "fr"], "rear": ["rl", "rr"]}


def test_cli_user_errors_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["metrics", str(tmp_path / "nowhere")]) == 2
    assert "no trajectory.npz" in capsys.readouterr().err
    Hopper().run(1.0).save(tmp_path)
    assert main(["metrics", str(tmp_path), "--leg", "wing"]) == 2
    assert "no leg, group or contact named 'wing'" in capsys.readouterr().err
    assert main(["metrics", str(tmp_path), "--group", "oops"]) == 2
    assert not (tmp_path / "metrics.json").exists()
    (tmp_path / "trajectory.npz").write_bytes(b"not a zip")
    assert main(["metrics", str(tmp_path)]) == 2
    assert "is not a legdsl trajectory: it is text" in capsys.readouterr().err


def test_cli_help_has_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["metrics", "--help"])
    assert "Example: legdsl metrics" in capsys.readouterr().out


def test_friction_needed_in_the_first_10_ms_of_stance() -> None:
    # at 1 kHz the first 10 ms of support are tau = 1..10 (the brush at tau = 0 is no
    # push): the spike at tau = 4 is in them, the one at tau = 95 (the last 10 ms) is not;
    # with the spike at tau = 20 they only see the smooth part, largest at tau = 10
    assert compute_metrics(_friction_run()).value("friction_first_toe") == pytest.approx(1.9)
    late = compute_metrics(_friction_run(spike_at=20))
    assert late.value("friction_first_toe") == pytest.approx(0.3 + 0.22 * math.sin(math.pi * 0.1))
    assert late.value("friction_toe") == pytest.approx(1.9)  # the whole stance still has it


def test_the_magnitude_of_a_sliding_joint_is_a_length(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """`--joint leg` (the hopper's slide) was reported in degrees: its travel in metres times
    57.3. The creature's file says which coordinates slide; the quaternion of a 3D root has no
    magnitude."""
    import legdsl

    root = Path(__file__).resolve().parents[2]
    monkeypatch.chdir(root)
    run = legdsl.load("creatures/hopper.leg").run(controller="hop", time=3)
    where = run.save(tmp_path / "hopper")
    assert main(["metrics", str(where), "--joint", "leg", "--against", "hip", "--json"]) == 0
    saved = json.loads(capsys.readouterr().out)
    row = saved["summary"]["joint_magnitude"]
    assert row["label"] == "magnitude of leg (m)"
    travel = [
        np.ptp(run["q.leg"][(run["t"] >= a) & (run["t"] <= b)])
        for a, b in zip(saved["strides"]["t_start"], saved["strides"]["t_end"], strict=True)
    ]
    assert row["value"] == pytest.approx(np.mean(travel), rel=1e-12)
    assert 0.01 < row["value"] < 0.35  # the leg's travel, within its limits
    assert main(["metrics", str(where), "--joint", "hip"]) == 0
    assert "magnitude of hip (deg)" in capsys.readouterr().out

    quadruped = legdsl.load("creatures/quadruped.leg").run(controller=None, time=0.2, drop=0.05)
    where = quadruped.save(tmp_path / "quadruped")
    assert main(["metrics", str(where), "--joint", "qw"]) == 2
    assert "--joint qw: a component of the root's orientation quaternion" in capsys.readouterr().err
    assert main(["metrics", str(where), "--joint", "z"]) == 0
    assert "magnitude of z (m)" in capsys.readouterr().out


def test_cli_refuses_a_window_past_the_run_as_plot_does(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--from 5 --to 9 of a 3 s run printed every row n/a with exit 0 (and --from 5 alone said
    'the window ends (3 s) before it starts'); plot said what to give."""
    Hopper().run(3.0).save(tmp_path)
    for window in (["--from", "5", "--to", "9"], ["--from", "5"]):
        assert main(["metrics", str(tmp_path), *window]) == 2
        err = capsys.readouterr().err
        assert (
            "nothing of" in err and "to measure: --from 5s is after its last sample, at 3 s" in err
        )
        assert "give --from and --to within 0 to 3 s" in err
    assert main(["metrics", str(tmp_path), "--from", "1.0001", "--to", "1.0002"]) == 2
    assert "none lies from 1.0001 to 1.0002 s" in capsys.readouterr().err
    assert main(["metrics", str(tmp_path), "--from", "2", "--to", "9"]) == 0
    assert not (tmp_path / "figure6.png").exists()


def test_cli_says_which_rows_a_run_whose_leg_file_is_gone_goes_without(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The foot clearance, touchdown speed and terrain rows need the creature: with its .leg
    file gone they were left out without a word."""
    root = Path(__file__).resolve().parents[2]
    leg = tmp_path / "hopper.leg"
    leg.write_text((root / "creatures" / "hopper.leg").read_text(encoding="utf-8"))
    run = tmp_path / "run"
    argv = ["run", str(leg), "--controller", "hop", "--time", "1", "--backend", "python",
            "--generated", str(root / "generated"), "--out", str(run)]  # fmt: skip
    assert main(argv) == 0
    assert main(["metrics", str(run)]) == 0
    out, err = capsys.readouterr()
    assert "foot clearance at the apex" in out and "note" not in err
    leg.unlink()
    assert main(["metrics", str(run)]) == 0
    out, err = capsys.readouterr()
    assert f"legdsl: note: the file '{leg}' that {run}/run.json names is gone, so the rows " in err
    assert "foot clearance" not in out
