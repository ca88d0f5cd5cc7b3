"""``use``: files relative to the one that says it, nested uses resolved once each."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.ir import controller as ir
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]


def called(state: ir.State) -> list[str]:
    out: list[str] = []

    def walk(body: tuple[ir.Stmt, ...]) -> None:
        for s in body:
            if isinstance(s, ir.Do):
                out.append(s.action)
                walk(s.body)

    walk(state.body)
    return out


def test_nested_uses_resolve_relative_to_each_file_and_once(tmp_path: Path) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "gaits.leg").write_text(
        'use "shared.leg"\nuse raibert\naction thrust(leg) { lengthen(leg, 2 cm) }\n'
    )
    (tmp_path / "lib" / "shared.leg").write_text(
        "action lengthen(leg, by) { leg.spring.rest = by }\n"
    )
    main = tmp_path / "main.leg"
    main.write_text(
        'use "lib/gaits.leg"\nuse "lib/shared.leg"\n'  # the second use of shared.leg adds nothing
        + CREATURE
        + "controller hop {\n  table {\n"
        "    state FLIGHT on liftoff(main): thrust(main); relax(main, 0 m)\n"
        "  }\n}\n"
    )
    (flight,) = check_model(main).controller("hop").states
    assert called(flight) == ["thrust", "lengthen", "relax"]


def _calls_lengthen_by_itself(main: Path) -> None:
    """The controller hop of ``main`` calls the ``lengthen`` that sets ``by``, not ``2 * by``."""
    (flight,) = check_model(main).controller("hop").states
    (do,) = flight.body
    assert isinstance(do, ir.Do)
    (assign,) = do.body
    assert isinstance(assign, ir.Assign) and isinstance(assign.value, ir.Num)  # not 2 * by


def test_a_files_own_action_overrides_a_used_one(tmp_path: Path) -> None:
    (tmp_path / "lib.leg").write_text("action lengthen(leg, by) { leg.spring.rest = 2 * by }\n")
    main = tmp_path / "main.leg"
    main.write_text(
        'use "lib.leg"\naction lengthen(leg, by) { leg.spring.rest = by }\n'
        + CREATURE
        + "controller hop {\n  table {\n"
        "    state FLIGHT on liftoff(main): lengthen(main, 1 cm)\n  }\n}\n"
    )
    _calls_lengthen_by_itself(main)


def test_a_file_used_directly_wins_over_one_used_through_another(tmp_path: Path) -> None:
    """near.leg is used by main.leg itself, far.leg only through middle.leg (read after
    near.leg, its action was taken): near's lengthen is the one called."""
    (tmp_path / "near.leg").write_text("action lengthen(leg, by) { leg.spring.rest = by }\n")
    (tmp_path / "middle.leg").write_text('use "far.leg"\n')
    (tmp_path / "far.leg").write_text("action lengthen(leg, by) { leg.spring.rest = 2 * by }\n")
    main = tmp_path / "main.leg"
    main.write_text(
        'use "near.leg"\nuse "middle.leg"\n' + CREATURE + "controller hop {\n  table {\n"
        "    state FLIGHT on liftoff(main): lengthen(main, 1 cm)\n  }\n}\n"
    )
    _calls_lengthen_by_itself(main)


def test_a_missing_file_deep_down_is_reported_at_the_users_use(tmp_path: Path) -> None:
    (tmp_path / "lib.leg").write_text('use "gone.leg"\n')
    main = tmp_path / "main.leg"
    main.write_text('use "lib.leg"\n' + CREATURE)
    with pytest.raises(LegError) as e:
        check_model(main)
    (d,) = e.value.diagnostics
    assert (Path(d.span.file).name, d.span.line) == ("main.leg", 1)
    assert "cannot find 'gone.leg' to use (asked for in lib.leg)" in d.message


def test_a_used_file_that_cannot_be_read_is_the_only_news(tmp_path: Path) -> None:
    """Its mistake, not also 'unknown action' at each call of what it would have defined."""
    (tmp_path / "lib.leg").write_text("action lengthen(leg, by) { leg.spring.rest = by\n")
    main = tmp_path / "main.leg"
    main.write_text(
        'use "lib.leg"\n' + CREATURE + "controller hop {\n  table {\n"
        "    state FLIGHT on liftoff(main): lengthen(main, 1 cm)\n  }\n}\n"
    )
    with pytest.raises(LegError) as e:
        check_model(main)
    (d,) = e.value.diagnostics
    assert (Path(d.span.file).name, d.span.line) == ("lib.leg", 1)
    assert "a '}' is missing" in d.message
    (tmp_path / "lib.leg").unlink()
    with pytest.raises(LegError) as e:
        check_model(main)
    (d,) = e.value.diagnostics
    assert d.message.startswith("cannot find 'lib.leg' to use")


@pytest.mark.parametrize(("target", "told"), [("/dev/zero", "not a file"), ("./lib", "a folder")])
def test_a_used_path_that_is_there_but_no_file_is_told_so(
    tmp_path: Path, target: str, told: str
) -> None:
    """Not 'cannot find': the path is there, but a device or a folder is no .leg file."""
    (tmp_path / "lib").mkdir()
    main = tmp_path / "main.leg"
    main.write_text(f'use "{target}"\n' + CREATURE)
    with pytest.raises(LegError) as e:
        check_model(main)
    (d,) = e.value.diagnostics
    assert (Path(d.span.file).name, d.span.line) == ("main.leg", 1)
    assert d.message.startswith(f"cannot use '{target}': ")
    assert f" is {told}" in d.message
    assert d.message.endswith("'use' takes a .leg file")


def test_two_files_the_same_distance_away_defining_one_action_is_an_error_at_the_call(
    tmp_path: Path,
) -> None:
    (tmp_path / "a.leg").write_text("action lengthen(leg, by) { leg.spring.rest = by }\n")
    (tmp_path / "b.leg").write_text("action lengthen(leg, by) { leg.spring.rest = 2 * by }\n")
    main = tmp_path / "main.leg"
    body = (
        CREATURE + "controller hop {\n  table {\n"
        "    state FLIGHT on liftoff(main): lengthen(main, 1 cm)\n  }\n}\n"
    )
    main.write_text('use "a.leg"\nuse "b.leg"\n' + body)
    with pytest.raises(LegError) as caught:
        check_model(main)
    line = 2 + body.split("\n").index("    state FLIGHT on liftoff(main): lengthen(main, 1 cm)") + 1
    assert (
        f"main.leg:{line}:36: error: action 'lengthen' is defined by both a.leg and b.leg, each "
        "1 'use' away, so neither wins; rename it in one of them, or leave out the 'use' of "
        "the one you do not mean"
    ) in caught.value.render()
    # one of its own, or one file nearer, wins; an action nobody calls is no error
    main.write_text('use "a.leg"\nuse "b.leg"\naction lengthen(leg, by) { leg.spring.rest = by }\n'
                    + body)  # fmt: skip
    _calls_lengthen_by_itself(main)
    (tmp_path / "middle.leg").write_text('use "b.leg"\n')
    main.write_text('use "a.leg"\nuse "middle.leg"\n' + body)
    _calls_lengthen_by_itself(main)
    uncalled = body.replace("lengthen(main, 1 cm)", "relax(main, 0 m)")
    main.write_text('use "a.leg"\nuse "b.leg"\nuse raibert\n' + uncalled)
    (flight,) = check_model(main).controller("hop").states
    assert called(flight) == ["relax"]


def test_two_files_the_same_distance_away_sharing_one_part_is_an_error_at_the_include(
    tmp_path: Path,
) -> None:
    (tmp_path / "a.leg").write_text("shared gains { param kp = 1 N*m/rad }\n")
    (tmp_path / "b.leg").write_text("shared gains { param kp = 2 N*m/rad }\n")
    main = tmp_path / "main.leg"
    body = (
        CREATURE + "controller hop {\n  include gains\n  table {\n"
        "    state FLIGHT on liftoff(main): hip_servo.kp = kp\n  }\n}\n"
    )
    main.write_text('use "a.leg"\nuse "b.leg"\n' + body)
    with pytest.raises(LegError) as caught:
        check_model(main)
    line = 2 + body.split("\n").index("  include gains") + 1
    assert (
        f"main.leg:{line}:11: error: shared part 'gains' is defined by both a.leg and b.leg, "
        "each 1 'use' away, so neither wins; rename it in one of them, or leave out the 'use' "
        "of the one you do not mean"
    ) in caught.value.render()
    (tmp_path / "middle.leg").write_text('use "b.leg"\n')
    main.write_text('use "a.leg"\nuse "middle.leg"\n' + body)  # a.leg is nearer: its kp
    assert [p.value for p in check_model(main).controller("hop").params] == [1.0]


def test_names_a_missing_files_shared_part_would_declare_are_not_reported_unknown(
    tmp_path: Path,
) -> None:
    """One error at the 'use', not one per name the part declares, per controller that
    includes it or extends one that does, per scene that sets it; a name misspelt in a
    controller that includes nothing from it is still reported."""
    main = tmp_path / "main.leg"
    main.write_text(
        'use "gone.leg"\n' + CREATURE + "shared mine {\n  include gains\n}\n"
        "controller hop {\n  include mine\n  table {\n"
        "    state FLIGHT on liftoff(main): hip_servo.kp = kp\n"
        "    state STANCE on touchdown(main): hip_servo.kv = kv * kp\n  }\n}\n"
        "controller skip extends hop {\n  param k = 1\n  signal s = kp * k\n}\n"
        "controller stand {\n  table {\n"
        "    state STAND on touchdown(main): hip_servo.kp = kpp\n  }\n}\n"
        "scene demo {\n  controller hop\n  set kp = 3 N*m/rad\n}\n"
    )
    with pytest.raises(LegError) as e:
        check_model(main)
    found = [(d.span.line, d.message.split(";")[0].split(":")[0]) for d in e.value.diagnostics]
    stand = main.read_text().split("\n").index("controller stand {") + 3
    assert found == [
        (1, "cannot find 'gone.leg' to use"),
        (stand, "unknown name 'kpp'"),
    ]


def test_a_used_path_through_dot_dot_is_told_as_the_file_it_names(tmp_path: Path) -> None:
    """``lib/../parts.leg`` is ``parts.leg`` in messages; where ``lib`` is a symlink, '..'
    is the link target's parent, so the path is told as written (it names another file)."""
    (tmp_path / "lib").mkdir()
    (tmp_path / "parts.leg").write_text("action lengthen(leg, by) { leg.spring.rest = by\n")
    (tmp_path / "lib" / "near.leg").write_text('use "../parts.leg"\n')
    main = tmp_path / "main.leg"
    main.write_text('use "lib/near.leg"\n' + CREATURE)
    with pytest.raises(LegError) as e:
        check_model(main)
    (d,) = e.value.diagnostics
    assert Path(d.span.file) == tmp_path / "parts.leg"
    elsewhere = tmp_path / "far" / "away"
    elsewhere.mkdir(parents=True)
    (tmp_path / "far" / "parts.leg").write_text("action lengthen(leg, by) {\n")
    (elsewhere / "near.leg").write_text('use "../parts.leg"\n')
    (tmp_path / "lib" / "near.leg").unlink()
    (tmp_path / "lib").rmdir()
    (tmp_path / "lib").symlink_to(elsewhere)
    with pytest.raises(LegError) as e:
        check_model(main)
    (d,) = e.value.diagnostics
    assert Path(d.span.file) == tmp_path / "lib" / ".." / "parts.leg"
    assert d.span.line == 1


def test_a_used_path_not_found_says_where_it_was_looked_for(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Run from the project's folder, 'use "lib/actions.leg"' in sub/hop.leg was told that
    other files are named by a path in quotes, as it was: not where it was looked for."""
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "actions.leg").write_text(
        "action lengthen(leg, by) { leg.spring.rest = by }\n"
    )
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "hop.leg").write_text('use "lib/actions.leg"\n' + CREATURE)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(LegError) as e:
        check_model(Path("sub/hop.leg"))
    (d,) = e.value.diagnostics
    assert d.message == (
        "cannot find 'lib/actions.leg' to use: looked for sub/lib/actions.leg: a path in 'use' "
        "is relative to the file that says it (sub/hop.leg), not to the working directory; for "
        "the lib/actions.leg of the working directory write 'use \"../lib/actions.leg\"'"
    )
