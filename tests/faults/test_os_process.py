"""The process and its surroundings: signals other than Ctrl-C and SIGTERM (a closed terminal,
the CPU-time limit), resource limits (``ulimit -n``, ``-f``, ``-v``), and odd standard
streams. Each is really done to a ``legdsl`` in a subprocess."""

from __future__ import annotations

import json
import os
import resource
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.faults.processes import wait_until_simulating

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))


def _long_run(generated: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "legdsl", "run", HOPPER, "--controller", "hop",
            "--time", "1e9", "--record-rate", "10Hz", "--backend", "python",
            "--generated", str(generated), "--out", str(out)]  # fmt: skip


def _limited(kind: int, soft: int) -> Callable[[], None]:
    def limit() -> None:
        hard = resource.getrlimit(kind)[1]
        resource.setrlimit(kind, (soft, hard))

    return limit


def _ended_by(out: Path, cause: str) -> None:
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "interrupted" and run["cause"] == cause, run
    assert (out / "trajectory.npz").is_file() and (out / "trajectory.csv").is_file()


@pytest.mark.parametrize("sig", [signal.SIGHUP, signal.SIGQUIT])
def test_a_closed_terminal_ends_a_run_with_what_it_recorded(
    sig: signal.Signals, generated: Path, tmp_path: Path
) -> None:
    """SIGHUP (the terminal closed) or SIGQUIT (Ctrl-\\) killed the run on the spot: no run
    directory at all."""
    out = tmp_path / "run"
    proc = subprocess.Popen(_long_run(generated, out), env=ENV, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)  # fmt: skip
    wait_until_simulating(proc)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + sig, err
    assert "Traceback" not in err and sig.name in err, err
    _ended_by(out, sig.name)


def test_a_run_ignoring_sighup_under_nohup_keeps_ignoring_it(
    generated: Path, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    argv = _long_run(generated, out)
    argv[argv.index("1e9")] = "8"
    proc = subprocess.Popen(argv, env=ENV, text=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE,
                            preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))  # fmt: skip
    time.sleep(1.5)
    proc.send_signal(signal.SIGHUP)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, err
    assert json.loads((out / "run.json").read_text())["status"] == "ok"


def test_the_cpu_time_limit_ends_a_run_with_what_it_recorded(
    generated: Path, tmp_path: Path
) -> None:
    """``ulimit -S -t 2``: SIGXCPU killed the run ("CPU time limit exceeded"), nothing written."""
    out = tmp_path / "run"
    proc = subprocess.run(_long_run(generated, out), env=ENV, capture_output=True, text=True,
                          timeout=60, preexec_fn=_limited(resource.RLIMIT_CPU, 2))  # fmt: skip
    assert proc.returncode == 128 + signal.SIGXCPU, proc.stderr
    assert "Traceback" not in proc.stderr and "SIGXCPU" in proc.stderr
    _ended_by(out, "SIGXCPU")


def _legdsl(*args: str, cwd: Path, env: dict[str, str] | None = None,
            **kw: object) -> subprocess.CompletedProcess[str]:  # fmt: skip
    if "stdout" not in kw and "stderr" not in kw:
        kw["capture_output"] = True
    return subprocess.run([sys.executable, "-m", "legdsl", *args], cwd=cwd, env=env or ENV,
                          text=True, timeout=60, **kw)  # type: ignore[call-overload]  # fmt: skip


def test_an_ascii_terminal_gets_escapes_not_an_internal_error(
    generated: Path, tmp_path: Path
) -> None:
    """PYTHONIOENCODING=ascii and an output folder named 'é日本': exit 70 after the run was
    written (UnicodeEncodeError printing its name)."""
    (tmp_path / "é日本").mkdir()
    env = dict(ENV, PYTHONIOENCODING="ascii")
    proc = _legdsl("run", HOPPER, "--time", "0.1", "--generated", str(generated),
                   "--out", "é日本/r", cwd=tmp_path, env=env)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "\\xe9\\u65e5\\u672c/r/" in proc.stdout
    proc = _legdsl("plot", "é日本/r", "-o", "é日本/p.png", cwd=tmp_path, env=env)
    assert proc.returncode == 0 and (tmp_path / "é日本" / "p.png").is_file(), proc.stderr


def test_with_standard_error_closed_messages_stay_off_standard_output(tmp_path: Path) -> None:
    """``2>&-``: print(file=sys.stderr) printed the error into standard output."""
    proc = _legdsl("check", "missing.leg", cwd=tmp_path, stdout=subprocess.PIPE,
                   preexec_fn=lambda: os.close(2))  # fmt: skip
    assert proc.returncode == 2 and proc.stdout == "", proc.stdout


def test_a_full_standard_output_is_named_as_such(tmp_path: Path) -> None:
    """``legdsl show hopper.leg > /dev/full``: "No space left on device", of no file named."""
    with open("/dev/full", "w") as full:
        proc = _legdsl("show", HOPPER, cwd=tmp_path, stdout=full, stderr=subprocess.PIPE)  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("legdsl: cannot write standard output: No space left")
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize("words", [("run", "--help"), ("--version",)])
def test_help_and_version_into_a_full_standard_output_fail(
    tmp_path: Path, words: tuple[str, ...]
) -> None:
    """``legdsl run --help > /dev/full`` exited 0: argparse swallows the write's error."""
    with open("/dev/full", "w") as full:
        proc = _legdsl(*words, cwd=tmp_path, stdout=full, stderr=subprocess.PIPE)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("legdsl: cannot write standard output: No space left")


def test_too_few_file_descriptors_say_which_limit(tmp_path: Path) -> None:
    """``ulimit -n 10`` on a sweep's worker processes: "Too many open files; check the path
    and its permissions"."""
    proc = _legdsl("sweep", HOPPER, "--controller", "hop", "--grid", "speed=0.5:1:2",
                   "--time", "0.2", "--from", "0.1", "--jobs", "2", "--out", str(tmp_path / "s"),
                   cwd=tmp_path, preexec_fn=_limited(resource.RLIMIT_NOFILE, 10))  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.splitlines()[-1] == (
        "legdsl: Too many open files: raise the limit of open files (ulimit -n) and run again"
    )


def test_a_compile_with_few_file_descriptors_lowers_its_controllers_here(tmp_path: Path) -> None:
    """``ulimit -n 6``: no pipe for a process that would lower the controllers, which are then
    lowered in the compiler's own process, to the same files. They were lowered with sympy's
    evaluation off (the context that rebuilds a process's answer), and came out otherwise:
    ``1/1.0**1.0`` unsimplified, and for the hopper past Python's recursion limit."""
    proc = _legdsl("compile", HOPPER, "--out", str(tmp_path / "g"), cwd=tmp_path,
                   preexec_fn=_limited(resource.RLIMIT_NOFILE, 6))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    plain = _legdsl("compile", HOPPER, "--out", str(tmp_path / "plain"), cwd=tmp_path)
    assert plain.returncode == 0, plain.stderr
    for name in ("control_hop.py", "control_hop.c"):
        here, forked = (tmp_path / out / "hopper" / name for out in ("g", "plain"))
        assert here.read_text() == forked.read_text(), name


@pytest.mark.parametrize("files", [8, 10])
def test_too_few_file_descriptors_for_the_c_compiler_say_which_limit(
    generated: Path, tmp_path: Path, files: int
) -> None:
    """The C backend under ``ulimit -n 10``: "cannot run /usr/bin/cc (Too many open files)",
    as if the compiler were at fault; under ``ulimit -n 8``: "no C compiler found"."""
    env = dict(ENV, LEGDSL_CACHE=str(tmp_path / "cache"))
    proc = _legdsl("run", HOPPER, "--controller", "hop", "--time", "0.05", "--backend", "c",
                   "--generated", str(generated), "--out", str(tmp_path / "r"), cwd=tmp_path,
                   env=env, preexec_fn=_limited(resource.RLIMIT_NOFILE, files))  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert (
        "Too many open files" in proc.stderr
        and "raise the limit of open files (ulimit -n)" in proc.stderr
    )
    assert "no C compiler found" not in proc.stderr and "Traceback" not in proc.stderr


def test_the_file_size_limit_is_named(tmp_path: Path) -> None:
    """``ulimit -f 1``: a message of the file system only; no half-written export either."""
    proc = _legdsl("export", HOPPER, "--format", "mjcf", "-o", "x.xml", cwd=tmp_path,
                   preexec_fn=_limited(resource.RLIMIT_FSIZE, 1024))  # fmt: skip
    assert proc.returncode == 2 and "(ulimit -f)" in proc.stderr, proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_run_under_a_memory_limit_is_not_ended_by_openblas(
    generated: Path, tmp_path: Path
) -> None:
    """``ulimit -v 225280``: OpenBLAS's thread per core could not have its buffers and ended the
    process ("OpenBLAS error: Memory allocation still failed", exit 1) with nothing said by
    legdsl; on one thread the run goes through."""
    proc = _legdsl("run", HOPPER, "--controller", "hop", "--time", "0.2", "--generated",
                   str(generated), "--out", str(tmp_path / "r"), cwd=tmp_path,
                   env={k: v for k, v in ENV.items() if k != "OPENBLAS_NUM_THREADS"},
                   preexec_fn=_limited(resource.RLIMIT_AS, 220 * 2**20))  # fmt: skip
    assert "OpenBLAS" not in proc.stderr and proc.returncode in (0, 2), proc.stderr


@pytest.mark.parametrize(("given", "used"), [(None, "1"), ("2", "2")])
def test_openblas_runs_one_thread_unless_asked(given: str | None, used: str) -> None:
    script = (
        "import os, sys\nfrom legdsl.__main__ import main\nsys.argv = ['legdsl', '--version']\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\nprint(os.environ['OPENBLAS_NUM_THREADS'])\n"
    )
    env = {k: v for k, v in ENV.items() if k != "OPENBLAS_NUM_THREADS"}
    if given is not None:
        env["OPENBLAS_NUM_THREADS"] = given
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env)
    assert proc.stdout.splitlines()[-1] == used, proc.stderr


@pytest.mark.parametrize("limit_mb", [160, 170, 175, 180])
def test_too_little_memory_is_one_line(tmp_path: Path, limit_mb: int) -> None:
    """``ulimit -v 163840``: a MemoryError traceback of numpy's import; at some limits the
    import machinery itself failed ("SystemError: error return without exception set"). (Much
    less memory and numpy's own library aborts the process as it loads, out of reach of
    Python.)"""
    proc = _legdsl("show", HOPPER, cwd=tmp_path,
                   preexec_fn=_limited(resource.RLIMIT_AS, limit_mb * 2**20))  # fmt: skip
    assert "Traceback" not in proc.stderr and proc.returncode in (0, 2), proc.stderr
    if proc.returncode == 2:
        assert "out of memory" in proc.stderr and "ulimit -v" in proc.stderr
