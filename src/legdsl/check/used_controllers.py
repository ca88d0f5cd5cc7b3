"""The controllers of the files a file ``use``s, for ``controller NAME extends BASE`` where
BASE is not in the file itself: the nearest file that defines BASE (the fewest 'use's away
from the file asking), as for actions and shared parts."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from legdsl.lang import ast


@dataclass(frozen=True)
class Tie:
    """Files the same fewest 'use's away that each define the controller: neither wins."""

    files: tuple[str, ...]
    distance: int


@dataclass(frozen=True)
class UsedControllers:
    trees: dict[Path, ast.SourceFile]  # each file read (the first one too), by resolved path
    edges: dict[Path, list[Path]]  # what each file uses
    name: Callable[[Path], str]  # a file as messages name it

    def own(self, file: str) -> list[ast.ControllerDecl]:
        """The controllers written in ``file`` (a span's file)."""
        tree = self.trees.get(Path(file).resolve())
        return list(tree.controllers) if tree is not None else []

    def find(self, asking: str, base: str) -> list[ast.ControllerDecl] | Tie | None:
        """The controllers named ``base`` of the nearest file ``asking`` uses that has one."""
        start = Path(asking).resolve()
        seen = {start}
        frontier = [start]
        distance = 0
        while frontier:
            distance += 1
            following = []
            for f in frontier:
                for u in self.edges.get(f, []):
                    if u not in seen:
                        seen.add(u)
                        following.append(u)
            defining = [
                f
                for f in following
                if f in self.trees and any(c.name.name == base for c in self.trees[f].controllers)
            ]
            if len(defining) > 1:
                return Tie(tuple(self.name(f) for f in defining), distance)
            if defining:
                return [c for c in self.trees[defining[0]].controllers if c.name.name == base]
            frontier = following
        return None
