"""Templates: a part of a creature's tree written once and instantiated many times.

``template leg(S, HIP) { ... }`` holds bodies, contacts, actuators and legs written as
at creature level; ``instance fl = leg(S = fl, HIP = (0.39 m, 0.12 m, 0 m))`` puts a copy
of them where the instance line is. A parameter is replaced where it stands alone as a
value (``at HIP``) and where it is a whole underscore-separated part of a name
(``thigh_S`` -> ``thigh_fl``); parameters are written in capitals so that they never
clash with the parts of ordinary names. Every span of the copy gets the words
``(in instance 'fl' of template 'leg')``, which every error there ends with.

``mirror sagittal`` (y -> -y) or ``mirror frontal`` (x -> -x) reflects the instance;
that is done on the checked model by ``legdsl.check.mirror``, on the names this
expansion records for each mirrored instance.

The actuators of a run of instance lines are listed springs first, then servos, then
force sources (each kind instance by instance, in the template's order), the order in
which a creature's actuators are usually written by hand; everything else is listed
instance by instance.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, fields, is_dataclass, replace
from typing import Any

from legdsl.check.values import did_you_mean
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.units import Quantity

PLANES = {"sagittal": 1, "frontal": 0}  # the world axis each mirror reflects: y, x
_KIND_ORDER = {"spring": 0, "servo": 1, "force": 2, "torque": 2}


@dataclass(frozen=True)
class MirrorPart:
    """What one mirrored instance declared: its bodies (with their joints), contacts, actuators."""

    axis: int  # 0: x (frontal), 1: y (sagittal)
    bodies: frozenset[str]
    contacts: frozenset[str]
    actuators: frozenset[str]
    # joints and contacts outside the instance placed 'at tip' of one of its bodies:
    # at the mirrored tip
    at_tips: frozenset[str] = frozenset()
    # its own joints and contacts placed 'at tip' of a body outside it: where that tip is
    # (mirrored only by the instance that holds that body, if one is)
    on_outer_tips: frozenset[str] = frozenset()


@dataclass(frozen=True)
class Expansion:
    items: tuple[ast.CreatureItem, ...]  # the creature's items, every instance expanded
    mirrors: tuple[MirrorPart, ...]
    # what refused instances would have declared (what, name): a controller naming one is
    # no news
    unmade: tuple[tuple[str, ast.Ident], ...] = ()


def expand(decl: ast.CreatureDecl, diag: Diagnostics, planar: bool) -> Expansion:
    """The creature's items with its templates instantiated; mistakes go to ``diag``."""
    return _Expander(diag, planar).expand(decl.items)


def _by_kind(actuators: list[ast.ActuatorDecl]) -> list[ast.ActuatorDecl]:
    """Springs, then servos, then force sources; each kind in the order given."""
    return sorted(actuators, key=lambda a: _KIND_ORDER.get(a.kind.name, 3))


def _at_tips(part: MirrorPart, items: list[ast.CreatureItem]) -> MirrorPart:
    """``part`` with the joints and contacts 'at tip' of a body on the other side of its
    border: outside it on its bodies, and its own on bodies outside it."""
    found: set[str] = set()
    outer: set[str] = set()
    for i in items:
        if isinstance(i, ast.BodyDecl):
            a = i.attach
            if not isinstance(a, ast.AttachJoint) or not _tip(a.at):
                continue
            inside, parent_inside = i.name.name in part.bodies, a.parent.name in part.bodies
            if parent_inside and not inside:
                found.add(a.joint.name)
            elif inside and not parent_inside:
                outer.add(a.joint.name)
        elif isinstance(i, ast.ContactDecl) and _tip(i.at):
            inside, body_inside = i.name.name in part.contacts, i.body.name in part.bodies
            if body_inside and not inside:
                found.add(i.name.name)
            elif inside and not body_inside:
                outer.add(i.name.name)
    return replace(part, at_tips=frozenset(found), on_outer_tips=frozenset(outer))


def _tip(value: ast.Value | None) -> bool:
    return isinstance(value, ast.NameValue) and value.ident.name == "tip"


def _declared(item: ast.TemplateItem) -> list[tuple[str, ast.Ident]]:
    """(what, name) of everything an item declares."""
    if isinstance(item, ast.BodyDecl):
        out = [("body", item.name)]
        if isinstance(item.attach, ast.AttachJoint):
            out.append(("joint", item.attach.joint))
        return out
    what = {ast.ActuatorDecl: "actuator", ast.ContactDecl: "contact", ast.LegDecl: "leg"}
    return [(what[type(item)], item.name)]


class _Expander:
    def __init__(self, diag: Diagnostics, planar: bool):
        self.diag = diag
        self.planar = planar
        self.templates: dict[str, ast.TemplateDecl] = {}
        self.instances: dict[str, ast.InstanceDecl] = {}
        self.owner: dict[str, str] = {}  # a name declared by an instance -> that instance
        self.unmade: list[tuple[str, ast.Ident]] = []

    def expand(self, items: tuple[ast.CreatureItem, ...]) -> Expansion:
        for t in (i for i in items if isinstance(i, ast.TemplateDecl)):
            self.template(t)
        out: list[ast.CreatureItem] = []
        run: list[ast.ActuatorDecl] = []  # the actuators of the current run of instances
        mirrors: list[MirrorPart] = []
        for item in items:
            if isinstance(item, ast.TemplateDecl):
                continue
            if not isinstance(item, ast.InstanceDecl):
                out += _by_kind(run)
                run = []
                out.append(item)
                continue
            made = self.instance(item)
            if made is None:
                continue
            copy, mirrored = made
            out += [i for i in copy if not isinstance(i, ast.ActuatorDecl)]
            run += [i for i in copy if isinstance(i, ast.ActuatorDecl)]
            if mirrored:
                mirrors.append(self.mirror_part(item, copy))
        out += _by_kind(run)
        parts = tuple(_at_tips(m, out) for m in mirrors)
        return Expansion(tuple(out), parts, tuple(self.unmade))

    def template(self, t: ast.TemplateDecl) -> None:
        first = self.templates.get(t.name.name)
        if first is not None:
            self.diag.error(
                t.name.span,
                f"template '{t.name.name}' is defined twice; the first is at {first.name.span}",
            )
            return
        seen: set[str] = set()
        for p in t.params:
            if p.name in seen:
                self.diag.error(p.span, f"parameter '{p.name}' is listed twice")
            seen.add(p.name)
        self.templates[t.name.name] = t

    def instance(self, inst: ast.InstanceDecl) -> tuple[list[ast.TemplateItem], bool] | None:
        """The template's items for this instance and whether to mirror them, or None (and
        errors) if it cannot be made. A mirror that cannot be made leaves the copy as is."""
        name, tname = inst.name.name, inst.template.name
        template = self.templates.get(tname)
        if template is None:
            self.diag.error(
                inst.template.span,
                f"unknown template '{tname}'{did_you_mean(tname, self.templates)}"
                + ("" if self.templates else "; write 'template NAME(PARAMETERS) { ... }' first"),
            )
            for meant in difflib.get_close_matches(tname, list(self.templates), n=1):
                given = {a.target.name: a.value for a in inst.args}  # what it would declare
                self.declare_unmade(self.templates[meant], given, inst.name.span)
            return None
        if name in self.instances:
            self.diag.error(
                inst.name.span,
                f"instance '{name}' is declared twice; the first is at "
                f"{self.instances[name].name.span}",
            )
            return None
        self.instances[name] = inst
        within = f" (in instance '{name}' of template '{tname}')"

        def here(span: Span) -> Span:
            return replace(span, within=within)

        params = [p.name for p in template.params]
        args: dict[str, ast.Value] = {}
        ok = True
        # An argument too many, or given twice, is told and left out: the instance is made
        # of the others, so that the names it declares are known to the rest of the file.
        misspelt: dict[str, ast.Value] = {}  # the parameter an unknown one likely means
        for a in inst.args:
            if a.target.name not in params:
                listed = ", ".join(params) or "none"
                self.diag.error(
                    here(a.target.span),
                    f"template '{tname}' has no parameter '{a.target.name}'; its parameters "
                    f"are {listed}{did_you_mean(a.target.name, params)}",
                )
                for meant in difflib.get_close_matches(a.target.name, params, n=1):
                    misspelt.setdefault(meant, a.value)
            elif a.target.name in args:
                self.diag.error(here(a.target.span), f"parameter '{a.target.name}' is given twice")
            else:
                args[a.target.name] = respan(a.value, within)
        for meant, value in misspelt.items():  # not told missing too
            args.setdefault(meant, respan(value, within))
        missing = [p for p in params if p not in args]
        if missing:
            self.diag.error(
                inst.name.span,
                f"instance '{name}' of template '{tname}' does not give "
                + ", ".join(f"'{p}'" for p in missing)
                + f"; write {tname}({', '.join(p + ' = ...' for p in params)})",
            )
            ok = False
        mirrored = inst.mirror is not None and self.mirror_ok(
            here(inst.mirror.span), inst, template
        )
        if not ok:
            self.declare_unmade(template, args, inst.name.span)
            return None
        sub = _Substitution(args, within, self.diag)
        copy: list[ast.TemplateItem] = [sub.node(i) for i in template.items]
        for item in copy:
            for what, ident in _declared(item):
                other = self.owner.get(ident.name)
                if other is not None and other != name:
                    self.diag.error(
                        ident.span,
                        f"{what} '{ident.name}' is also declared by instance '{other}': "
                        "give the instances arguments that make their names differ",
                    )
                    ok = False
                self.owner.setdefault(ident.name, name)
        if not ok:  # its names no other instance made
            mine = [
                (w, i) for item in copy for w, i in _declared(item) if self.owner[i.name] == name
            ]
            self.unmade += mine
        return (copy, mirrored) if ok else None

    def declare_unmade(
        self, template: ast.TemplateDecl, args: dict[str, ast.Value], at: Span
    ) -> None:
        """What an instance that cannot be made would declare, as far as the arguments given
        make its names (``at``: the instance's name, where its mistake is told)."""
        probe = _Substitution(args, "", Diagnostics({}))
        for item in template.items:
            for what, ident in _declared(item):
                self.unmade.append((what, ast.Ident(probe.name(ident), at)))

    def mirror_ok(self, span: Span, inst: ast.InstanceDecl, template: ast.TemplateDecl) -> bool:
        assert inst.mirror is not None
        plane = inst.mirror
        if plane.name not in PLANES:
            self.diag.error(
                span,
                f"unknown mirror '{plane.name}'; use 'mirror sagittal' (y to -y, left to "
                f"right) or 'mirror frontal' (x to -x, front to back){did_you_mean(plane.name, PLANES)}",
            )
            return False
        if self.planar and plane.name == "sagittal":
            self.diag.error(
                span,
                "a planar creature lies in the sagittal (x-z) plane, so it cannot be mirrored "
                "about it; use 'mirror frontal' (x to -x) or no mirror",
            )
            return False
        for b in template.items:
            if isinstance(b, ast.BodyDecl) and not isinstance(b.attach, ast.AttachJoint):
                self.diag.error(
                    span,
                    f"template '{template.name.name}' holds the root body '{b.name.name}', "
                    "which a mirror cannot move; mirror only parts that hang from another body",
                )
                return False
        return True

    def mirror_part(self, inst: ast.InstanceDecl, copy: list[ast.TemplateItem]) -> MirrorPart:
        assert inst.mirror is not None

        def names(kind: type) -> frozenset[str]:
            return frozenset(i.name.name for i in copy if isinstance(i, kind))

        return MirrorPart(
            PLANES[inst.mirror.name],
            names(ast.BodyDecl),
            names(ast.ContactDecl),
            names(ast.ActuatorDecl),
        )


def respan(node: Any, within: str) -> Any:
    """``node`` with ``within`` on every span in it."""
    if isinstance(node, Span):
        return replace(node, within=within)
    if isinstance(node, tuple):
        return tuple(respan(x, within) for x in node)
    if is_dataclass(node) and not isinstance(node, type | Quantity):
        return replace(
            node, **{f.name: respan(getattr(node, f.name), within) for f in fields(node)}
        )
    return node


GIVEN_A_VALUE = "is given a value, not a name"
# The fields that hold a word of the language, never a name: no parameter is put there (a
# parameter 'spring' naming the leg's spring leaves 'spring(k = ...)' a spring).
_WORDS: dict[type, tuple[str, ...]] = {
    ast.AttachJoint: ("kind",),  # via revolute
    ast.ActuatorDecl: ("kind",),  # servo(...)
    ast.Prop: ("key",),  # mass 2 kg
    ast.Arg: ("keyword",),  # k = 3000 N/m
    ast.Call: ("func",),  # shape capsule(...)
}


class _Substitution:
    """The arguments of one instance put into a copy of its template's items."""

    def __init__(self, args: dict[str, ast.Value], within: str, diag: Diagnostics):
        self.args = args
        self.within = within
        self.diag = diag

    def node(self, node: Any) -> Any:
        if isinstance(node, Span):
            return replace(node, within=self.within)
        if isinstance(node, ast.NameValue) and node.ident.name in self.args:
            return self.args[node.ident.name]  # a value: the argument as written
        if isinstance(node, ast.Ident):
            return ast.Ident(self.name(node), replace(node.span, within=self.within))
        if isinstance(node, tuple):
            return tuple(self.node(x) for x in node)
        if isinstance(node, ast.Prop) and node.key.name == "stop":  # 'stop k = ..., b = ...'
            return respan(node, self.within)  # words and numbers: no name in it
        if is_dataclass(node) and not isinstance(node, type | Quantity):
            words = _WORDS.get(type(node), ())
            changed = {}
            for f in fields(node):
                value = getattr(node, f.name)
                changed[f.name] = (
                    respan(value, self.within) if f.name in words else self.node(value)
                )
            return replace(node, **changed)
        return node

    def name(self, ident: ast.Ident) -> str:
        parts = ident.name.split("_")
        out = []
        for k, part in enumerate(parts):
            arg = self.args.get(part)
            if arg is None:
                out.append(part)
            elif isinstance(arg, ast.NameValue):
                out.append(arg.ident.name)
            elif k > 0 and isinstance(arg, ast.Number) and arg.text.isdigit():
                out.append(arg.text)  # 'a_S' with S = 1 is 'a_1', a name as written by hand
            else:
                self.diag.error(
                    replace(ident.span, within=self.within),
                    f"parameter '{part}' {GIVEN_A_VALUE}, so it cannot stand in the name "
                    f"'{ident.name}': give it a name (or, after the name's first part, a whole "
                    f"number: '{parts[0]}_1')",
                )
                out.append(part)
        return "_".join(out)
