"""An outside user's literal audit of docs/animation.md: it said the runtime leaves a lifted
contact's last force in trajectory.npz ("40 of 402 samples of the kangaroo's 1 s drop"),
where the runtime records it as zero (0 of 193 samples); and its player-size table gave the
kangaroo one contact (it has two: toe, tail_end). The doc's figures are checked here."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from conftest import CREATURES

from legdsl.pipeline.session import RunSession, check_file
from legdsl.sim.run_loop import RunOptions

DOC = " ".join((Path(__file__).resolve().parents[2] / "docs" / "animation.md").read_text().split())


def test_the_kangaroo_drop_has_no_lifted_force_as_the_doc_says(generated: Path) -> None:
    session = RunSession.from_file(CREATURES / "kangaroo.leg", generated=generated)
    tr = session.run(options=RunOptions(duration=1.0, drop=0.1)).result.trajectory
    lifted = tr.contact == 0
    stale = int(np.count_nonzero((tr.force * lifted[..., None]).any(axis=(1, 2))))
    assert lifted.any() and stale == 0
    said = re.search(r"none of the (\d+) samples of the kangaroo's 1 s drop, `--drop 0.1`", DOC)
    assert said is not None and int(said.group(1)) == len(tr.t)
    assert "leaves a lifted contact's last force" not in DOC


def test_the_player_size_table_counts_links_and_contacts_as_show_does() -> None:
    rows = dict(re.findall(r"\| (kangaroo|biped|quadruped)[^|]*\| (\d+, \d+) \|", DOC))
    assert set(rows) == {"kangaroo", "biped", "quadruped"}
    for name, counted in rows.items():
        model = check_file(str(CREATURES / f"{name}.leg"), None, None, None)[0]
        assert counted == f"{len(model.bodies)}, {len(model.contacts)}", name
