"""The files a random language file (tests/lang/test_random_language.py) uses beyond
parts.leg: a chain of `use`s (lib/near.leg uses far.leg), a file used from two paths
(parts.leg by the file and by lib/near.leg, read once), a used file's shared part holding
roles and a table, and a controller that `extends` a used file's controller of its own
name (lib/base.leg's `coast`, for a creature of that file). USE_MISTAKES are the mistakes
made in them: a missing file further down, a syntax error in a used file (told in that
file), a cycle of `use`, a base two used files define at the same distance, and a member
misspelt in a used action or base controller.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

USE_MISTAKES = (
    "use_deep_missing",
    "used_syntax_error",
    "use_cycle",
    "extends_two_used",
    "used_member_misspelled",  # in far.leg's action: told at the calls, naming the action
    "base_member_misspelled",  # in base.leg's coast: told there, naming both controllers
)
IN_CHAIN = ("use_deep_missing", "used_syntax_error", "use_cycle", "used_member_misspelled")
# what the diagnostics of each must show: the mistake itself, not another one it causes
USE_MISTAKE_SAYS = {
    "use_deep_missing": "cannot find 'gone.leg' to use (asked for in lib/far.leg)",
    "used_syntax_error": "lib/far.leg:3:",
    "use_cycle": "-> lib/near.leg -> lib/far.leg -> lib/near.leg;",
    "extends_two_used": "defined by both lib/base.leg and lib/base2.leg",
    "used_member_misspelled": "no member 'sprng'",
    "base_member_misspelled": "(in controller 'coast', from controller 'coast' of lib/base.leg)",
}
USE_MISTAKE_SHARE = 0.15  # of the files without a mistake of their own

DONOR = """creature donor {
  planar
  body box free { mass 5 kg  inertia 0.2 kg*m^2  initial x = 0 m, z = 0.8 m }
  body rod on box via prismatic slide at (0 m, -0.05 m) {
    length 0.6 m  com 0.3 m  mass 0.3 kg  inertia 0.009 kg*m^2
  }
  contact tip on rod at tip
  leg main { joints slide  foot tip  alias spring = slide_spring }
  actuator slide_spring on slide spring(k = 2500 N/m, rest = 0 m)
}
controller coast {
  roles active = main
  param push = 1 cm
  table {
    state UP on liftoff(active): active.spring.rest = 0 m
    state DOWN on touchdown(active): active.spring.rest = push
  }
}
"""


@dataclass
class UseSpec:
    chain: bool  # lib/near.leg uses far.leg, which defines the action 'brace'
    twice: bool  # lib/near.leg uses ../parts.leg too: one file, two paths
    part_table: bool  # near.leg's shared part 'coast_part' holds a table (and roles)
    part_roles: bool
    extends_used: bool  # 'controller coast extends coast': lib/base.leg's
    run: str  # the controller a valid file runs, "" for the test's own choice
    mistake: str = ""

    @property
    def near(self) -> bool:
        return self.chain or self.twice or self.part_table or self.mistake in IN_CHAIN


def draw_use(seed: int, other_mistake: str) -> UseSpec:
    """Drawn apart from the rest (the files of earlier seeds stay as they were)."""
    rng = random.Random(seed * 104729 + 3)  # CI seeds 0-7: one use mistake (far.leg)
    spec = UseSpec(
        chain=rng.random() < 0.4,
        twice=rng.random() < 0.3,
        part_table=rng.random() < 0.4,
        part_roles=rng.random() < 0.5,
        extends_used=rng.random() < 0.35,
        run=rng.choice(["", "", "glide", "coast"]),
    )
    if not other_mistake and rng.random() < USE_MISTAKE_SHARE:
        spec.mistake = rng.choice(USE_MISTAKES)
        spec.chain = spec.chain or spec.mistake in IN_CHAIN
        spec.extends_used = spec.extends_used or spec.mistake in USE_MISTAKES[3::2]
    if spec.run == "glide" and not (spec.near and (spec.chain or spec.part_table)):
        spec.run = ""
    if spec.run == "coast" and not spec.extends_used:
        spec.run = ""
    return spec


def use_lines(spec: UseSpec) -> list[str]:
    out = ['use "lib/near.leg"'] if spec.near else []
    if spec.extends_used:
        out.append('use "lib/base.leg"')
    if spec.mistake == "extends_two_used":
        out.append('use "lib/base2.leg"')
    return out


def controller_lines(spec: UseSpec, roles: str, forward: str) -> list[str]:
    """``glide`` (brace from the chain, or near.leg's part) and ``coast`` (base.leg's)."""
    out: list[str] = []
    if spec.near and (spec.chain or spec.part_table):
        out.append(f"controller glide {forward}{{")
        if spec.part_table:
            out.append("  include coast_part")
            out += [] if spec.part_roles else [f"  {roles}"]
            out.append("  param push = 1.5 cm")
        else:
            out += [
                f"  {roles}",
                "  param push = 1.5 cm",
                "  table {",
                "    state UP on liftoff(active): brace(active, 0 m)",
                "    state DOWN on touchdown(active): brace(active, push)",
                "  }",
            ]
        out.append("}")
    if spec.extends_used:
        out += [
            f"controller coast {forward}extends coast {{",
            f"  {roles}",
            "  param push = 2 cm",
            "}",
        ]
    return out


def files(spec: UseSpec, roles: str) -> dict[str, str]:
    """Relative path -> text of the used files (parts.leg is the test's)."""
    m = spec.mistake
    brace = "action brace(l, r) {\n  l.spring.rest = r\n}\n"
    if m == "used_syntax_error":
        brace = "action brace(l, r) {\n  l.spring.rest = r\n"  # the '}' left out
    far = "# the end of a chain of use\n" + brace
    if m == "use_deep_missing":
        far = 'use "gone.leg"\n' + far
    if m == "use_cycle":
        far = 'use "near.leg"\n' + far
    if m == "used_member_misspelled":
        far = far.replace("l.spring", "l.sprng")
    near = ['use "far.leg"'] if spec.chain else []
    if spec.twice:
        near.append('use "../parts.leg"')
    if not spec.chain:
        near.append(brace)
    if spec.part_table:
        near += ["shared coast_part {", "  param push = 1 cm"]
        near += [f"  {roles}"] if spec.part_roles else []
        near += [
            "  table {",
            "    state UP on liftoff(active): brace(active, 0 m)",
            "    state DOWN on touchdown(active): brace(active, push)",
            "  }",
            "}",
        ]
    base = DONOR
    if m == "base_member_misspelled":
        base = DONOR.replace("active.spring.rest = push", "active.sprin.rest = push")
    out = {"lib/near.leg": "\n".join(near) + "\n", "lib/far.leg": far, "lib/base.leg": base}
    if m == "extends_two_used":
        out["lib/base2.leg"] = DONOR.replace("donor", "donor2")
    return out
