"""Compile is atomic under SIGKILL at every instant (issue 18, item 3).

``LEGDSL_KILL_AT=N`` makes a writer kill itself at its N-th instant (``legdsl.files.instant``):
after each temporary file is written, after each is renamed into the new directory, and at
the three steps of the swap. Whatever the instant, ``generated/NAME/`` is afterwards the old
complete module set or the new one, once the next writer or reader has recovered it, and no
leftover stays behind.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from legdsl.files import is_leftover, recover_dir, temp_sibling, write_atomic
from legdsl.pipeline.generated import write_module_dir

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"
FILES = [f"m{i}.py" for i in range(6)]  # 1 + 2 * 6 + 3 = 16 instants
INSTANTS = 1 + 2 * len(FILES) + 3

WRITER = """
import sys
from pathlib import Path
from legdsl.pipeline.generated import write_module_dir
names = sys.argv[2:]
write_module_dir(Path(sys.argv[1]), "creature", [(n, "NEW " + n) for n in names])
"""


def _env(kill_at: int | None) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(SRC))
    env.pop("LEGDSL_KILL_AT", None)
    if kill_at is not None:
        env["LEGDSL_KILL_AT"] = str(kill_at)
    return env


def _contents(d: Path) -> dict[str, str]:
    return {p.name: p.read_text() for p in sorted(d.iterdir())}


@pytest.mark.parametrize("kill_at", range(1, INSTANTS + 1))
def test_a_killed_write_leaves_the_old_or_the_new_set(tmp_path: Path, kill_at: int) -> None:
    root = tmp_path / "generated"
    old = {n: "OLD " + n for n in FILES}
    new = {n: "NEW " + n for n in FILES}
    write_module_dir(root, "creature", list(old.items()))
    done = subprocess.run(
        [sys.executable, "-c", WRITER, str(root), *FILES], env=_env(kill_at), capture_output=True
    )
    assert done.returncode == -signal.SIGKILL, done.stderr.decode()
    final = root / "creature"
    names = sorted(p.name for p in root.iterdir())
    # Killed between the two renames of the swap, only the retired copy is there: the next
    # reader or writer puts it back.
    assert final.is_dir() or any(n.startswith(".creature.old-") for n in names), names
    recover_dir(final)
    assert _contents(final) in (old, new)
    assert sorted(p.name for p in root.iterdir()) == ["creature"]  # no leftovers
    write_module_dir(root, "creature", list(new.items()))
    assert _contents(final) == new


def test_the_writer_runs_through_without_a_kill(tmp_path: Path) -> None:
    root = tmp_path / "generated"
    done = subprocess.run(
        [sys.executable, "-c", WRITER, str(root), *FILES], env=_env(None), capture_output=True
    )
    assert done.returncode == 0, done.stderr.decode()
    assert _contents(root / "creature") == {n: "NEW " + n for n in FILES}
    assert sorted(p.name for p in root.iterdir()) == ["creature"]


def test_a_real_compile_killed_inside_the_swap_is_recovered_by_the_next_run(
    tmp_path: Path,
) -> None:
    """``legdsl compile`` killed after retiring generated/hopper/ and before the new one is
    in place; the next ``legdsl run`` puts the old (here: equal, so fresh) set back."""
    gen = tmp_path / "generated"
    shutil.copytree(ROOT / "generated" / "hopper", gen / "hopper")
    leg = ROOT / "creatures" / "hopper.leg"
    n_files = len(list((gen / "hopper").iterdir()))
    retire = 1 + 2 * n_files + 1  # the instant right after the old directory is retired
    cmd = [sys.executable, "-m", "legdsl"]
    done = subprocess.run(
        [*cmd, "compile", str(leg), "--out", str(gen)], env=_env(retire), capture_output=True
    )
    assert done.returncode == -signal.SIGKILL
    assert not (gen / "hopper").exists()
    assert any(n.name.startswith(".hopper.old-") for n in gen.iterdir())
    done = subprocess.run(
        [*cmd, "run", str(leg), "--time", "0.05", "--generated", str(gen)]
        + ["--out", str(tmp_path / "run")],
        env=_env(None),
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert "compiling" not in done.stderr  # the recovered set was complete and fresh
    assert sorted(p.name for p in gen.iterdir()) == ["hopper"]


def test_leftovers_of_a_live_writer_are_left_alone(tmp_path: Path) -> None:
    final = tmp_path / "creature"
    final.mkdir()
    mine = temp_sibling(final, "new")  # this process is alive
    mine.mkdir()
    recover_dir(final)
    assert mine.exists()


def test_temporary_names_never_repeat() -> None:
    names = {temp_sibling(Path("x/run.json")).name for _ in range(1000)}
    assert len(names) == 1000
    assert all(is_leftover(Path(n), "run.json") for n in names)


def test_write_atomic_refuses_other_types_and_keeps_the_old_file(tmp_path: Path) -> None:
    target = tmp_path / "a.json"
    write_atomic(target, "old")
    with pytest.raises(TypeError):
        write_atomic(target, 42)  # type: ignore[arg-type]
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.json"]


RACER = """
import sys
from pathlib import Path
from legdsl.pipeline.generated import write_module_dir
tag = sys.argv[2]
for _ in range(10):
    write_module_dir(Path(sys.argv[1]), "creature", [(n, tag + " " + n) for n in sys.argv[3:]])
"""


def test_parallel_writers_of_one_module_never_collide(tmp_path: Path) -> None:
    """Two compiles of one creature at the same moment: both succeed, the result is one
    writer's complete set, and nothing is left behind."""
    root = tmp_path / "generated"
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", RACER, str(root), f"W{k}", *FILES],
            env=_env(None),
            stderr=subprocess.PIPE,
        )
        for k in range(3)
    ]
    for proc in procs:
        _, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err.decode()
    contents = _contents(root / "creature")
    tags = {text.split()[0] for text in contents.values()}
    assert len(tags) == 1 and sorted(contents) == sorted(FILES)
    assert sorted(p.name for p in root.iterdir()) == ["creature"]
