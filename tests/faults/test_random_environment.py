"""The world around a command, as outside testers perturb it (docs/runtime.md, The C backend and
What a run writes).

Each draw, from its seed, picks a command (a compile; a short run of the hopper or the kangaroo
on either backend, with or without --animate; metrics, a plot, a motion export or a player of a
finished run; check; show) and one to three perturbations of its world, combined: the locale,
the standard streams' encoding, the terminal, its width, HOME, TMPDIR, LEGDSL_CACHE, odd
directory names, a read-only or linked ``gen``, the .leg file reached oddly or with CRLF line
endings or a BOM, a missing, failing or slow C compiler, a PATH without one, the umask, a closed
standard input and redirected outputs. The command must exit 0 with the outputs of the same
command in a plain environment, or exit 2 with one line saying what to change (never a
traceback, never "internal error"); and the same command run again in the plain environment
must give the plain outputs (nothing half written, no stale cache entry).

An unwritable place is under /sys, which refuses root too (the tests may run as root, whom
permissions do not stop); exit 2 is right only where the draw may refuse (a C run without a
usable compiler or cache, a directory near PATH_MAX). Seeds 0-239 pass.

    LEGDSL_RANDOM_ENVIRONMENTS=80 LEGDSL_RANDOM_ENVIRONMENT_SEED=0 \
        pytest tests/faults/test_random_environment.py
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from seeded import told_with_seed

ROOT = Path(__file__).resolve().parents[2]
COUNT = int(os.environ.get("LEGDSL_RANDOM_ENVIRONMENTS", "1"))
FIRST = int(os.environ.get("LEGDSL_RANDOM_ENVIRONMENT_SEED", "0"))
RERUN = "LEGDSL_RANDOM_ENVIRONMENTS=1 LEGDSL_RANDOM_ENVIRONMENT_SEED={}"
UNWRITABLE = "/sys"  # a directory no one may write in, root included (sysfs)
FIN = "finished"  # a finished run's directory, linked into the scratch directory


def _commands(rng: np.random.Generator) -> tuple[str, list[str]]:
    """(kind, argv) of a command; paths are relative to a scratch directory."""
    kind = ["compile", "run", "run", "run", "metrics", "plot", "export", "animate", "check",
            "show"][int(rng.integers(10))]  # fmt: skip
    name = ("hopper", "kangaroo")[int(rng.integers(2))]
    leg = f"creatures/{name}.leg"
    if kind == "compile":
        return kind, ["compile", leg, "--out", "out"]
    if kind == "run":
        time = ("0.2", "0.3", "0.5")[int(rng.integers(3))]
        backend = ("c", "python")[int(rng.integers(2))]
        animate = ["--animate"] if rng.random() < 0.4 else []
        return kind, ["run", leg, "--time", time, "--backend", backend, "--generated", "gen",
                      "--out", "out", *animate]  # fmt: skip
    if kind == "metrics":
        return kind, ["metrics", FIN, "--generated", "gen"]
    if kind == "plot":
        return kind, ["plot", FIN, "-o", "out/figure.png"]
    if kind == "export":
        return kind, ["export-motion", FIN, "-o", "out/motion.glb", "--generated", "gen"]
    if kind == "animate":
        return kind, ["animate", FIN, "-o", "out/player.html", "--generated", "gen"]
    return kind, [kind, leg]


# ------------------------------------------------------------------------ the perturbations
@dataclass
class World:
    """How a command is started: its environment's changes (None unsets), its directory's name,
    its .leg path, its umask and standard streams, and what to undo before the plain rerun."""

    env: dict[str, str | None] = field(default_factory=dict)
    dirname: str = "plain"
    leg: Callable[[Path, str], str] | None = None  # (scratch, argv's leg) -> the path given
    prepare: list[Callable[[Path], None]] = field(default_factory=list)
    undo: list[Callable[[Path], None]] = field(default_factory=list)
    umask: int | None = None
    stdin: str = "inherit"  # or "closed", "devnull"
    outputs: str = "pipe"  # or "files"
    may_refuse: str = ""  # exit 2 with one line is right: "c" (for a C run), "any" command
    changes_text: bool = False  # standard output may be encoded or worded otherwise


def _gen_read_only(scratch: Path) -> None:
    for p in [scratch / "gen", *(scratch / "gen").rglob("*")]:
        p.chmod(0o555 if p.is_dir() else 0o444)


def _gen_writable(scratch: Path) -> None:
    for p in [scratch / "gen", *(scratch / "gen").rglob("*")]:
        p.chmod(0o755 if p.is_dir() else 0o644)


def _gen_elsewhere(scratch: Path) -> None:
    away = scratch.parent / f"{scratch.name}-gen-elsewhere"
    shutil.move(scratch / "gen", away)
    (scratch / "gen").symlink_to(away)


def _leg_copy(end: bytes, bom: bytes) -> Callable[[Path, str], str]:
    def copy(scratch: Path, leg: str) -> str:
        (scratch / "local").mkdir(exist_ok=True)
        text = (ROOT / leg).read_bytes().replace(b"\n", end)
        (scratch / "local" / Path(leg).name).write_bytes(bom + text)
        return f"local/{Path(leg).name}"

    return copy


def _leg_linked(scratch: Path, leg: str) -> str:
    (scratch / "linked.leg").symlink_to(ROOT / leg)
    return "linked.leg"


def _leg_dotdot(scratch: Path, leg: str) -> str:
    (scratch / "sub").mkdir(exist_ok=True)
    return f"sub/../{leg}"


def _sleepy_compiler(scratch: Path) -> None:
    tools = scratch.parent / f"{scratch.name}-tools"
    tools.mkdir(exist_ok=True)
    wrapper = tools / "slowcc"
    wrapper.write_text(f'#!/bin/sh\nsleep 0.3\nexec {shutil.which("cc")} "$@"\n')
    wrapper.chmod(0o755)


def _cache_file(scratch: Path) -> None:
    (scratch.parent / f"{scratch.name}-cachefile").write_text("not a directory\n")


def _tmp_file(scratch: Path) -> None:
    (scratch.parent / f"{scratch.name}-tmpfile").write_text("not a directory\n")


def _near_path_max(base: Path) -> str:
    """Directory names under ``base`` that bring the path near PATH_MAX (4096)."""
    parts, length = [], len(str(base))
    while length < 3900:
        parts.append("d" * min(200, 3900 - length))
        length += len(parts[-1]) + 1
    return "/".join(parts)


def _perturbations() -> list[tuple[str, Callable[[World], None]]]:
    """(name, how it changes a World)."""

    def env(**values: str | None) -> Callable[[World], None]:
        return lambda w: w.env.update(values)

    def text(**values: str | None) -> Callable[[World], None]:
        def apply(w: World) -> None:
            w.env.update(values)
            w.changes_text = True

        return apply

    def refusing(change: Callable[[World], None], where: str = "c") -> Callable[[World], None]:
        def apply(w: World) -> None:
            change(w)
            w.may_refuse = "any" if "any" in (where, w.may_refuse) else where

        return apply

    def attr(**values: object) -> Callable[[World], None]:
        def apply(w: World) -> None:
            for k, v in values.items():
                setattr(w, k, v)

        return apply

    def prepared(step: Callable[[Path], None], undo: Callable[[Path], None] | None = None,
                 **values: object) -> Callable[[World], None]:  # fmt: skip
        def apply(w: World) -> None:
            w.prepare.append(step)
            if undo:
                w.undo.append(undo)
            w.env.update(values.get("env", {}))  # type: ignore[call-overload]

        return apply

    def sibling(suffix: str) -> str:
        return "{sibling}" + suffix  # filled in with the scratch directory's path

    no_cc_path = str(Path(sys.executable).parent)  # python, but no cc, gcc or clang
    return [
        ("LANG=LC_ALL=C", text(LANG="C", LC_ALL="C")),
        ("LC_ALL=POSIX", text(LC_ALL="POSIX")),
        ("LC_ALL=en_US.ISO-8859-1", text(LANG="en_US.ISO-8859-1", LC_ALL="en_US.ISO-8859-1")),
        ("PYTHONIOENCODING=ascii", text(PYTHONIOENCODING="ascii")),
        ("PYTHONIOENCODING=latin-1", text(PYTHONIOENCODING="latin-1")),
        ("TERM=dumb", env(TERM="dumb")),
        ("TERM=none", env(TERM="none")),
        ("TERM unset", env(TERM=None)),
        ("COLUMNS=1", text(COLUMNS="1")),
        ("COLUMNS=0", text(COLUMNS="0")),
        ("COLUMNS=100000", text(COLUMNS="100000")),
        ("HOME unset", env(HOME=None)),
        ("HOME unwritable, no cache set",
         refusing(env(HOME=UNWRITABLE, LEGDSL_CACHE=None, XDG_CACHE_HOME=None))),
        ("TMPDIR missing", env(TMPDIR=sibling("-no-such-tmp"))),
        ("TMPDIR unwritable", env(TMPDIR=UNWRITABLE)),
        ("TMPDIR a file", prepared(_tmp_file, env={"TMPDIR": sibling("-tmpfile")})),
        ("LEGDSL_CACHE a file",
         refusing(prepared(_cache_file, env={"LEGDSL_CACHE": sibling("-cachefile")}))),
        ("LEGDSL_CACHE unwritable", refusing(env(LEGDSL_CACHE=UNWRITABLE + "/legdsl"))),
        ("LEGDSL_CACHE's parent missing", env(LEGDSL_CACHE=sibling("-no/such/parent/cache"))),
        ("LEGDSL_CACHE with spaces and accents", env(LEGDSL_CACHE=sibling("-c a'chê 日本"))),
        ("LEGDSL_CACHE very long",
         refusing(env(LEGDSL_CACHE=sibling("-" + "/".join(["c" * 200] * 15))))),
        ("directory with spaces", attr(dirname="with spaces")),
        ("directory with quotes", attr(dirname="it's \"quoted\"")),
        ("directory non-ASCII", attr(dirname="é 日本 ü")),
        ("directory with a leading dash", attr(dirname="-dash")),
        ("directory near PATH_MAX", refusing(attr(dirname="{near_path_max}"), "any")),
        ("gen read-only", prepared(_gen_read_only, _gen_writable)),
        ("gen a link elsewhere", prepared(_gen_elsewhere)),
        (".leg through a link", attr(leg=_leg_linked)),
        (".leg by a path with ..", attr(leg=_leg_dotdot)),
        (".leg with CRLF", attr(leg=_leg_copy(b"\r\n", b""))),
        (".leg with a BOM", attr(leg=_leg_copy(b"\n", b"\xef\xbb\xbf"))),
        ("LEGDSL_CC missing", refusing(env(LEGDSL_CC="no-such-cc"))),
        ("LEGDSL_CC=false", refusing(env(LEGDSL_CC="false"))),
        ("LEGDSL_CC sleeps", prepared(_sleepy_compiler, env={"LEGDSL_CC": sibling("-tools/slowcc")})),
        ("CC missing", env(CC="no-such-cc")),
        ("PATH without a C compiler", refusing(env(PATH=no_cc_path))),
        ("umask 077", attr(umask=0o077)),
        ("umask 0777", attr(umask=0o777)),
        ("stdin closed", attr(stdin="closed")),
        ("stdin /dev/null", attr(stdin="devnull")),
        ("outputs to files", attr(outputs="files")),
    ]  # fmt: skip


@dataclass
class Draw:
    seed: int
    kind: str
    argv: list[str]
    names: list[str]
    empty_gen: bool = False

    def __str__(self) -> str:
        gen = ", gen empty" if self.empty_gen and "gen" in self.argv else ""
        return f"seed {self.seed}: legdsl {' '.join(self.argv)}{gen}; {' + '.join(self.names)}"


def draw(seed: int) -> Draw:
    rng = np.random.default_rng(seed)
    kind, argv = _commands(rng)
    table = _perturbations()
    picked = rng.choice(len(table), size=int(rng.integers(1, 4)), replace=False)
    names = [table[int(i)][0] for i in sorted(picked)]
    # drawn apart, so that the draws above stay those of their seeds: an empty ``gen`` (the
    # command compiles its creature in the perturbed world), unless it is to be read-only
    empty = "gen read-only" not in names and bool(np.random.default_rng([seed, 1]).random() < 0.3)
    return Draw(seed, kind, argv, names, empty)


def world_of(d: Draw) -> World:
    w = World()
    table = dict(_perturbations())
    for name in d.names:
        table[name](w)
    return w


# ------------------------------------------------------------------------ running commands
def _scratch(directory: Path, warm_cache: Path | None) -> Path:
    """``creatures`` linked, ``gen`` holding the shipped modules (up to date) and a C library
    cache of its own (a copy of a warm one)."""
    directory.mkdir(parents=True)
    (directory / "creatures").symlink_to(ROOT / "creatures")
    shutil.copytree(ROOT / "generated" / "hopper", directory / "gen" / "hopper")
    shutil.copytree(ROOT / "generated" / "kangaroo", directory / "gen" / "kangaroo")
    if warm_cache is not None and warm_cache.is_dir():
        shutil.copytree(warm_cache, directory / "cache")
    return directory


def _plain_env(scratch: Path) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), LEGDSL_CACHE=str(scratch / "cache"))
    for name in ("LEGDSL_KILL_AT", "LEGDSL_CC", "LEGDSL_BACKEND", "PYTHONIOENCODING"):
        env.pop(name, None)
    return env


@dataclass
class Done:
    code: int
    out: str
    err: str


def _legdsl(argv: list[str], scratch: Path, env: dict[str, str], w: World | None = None) -> Done:
    w = w or World()

    def before() -> None:
        os.nice(10)
        if w.umask is not None:
            os.umask(w.umask)
        if w.stdin == "closed":
            os.close(0)

    stdin = subprocess.DEVNULL if w.stdin in ("closed", "devnull") else None
    command = [sys.executable, "-m", "legdsl", *argv]
    if w.outputs == "files":
        with open(scratch.parent / f"{scratch.name}.out", "w+b") as out, \
                open(scratch.parent / f"{scratch.name}.err", "w+b") as err:  # fmt: skip
            proc = subprocess.run(command, cwd=scratch, env=env, stdin=stdin, stdout=out,
                                  stderr=err, timeout=300, preexec_fn=before)  # fmt: skip
            out.seek(0)
            err.seek(0)
            return Done(proc.returncode, out.read().decode(errors="replace"),
                        err.read().decode(errors="replace"))  # fmt: skip
    proc = subprocess.run(command, cwd=scratch, env=env, stdin=stdin, capture_output=True,
                          timeout=300, preexec_fn=before)  # fmt: skip
    return Done(proc.returncode, proc.stdout.decode(errors="replace"),
                proc.stderr.decode(errors="replace"))  # fmt: skip


_references: dict[tuple[str, ...], tuple[Path, Done]] = {}


def _prepare(argv: list[str], scratch: Path, base: Path) -> None:
    if FIN in argv:
        (scratch / FIN).symlink_to(_finished_run(base) / "out")
    (scratch / "out").mkdir(exist_ok=True)


def _finished_run(base: Path) -> Path:
    key = ("finished",)
    if key not in _references:
        scratch = _scratch(base / "finished-run", None)
        argv = ["run", "creatures/hopper.leg", "--time", "0.5", "--generated", "gen",
                "--out", "out"]  # fmt: skip
        done = _legdsl(argv, scratch, _plain_env(scratch))
        assert done.code == 0, done.err
        _references[key] = (scratch, done)
    return _references[key][0]


def _reference(argv: list[str], base: Path) -> tuple[Path, Done]:
    key = tuple(argv)
    if key not in _references:
        scratch = _scratch(base / f"reference-{len(_references)}", base / "finished-run" / "cache")
        _prepare(argv, scratch, base)
        done = _legdsl(argv, scratch, _plain_env(scratch))
        assert done.code == 0, f"legdsl {' '.join(argv)}, plain: exit {done.code}\n{done.err}"
        _references[key] = (scratch, done)
    return _references[key]


# ------------------------------------------------------------------------ what each gives
def _tree(directory: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(directory)): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


def _same_outputs(kind: str, scratch: Path, reference: Path, argv: list[str]) -> None:
    out, ref = scratch / "out", reference / "out"
    assert not [p for p in out.rglob(".*")], f"hidden leftovers {list(out.rglob('.*'))}"
    if kind == "run":
        from legdsl.sim.trajectory import Trajectory

        again, plain = Trajectory.load(out), Trajectory.load(ref)
        for name in ("t", "q", "v", "force", "state"):
            assert np.array_equal(getattr(again, name), getattr(plain, name)), name
        for name in ("trajectory.npz", "trajectory.csv"):
            assert (out / name).read_bytes() == (ref / name).read_bytes(), name
        if "--animate" in argv:
            assert (out / "animation.html").stat().st_size > 0
    elif kind in ("compile", "plot", "export", "animate"):
        mine, theirs = _tree(out), _tree(ref)
        assert sorted(mine) == sorted(theirs), (sorted(mine), sorted(theirs))
        if kind != "compile" or argv[1].startswith("creatures/"):
            for name in mine:
                assert mine[name] == theirs[name], f"{name} differs"


def _same_text(
    done: Done, plain: Done, scratch: Path, reference: Path, leg: tuple[str, str]
) -> None:
    """The same standard output, but for the directory's and the .leg file's names."""
    mine = done.out.replace(str(scratch), "<here>").replace(leg[1], leg[0])
    assert mine == plain.out.replace(str(reference), "<here>")


def _said_well(d: Draw, done: Done, may_refuse: bool) -> None:
    err = done.err
    assert "Traceback" not in err and "internal error" not in err, f"exit {done.code}\n{err}"
    assert "Exception ignored" not in err, err
    if done.code == 0:
        return
    assert done.code == 2 and may_refuse, f"exit {done.code}\n{err}"
    last = err.strip().splitlines()[-1] if err.strip() else ""
    assert last.startswith("legdsl: ") or "^" in last, f"no line saying what to change:\n{err}"


# ------------------------------------------------------------------------ the draws
def _fill(text: str, scratch: Path) -> str:
    return text.replace("{sibling}", str(scratch.parent / scratch.name))


@pytest.mark.parametrize("seed", range(FIRST, FIRST + COUNT))
def test_a_perturbed_world(seed: int, tmp_path_factory: pytest.TempPathFactory) -> None:
    d = draw(seed)
    w = world_of(d)
    base = tmp_path_factory.getbasetemp() / "random-environment"
    with told_with_seed(str(d), RERUN.format(seed), lambda: ""):
        _check(d, w, base)


def _check(d: Draw, w: World, base: Path) -> None:
    reference, plain = _reference(d.argv, base)
    here = base / f"seed-{d.seed}"
    dirname = w.dirname.replace("{near_path_max}", _near_path_max(here))
    scratch = _scratch(here / dirname, base / "finished-run" / "cache")
    _prepare(d.argv, scratch, base)
    if d.empty_gen and FIN not in d.argv:
        for module in (scratch / "gen").iterdir():
            shutil.rmtree(module)
    argv = list(d.argv)
    leg = next((a for a in argv if a.endswith(".leg")), "")
    given = (leg, leg)
    if w.leg is not None and leg:
        given = (leg, w.leg(scratch, leg))
        argv[argv.index(leg)] = given[1]
    for step in w.prepare:
        step(scratch)
    env = _plain_env(scratch)
    for name, value in w.env.items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = _fill(value, scratch)
    done = _legdsl(argv, scratch, env, w)
    c_run = d.kind == "run" and "c" in argv
    _said_well(d, done, w.may_refuse == "any" or (w.may_refuse == "c" and c_run))
    if done.code == 0:
        _same_outputs(d.kind, scratch, reference, argv)
        if d.kind in ("check", "show", "metrics") and not w.changes_text:
            _same_text(done, plain, scratch, reference, given)
    if "gen a link elsewhere" in d.names:
        assert (scratch / "gen").is_symlink(), "gen, a link, was replaced by a directory"
    for step in w.undo:
        step(scratch)
    again = _legdsl(argv, scratch, _plain_env(scratch))
    assert again.code == 0, f"run again, plain: exit {again.code}\n{again.err}"
    _same_outputs(d.kind, scratch, reference, argv)
    if d.kind in ("check", "show", "metrics"):
        _same_text(again, plain, scratch, reference, given)
    if d.empty_gen and d.kind == "run":  # the modules compiled are the shipped ones, whole
        name = Path(leg).stem
        # written from the path given (its comments name it), which SHA256SUMS then digests
        made = {
            k: v.replace(given[1].encode(), leg.encode())
            for k, v in _tree(scratch / "gen" / name).items()
            if "__pycache__" not in k and (k != "SHA256SUMS" or given[0] == given[1])
        }
        shipped = _tree(ROOT / "generated" / name)
        assert made and all(made[k] == shipped.get(k) for k in made), "modules differ"
    shutil.rmtree(here)


def test_a_c_library_builds_with_tmpdir_unwritable(tmp_path: Path) -> None:
    """Seed 14: ``TMPDIR=/sys legdsl run ... --backend c``: "cc cannot build a C library here
    (Cannot create temporary file in /sys/...); install a C compiler with its headers", exit 2
    (``--backend auto`` fell back to Python). The compiler's temporary files now go in the
    build's directory in the cache: the run is the plain one."""
    scratch = _scratch(tmp_path / "s", None)
    argv = ["run", "creatures/hopper.leg", "--time", "0.2", "--backend", "c", "--generated",
            "gen", "--out", "out"]  # fmt: skip
    done = _legdsl(argv, scratch, _plain_env(scratch) | {"TMPDIR": UNWRITABLE})
    assert done.code == 0 and "Traceback" not in done.err, done.err
    cache = scratch / "cache"
    assert "built" in done.err and sorted(p.name for p in cache.iterdir()) == sorted(
        [*(p.name for p in cache.glob("hopper-*.so")), "objects", "grammar", "compilers"]
    )  # the library, its units' objects, the parser's tables and the compiler's answers, and
    # no temporary file left
    assert all(p.suffix == ".json" for p in (cache / "compilers").iterdir())
    assert all(p.suffix == ".o" for p in (cache / "objects").iterdir())
    assert all(p.suffix == ".lark-tables" for p in (cache / "grammar").iterdir())


def test_a_compile_into_a_linked_module_directory_keeps_the_link(tmp_path: Path) -> None:
    """``gen/hopper`` a link to modules kept elsewhere (shared with another checkout):
    ``legdsl compile hopper.leg --out gen`` replaced the link by a directory of its own, and
    the modules it named stayed old. Now they are replaced, and the link stays."""
    scratch = _scratch(tmp_path / "s", None)
    kept = tmp_path / "kept" / "hopper"
    shutil.move(scratch / "gen" / "hopper", kept)
    (kept / "dynamics.c").write_text("/* old */\n")
    (scratch / "gen" / "hopper").symlink_to(kept)
    done = _legdsl(["compile", "creatures/hopper.leg", "--out", "gen"], scratch,
                   _plain_env(scratch))  # fmt: skip
    assert done.code == 0, done.err
    assert (scratch / "gen" / "hopper").is_symlink()
    made = {k: v for k, v in _tree(kept).items() if "__pycache__" not in k}
    assert made == _tree(ROOT / "generated" / "hopper")
    assert sorted(p.name for p in kept.parent.iterdir()) == ["hopper"]  # nothing left beside
