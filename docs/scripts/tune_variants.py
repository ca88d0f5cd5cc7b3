"""How often ``legdsl tune`` brings a creature no one tuned to its speeds (docs/api.md,
"Tuning creatures no one tuned"):

    python docs/scripts/tune_variants.py creatures/hopper.leg --controller hop -n 14 \\
        --seed 1 --recipe heavy20 --out /tmp/variants --png docs/img/hopper-variants-tune-20s.png

draws N seeded random variants of a shipped planar creature by rewriting numbers of its
``.leg`` text only: each body's mass times 0.5 to 3 (its own draw) and its inertia with it,
times L^2 too; every length of the creature (link lengths, centres of mass, attachment and
contact points, prismatic limits, shapes, the initial height) and every length the
controller writes (its inputs and parameters in metres, or per metre: the hop height, the
stroke, the length where thrust ends) times one L of 0.7 to 1.4 (per metre: divided); the
stiffness of each leg's ``spring`` (and of the parameters that set it, ``SPRING_PARAMS``)
times 0.5 to 2. Parameters are changed where they are declared, by docs/scripts/detune.py's
writer. With ``--similar`` the same draws make dynamically similar creatures (docs/scaling.md,
g fixed, time as sqrt(L)): every body's mass times one M (the total mass's factor of the
per-body draws: a light tail on springs scaled with the whole animal made the explicit
integrator diverge), every quantity of kg^a m^b s^c in the actuators, the controller's
inputs and parameters times M^a L^b L^(c/2) (so a torque, a servo's
gain and its limit times M L, a time sqrt(L)); the leg spring's stiffness M L times the draw
of 0.5 to 2 taken to the power 1/3 (0.79 to 1.26: animals' springs scatter about the similar
one); the old draw (without ``--similar``) is unchanged. For each variant it runs the shipped gains 20 s at each speed (``legdsl run``, then
``legdsl metrics --from 3``), tunes them with ONE recipe (``RECIPE``, the same for every
variant, ``--recipe``: the heavy hopper's of docs/api.md, scored over 10 s as written there or
over 20 s; the detuned kangaroo's) and runs the tuned file 20 s at each speed the same way. A
variant succeeds when the tuned file lasts 20 s at every speed within 10% of each. It prints
a table and a progress line with the time left, writes OUT/variants.md (the markdown table),
OUT/variants.json and a plot (``--png``) of the mean speed error before and after per variant.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).parent))
from detune import write_times  # noqa: E402  # the parameter writer, shared

from legdsl.check.source import check_model  # noqa: E402
from legdsl.lang import ast  # noqa: E402
from legdsl.lang.parser import parse_file  # noqa: E402
from legdsl.lang.scaling import _NUMBER, _walk, format_number  # noqa: E402
from legdsl.lang.units import KINDS  # noqa: E402

LENGTH = KINDS["length"][0]
SPEEDS = (0.5, 1.0, 1.5)  # the hopper's; main() sets the recipe's
RUN_TIME = 20.0
FROM = 3.0
SUCCESS = 0.10  # the tuned speed within 10% of each command
HEAVY = [  # the heavy hopper's recipe (docs/api.md, "Tuning a new creature")
    "--param", "k_speed=0.02:0.2", "--param", "kp=50:600", "--param", "kv=5:60",
    "--param", "swing_kp=50:600", "--param", "stroke=0.01:0.08",
    "--speeds", ",".join(f"{s:g}" for s in SPEEDS), "--from", "3",
    "--generations", "12", "--popsize", "10", "--seed", "1", "--jobs", "1",
]  # fmt: skip
KANGAROO = [  # the detuned kangaroo's recipe (docs/api.md, "Tuning from detuned gains")
    "--param", "k_speed=0.01:0.12", "--param", "kp=30:300", "--param", "kv=1:30",
    "--speeds", "3,4,5", "--time", "20", "--from", "3",
    "--generations", "10", "--popsize", "8", "--seed", "1", "--jobs", "1",
]  # fmt: skip
# the kangaroo's with what a new kangaroo needs (docs/api.md): the ankle spring's stiffness
# (its stance time sets the neutral point), the thrust (stroke, k_height) and the foot
# placement's correction limit (max_correction, which held variant 3 at 1.995 m/s); the
# bounds wide enough for a --similar variant's gains (kp x M L up to 3.3)
KANGAROO_RICH = [
    "--param", "k_speed=0.01:0.12", "--param", "kp=30:800", "--param", "kv=1:80",
    "--param", "ankle_k=40:800", "--param", "stroke=0:0.26", "--param", "k_height=0.2:4",
    "--param", "max_correction=0.02:0.15",
    "--speeds", "3,4,5", "--time", "20", "--from", "3",
    "--generations", "10", "--popsize", "8", "--seed", "1", "--jobs", "1",
]  # fmt: skip
RECIPE = {  # one recipe for every variant, by --recipe
    "heavy": [*HEAVY, "--time", "10"],  # as written there: runs of 10 s
    "heavy20": [*HEAVY, "--time", "20"],  # the same, scored over the 20 s it is checked on
    "kangaroo": KANGAROO,
    "kangaroo_rich": KANGAROO_RICH,
}
# controller parameters that set the leg spring's stiffness (scaled with it): the kangaroo's
# hop sets its ankle spring's k to ankle_k while hopping
SPRING_PARAMS = {"kangaroo": ("ankle_k",), "kangaroo_rich": ("ankle_k",)}


def draw(rng: random.Random, bodies: dict[str, float], similar: bool = False) -> dict[str, Any]:
    """One variant's factors (``bodies``: each body's mass). The same random draws with and
    without ``similar``, so ``--similar`` varies the same creatures."""
    factors: dict[str, Any] = {
        "L": round(rng.uniform(0.7, 1.4), 3),
        "spring": round(rng.uniform(0.5, 2.0), 3),
        "mass": {b: round(rng.uniform(0.5, 3.0), 3) for b in bodies},
    }
    if similar:  # the spring scatters about the dynamically similar one (stiffness ~ M g L)
        M = sum(m * factors["mass"][b] for b, m in bodies.items()) / sum(bodies.values())
        factors["M"] = round(M, 3)
        factors["spring"] = round(M * factors["L"] * factors["spring"] ** (1 / 3), 3)
    return factors


def scale_of(factors: dict[str, Any]) -> Any:
    """The factor of a quantity of dimension ``dim``: a length's L^n only (the old draw), or,
    for a ``--similar`` draw, M^a L^b L^(c/2) of kg^a m^b s^c (g fixed)."""
    L = factors["L"]
    if "M" not in factors:
        return lambda dim: length_factor(dim, L)
    M = factors["M"]
    return lambda dim: M ** dim[0] * L ** dim[1] * L ** (dim[2] / 2)


def variant_text(source: Path, factors: dict[str, Any]) -> str:
    """The creature's text with its numbers rewritten by ``factors`` (``draw``): masses,
    inertias, every length, the leg springs' stiffness, and the controllers' inputs in
    metres (their parameters are left to ``write_times``, which finds where they are
    declared)."""
    tree, text = parse_file(source)
    L = factors["L"]
    scaled = scale_of(factors)
    edits: list[tuple[ast.Span, float]] = []  # the span of a number and its factor

    def collect(node: Any, scale_of: Any) -> None:
        found: list[tuple[ast.Span, Any]] = []
        _walk(node, None, found)
        edits.extend((span, scale_of(dim)) for span, dim in found)

    def length_only(dim: Any) -> float:
        return length_factor(dim, L)

    legs = [p for c in tree.creatures for i in c.items if isinstance(i, ast.LegDecl)
            for p in i.props if p.key.name == "alias"]  # fmt: skip
    leg_springs = {a.value.ident.name for p in legs if isinstance(p.value, ast.Assigns)
                   for a in p.value.items if a.target.name == "spring"
                   and isinstance(a.value, ast.NameValue)}  # fmt: skip

    for creature in tree.creatures:
        for item in creature.items:
            if isinstance(item, ast.BodyDecl):
                m = factors.get("M") or factors["mass"].get(item.name.name, 1.0)
                collect(item.attach, length_only)
                for prop in item.props:
                    key = prop.key.name
                    if key == "mass":
                        collect(prop.value, lambda d, m=m: m)
                    elif key == "inertia":
                        collect(prop.value, lambda d, m=m: m * L * L)
                    else:
                        collect(prop.value, length_only)
            elif isinstance(item, ast.ContactDecl):
                collect(item.at, length_only)
            elif isinstance(item, ast.ActuatorDecl) and item.name.name in leg_springs:
                for arg in item.args:  # its stiffness; its rest length moves with the links
                    k = arg.keyword is not None and arg.keyword.name == "k"
                    collect(arg.value, (lambda d: factors["spring"]) if k else scaled)
            elif isinstance(item, ast.ActuatorDecl):
                collect(item.args, scaled)
    declared = [i for c in tree.controllers for i in c.items]
    declared += [i for s in tree.shared for i in s.items]
    for decl in declared:
        if isinstance(decl, ast.InputDecl):
            collect(decl.value, scaled)
    starts = [0]
    for line in text.splitlines(keepends=True):
        starts.append(starts[-1] + len(line))
    out = text
    spots = [(starts[s.line - 1] + s.col - 1, f) for s, f in edits if f != 1.0]
    for start, f in sorted(set(spots), reverse=True):
        match = _NUMBER.match(out, start)
        assert match is not None, f"no number at offset {start}"
        out = out[:start] + format_number(float(match.group(0)) * f) + out[match.end() :]
    return out


def length_factor(dim: Any, L: float) -> float:
    """L^n for a quantity of kg^0 m^n s^0 (an angle per metre too: 1/L); else 1."""
    mass, length, time_, _ = dim
    return L**length if mass == 0 and time_ == 0 and length != 0 else 1.0


def write_variant(
    source: Path, controller: str, factors: dict[str, Any], out: Path, springs: tuple[str, ...]
) -> Path:
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(variant_text(source, factors))
    params = check_model(out).controller(controller).params
    scaled = scale_of(factors)
    times = {p.name: scaled(p.dim) for p in params if p.value != 0}
    times |= {name: factors["spring"] for name in springs}
    write_times(out, controller, {n: f for n, f in times.items() if f != 1.0}, out)
    return out


def legdsl(*argv: str, check: bool = False) -> subprocess.CompletedProcess[str]:
    done = subprocess.run(["nice", "-n", "10", "legdsl", *argv], capture_output=True, text=True)
    if check and done.returncode != 0:
        sys.exit(f"legdsl {' '.join(argv)} failed ({done.returncode}): {done.stderr}")
    return done


def measure(file: Path, controller: str, out: Path, generated: Path) -> list[dict[str, Any]]:
    """At each speed, a 20 s run: its status (ok, fell at t) and running speed from 3 s."""
    rows = []
    for speed in SPEEDS:
        run = out / f"v{speed:g}"
        legdsl("run", str(file), "--controller", controller, "--set", f"speed={speed:g}m/s",
               "--time", f"{RUN_TIME:g}", "--backend", "c", "--generated", str(generated),
               "-o", str(run))  # fmt: skip
        info = json.loads((run / "run.json").read_text())
        metrics = legdsl("metrics", str(run), "--from", f"{FROM:g}", "--json",
                         "--generated", str(generated))  # fmt: skip
        summary = json.loads(metrics.stdout)["summary"] if metrics.returncode == 0 else {}
        measured = (summary.get("running_speed") or {}).get("value")
        measured = float(measured) if measured is not None else math.nan
        rows.append({"speed": speed, "status": info["status"], "sim_time": info["sim_time"],
                     "running_speed": measured,
                     "error": abs(measured - speed) / speed if info["status"] == "ok" else
                     math.nan})  # fmt: skip
    return rows


def held(rows: list[dict[str, Any]]) -> bool:
    return all(r["status"] == "ok" and r["error"] <= SUCCESS for r in rows)


def cell(row: dict[str, Any]) -> str:
    if row["status"] != "ok":
        return f"{row['status']} {row['sim_time']:.1f} s"
    return f"{100 * (row['running_speed'] - row['speed']) / row['speed']:+.1f}%"


def table(results: list[dict[str, Any]]) -> str:
    head = ("| # | L | masses (body, links) | spring k | shipped gains at "
            + ", ".join(f"{s:g}" for s in SPEEDS) + " m/s | tune objective | tuned at "
            + ", ".join(f"{s:g}" for s in SPEEDS) + " m/s | held |")  # fmt: skip
    lines = [head, "|" + "---|" * 8]
    for r in results:
        f = r["factors"]
        lines.append(
            f"| {r['index']} | x{f['L']:.2f} | {masses(f)}"
            f" | x{f['spring']:.2f} | {'; '.join(map(cell, r['before']))}"
            f" | {r['objective'][0]:.3g} -> {r['objective'][1]:.3g}"
            f" | {'; '.join(map(cell, r['after']))} | {'yes' if held(r['after']) else 'no'} |"
        )
    wins = sum(held(r["after"]) for r in results)
    shipped = sum(held(r["before"]) for r in results)
    lines.append("")
    lines.append(f"held every speed within {SUCCESS:.0%} for {RUN_TIME:g} s: shipped gains "
                 f"{shipped}/{len(results)}, tuned {wins}/{len(results)}")  # fmt: skip
    return "\n".join(lines)


def masses(factors: dict[str, Any]) -> str:
    if "M" in factors:  # --similar: one factor for every body
        return f"x{factors['M']:.2f} (every body)"
    return ", ".join(f"x{m:.2f}" for m in factors["mass"].values())


def mean_error(rows: list[dict[str, Any]]) -> float:
    """The mean relative speed error; a run that fell counts as 1 (off the scale)."""
    return sum(1.0 if r["status"] != "ok" else min(r["error"], 1.0) for r in rows) / len(rows)


def plot(results: list[dict[str, Any]], png: Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.4), dpi=110)
    xs = [r["index"] for r in results]
    before = [mean_error(r["before"]) for r in results]
    after = [mean_error(r["after"]) for r in results]
    for x, b, a in zip(xs, before, after, strict=True):
        ax.plot([x, x], [max(b, 1e-3), max(a, 1e-3)], color="grey", lw=1)
    ax.scatter(xs, [max(b, 1e-3) for b in before], marker="o", label="shipped gains")
    ax.scatter(xs, [max(a, 1e-3) for a in after], marker="s", label="tuned")
    ax.axhline(SUCCESS, color="green", ls=":", lw=1, label=f"{SUCCESS:.0%}")
    ax.set_yscale("log")
    ax.set_xlabel("variant")
    ax.set_ylabel("mean relative speed error (a fall counts 1)")
    ax.set_title(title)
    ax.set_xticks(xs)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3, frameon=False)
    fig.tight_layout()
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", type=Path)
    parser.add_argument("--controller", default="hop")
    parser.add_argument("-n", type=int, default=14, help="variants (14)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--png", type=Path, default=None)
    parser.add_argument("--recipe", choices=RECIPE, default="heavy20")
    parser.add_argument("--similar", action="store_true",
                        help="dynamically similar variants (the leg spring, every torque, "
                        "gain and time scaled with the mass and L)")  # fmt: skip
    parser.add_argument(
        "--only",
        type=int,
        action="append",
        default=None,
        metavar="N",
        help="run only variant N (repeatable; the draws stay the same)",
    )
    parser.add_argument(
        "--write-only", action="store_true", help="write each variant's .leg and stop"
    )
    args = parser.parse_args()
    recipe = RECIPE[args.recipe]
    global SPEEDS
    SPEEDS = tuple(float(v) for v in recipe[recipe.index("--speeds") + 1].split(","))
    rng = random.Random(args.seed)
    tree, _ = parse_file(args.file)
    bodies = {b.name: b.mass for b in check_model(args.file).bodies}
    results: list[dict[str, Any]] = []
    began = time.perf_counter()
    for index in range(1, args.n + 1):
        factors = draw(rng, bodies, args.similar)
        if args.only and index not in args.only:
            continue
        home = args.out / f"v{index:02d}"
        springs = SPRING_PARAMS.get(args.recipe, ())
        file = write_variant(args.file, args.controller, factors, home / args.file.name, springs)
        if args.write_only:
            print(f"wrote {file}: {json.dumps(factors)}")
            continue
        generated = home / "generated"
        before = measure(file, args.controller, home / "before", generated)
        tuned = legdsl("tune", str(file), "--controller", args.controller, *recipe,
                       "--generated", str(generated), "--out", str(home / "tuned"))  # fmt: skip
        (home / "tune.log").write_text(tuned.stdout + tuned.stderr)
        if tuned.returncode != 0:
            print(f"variant {index}: tune failed: {tuned.stderr.strip()}", flush=True)
            after, objective = before, (math.nan, math.nan)
        else:
            done = json.loads((home / "tuned" / "tune.json").read_text())
            objective = (done["start"]["objective"], done["best"]["objective"])
            after = measure(home / "tuned" / file.name, args.controller, home / "after", generated)
        results.append({"index": index, "factors": factors, "before": before, "after": after,
                        "objective": objective, "tune_status": tuned.returncode})  # fmt: skip
        spent = time.perf_counter() - began
        print(f"variant {index}/{args.n}: L x{factors['L']:.2f}, before "
              f"{'; '.join(map(cell, before))}, tuned {'; '.join(map(cell, after))} "
              f"({spent:.0f} s, about {spent / index * (args.n - index):.0f} s left)", flush=True)  # fmt: skip
        (args.out / "variants.json").write_text(json.dumps(results, indent=1) + "\n")
    if args.write_only:
        return 0
    text = table(results)
    print(text)
    (args.out / "variants.md").write_text(text + "\n")
    if args.png is not None:
        time_of = recipe[recipe.index("--time") + 1]
        title = f"{args.file.stem}: {args.n} random variants, seed {args.seed}, --recipe "
        similar = ", --similar" if args.similar else ""
        plot(results, args.png, title + f"{args.recipe}{similar} (--time {time_of})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
