"""After ``import legdsl`` alone, the spellings docs/api.md uses work (``legdsl.api.Quantity``,
``legdsl.api.LegdslWarning`` in ``warnings.filterwarnings``): ``legdsl.api`` was an
AttributeError until something imported the API. ``dir(legdsl)`` lists them, and importing
legdsl stays light (the API is imported when first used)."""

from __future__ import annotations

import subprocess
import sys

SCRIPT = """
import sys, warnings
import legdsl
assert "legdsl.api" not in sys.modules and "numpy" not in sys.modules, "import not light"
names = dir(legdsl)
for name in ("api", "load", "open_run", "Run", "Creature", "Quantity", "LegdslWarning"):
    assert name in names, name
assert "os" not in names and "sys" not in names, names
assert "legdsl.api" not in sys.modules, "dir imported the API"
q = legdsl.api.Quantity(1.5, "m/s")
assert float(q) == 1.5, q
warnings.filterwarnings("ignore", category=legdsl.api.LegdslWarning)
assert legdsl.Quantity is legdsl.api.Quantity
try:
    legdsl.nosuch
except AttributeError as e:
    assert "nosuch" in str(e)
else:
    raise SystemExit("legdsl.nosuch")
print("ok")
"""


def test_documented_spellings_work_after_import_legdsl() -> None:
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"
