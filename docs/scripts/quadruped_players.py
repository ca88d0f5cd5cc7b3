"""The quadruped's HTML players, one per gait and one of the transition run, and a picture of each.

    python docs/scripts/quadruped_players.py OUT_DIR     # players in OUT_DIR, pictures in docs/img

Runs each gait at the speed of its Figure 6 in docs/quadruped.md (trot 2.3 m/s, pace 2 m/s,
bound 2.8 m/s, gallop 4 m/s, 10 s) and the issue's transition run (24 s) with ``legdsl run
... --animate``, which writes ``OUT_DIR/NAME/animation.html``; then opens each player in
headless Chromium (the browser tests' driver, tests/chromium.py), moves it to a moment in mid
stride with the state, speed, force and footprint overlays on, and saves the screenshot as
``docs/img/player-quadruped-NAME.png``. Needs Chromium (``apt-get install chromium``).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))

from chromium import Chromium, find_chromium  # noqa: E402

TRANSITION = [
    "--controller", "trot", "--set", "speed=2m/s",
    "--switch", "6s=bound", "--set", "speed=2.8m/s@6s",
    "--switch", "12s=gallop", "--set", "speed=4m/s@12s",
    "--switch", "18s=trot", "--set", "speed=2m/s@18s", "--time", "24",
]  # fmt: skip
RUNS = {  # name: (the run's arguments, the moment shown in seconds)
    "trot": (["--controller", "trot", "--set", "speed=2.3m/s", "--time", "10"], 8.0),
    "pace": (["--controller", "pace", "--set", "speed=2m/s", "--time", "10"], 8.0),
    "bound": (["--controller", "bound", "--set", "speed=2.8m/s", "--time", "10"], 8.0),
    "gallop": (["--controller", "gallop", "--set", "speed=4m/s", "--time", "10"], 8.0),
    "transition": (TRANSITION, 14.0),
}
WIDTH, HEIGHT = 1000, 600


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    browser_path = find_chromium()
    if browser_path is None:
        sys.exit("Chromium is needed: apt-get install chromium")
    with Chromium(browser_path, WIDTH, HEIGHT) as browser:
        for name, (args, moment) in RUNS.items():
            run = out / name
            command = [sys.executable, "-m", "legdsl", "run", "creatures/quadruped.leg", *args]
            done = subprocess.run([*command, "--out", str(run), "--animate"], cwd=ROOT,
                                  capture_output=True, text=True)  # fmt: skip
            print(f"{name}: {done.stdout.strip().splitlines()[-1] if done.stdout else ''}")
            if done.returncode not in (0, 4):  # 4: the run fell, and its player shows where
                sys.exit(done.stderr)
            browser.open((run / "animation.html").resolve().as_uri())
            browser.wait_for("window.legdsl && window.legdsl.ready", timeout=60)
            if browser.errors():
                sys.exit(f"{name}: the player reported {browser.errors()}")
            browser.evaluate("legdsl.setOverlays({state: true, speed: true, forces: true, "
                             "footprints: true, com: false})")  # fmt: skip
            browser.evaluate(f"legdsl.setTime({moment})")
            picture = ROOT / "docs" / "img" / f"player-quadruped-{name}.png"
            picture.write_bytes(browser.screenshot())
            print(f"  {run / 'animation.html'} -> {picture.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
