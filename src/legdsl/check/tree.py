"""The link tree of a creature: its bodies in order (parents before children), each
checked with the joint that hangs it from its parent, and the initial state they make."""

from __future__ import annotations

from dataclasses import replace

from legdsl.check.bodies import BodyChecker
from legdsl.check.joints import JointChecker
from legdsl.check.scope import CreaturePart, Scope
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Body, Joint
from legdsl.lang import ast


class TreeChecker(CreaturePart):
    """Orders the body declarations into a tree, then checks each body and its joint."""

    def __init__(self, scope: Scope):
        super().__init__(scope)
        self.bodies = BodyChecker(scope)
        self.joints = JointChecker(scope)

    def tree_order(self, creature: ast.Ident, decls: list[ast.BodyDecl]) -> list[ast.BodyDecl]:
        """Bodies with parents before children; reports duplicates, roots and cycles."""
        by_name: dict[str, ast.BodyDecl] = {}
        for b in decls:
            if b.name.name in by_name:
                first = by_name[b.name.name]
                self.err(
                    b.name.span,
                    f"body '{b.name.name}' is declared twice (a body has one parent); "
                    f"the first is at {first.name.span}{first.name.span.within}",
                )
                if isinstance(b.attach, ast.AttachJoint):  # what is on its joint: not told again
                    self.unsettled.add(b.attach.joint.name)
                continue
            by_name[b.name.name] = b
        roots = [b for b in by_name.values() if not isinstance(b.attach, ast.AttachJoint)]
        if not roots and by_name:
            self.err(
                creature.span,
                f"creature '{creature.name}' has no root body: "
                "make one body 'free' (it flies) or 'fixed' (welded to the world)",
            )
        elif not by_name:
            self.err(creature.span, f"creature '{creature.name}' has no bodies")
        for extra in roots[1:]:
            self.err(
                extra.attach.span,
                f"a second root: body '{extra.name.name}' is also free or fixed, but "
                f"'{roots[0].name.name}' is the root; hang it from a parent with "
                "'on PARENT via KIND JOINT'",
            )
        children: dict[str, list[ast.BodyDecl]] = {}
        # Bodies cut off the tree by a mistake told here (a misspelt parent, hung from itself,
        # a second root, a cycle) are still checked, with the bodies below them, so that their
        # own mistakes show and no name they declare looks unknown.
        cut: list[ast.BodyDecl] = [_rooted(extra) for extra in roots[1:]]
        for b in by_name.values():
            if isinstance(b.attach, ast.AttachJoint):
                parent = b.attach.parent
                if parent.name not in by_name:
                    self.err(parent.span, _unknown_parent(parent.name, b.name.name, by_name))
                    cut.append(b)
                elif parent.name == b.name.name:
                    self.err(parent.span, _self_parent(b.name.name, by_name))
                    cut.append(_unhung(b))
                else:
                    children.setdefault(parent.name, []).append(b)
        order: list[ast.BodyDecl] = []
        seen: set[str] = set()

        def below(top: ast.BodyDecl) -> None:
            """``top`` and the bodies below it, parents first, into ``order``."""
            stack = [top]
            while stack:
                b = stack.pop()
                if b.name.name in seen:
                    continue
                seen.add(b.name.name)
                order.append(b)
                stack.extend(reversed(children.get(b.name.name, [])))

        for top in roots[:1] + cut:
            below(top)
        # Bodies still not reached hang from a cycle: told once, and cut at the body told.
        for b in by_name.values():
            if b.name.name in seen:
                continue
            chain = [b.name.name]
            node = b
            while isinstance(node.attach, ast.AttachJoint):
                node = by_name[node.attach.parent.name]
                if node.name.name in chain:
                    loop = chain[chain.index(node.name.name) :]
                    at = loop.index(min(loop))  # told from its first name, whichever body led
                    loop = loop[at:] + loop[:at]
                    first = by_name[loop[0]]
                    self.err(
                        first.name.span,
                        "bodies form a cycle: "
                        + " -> ".join([*loop, loop[0]])
                        + f"; a creature is a tree: hang '{loop[0]}' from a body outside the "
                        "cycle (or make it the root, 'free' or 'fixed')",
                    )
                    below(_unhung(first))
                    break
                chain.append(node.name.name)
        return order

    def build_tree(
        self, order: list[ast.BodyDecl]
    ) -> tuple[list[Body], list[Joint], list[float], list[float]]:
        """The bodies and joints in ``order``, and the initial positions and rates they make."""
        bodies: list[Body] = []
        joints: list[Joint] = []
        q0: list[float] = []
        v0: list[float] = []
        by_name: dict[str, Body] = {}
        for decl in order:
            props = self.bodies.body_props(decl)
            body = self.bodies.body(decl, props, by_name)
            joint, q_init, v_init = self.joints.joint(decl, props, body, by_name, len(q0), len(v0))
            by_name[body.name] = body
            bodies.append(body)
            joints.append(joint)
            q0 += q_init
            v0 += v_init
        return bodies, joints, q0, v0


def _unhung(body: ast.BodyDecl) -> ast.BodyDecl:
    """``body`` hung from no body of the creature (its parent named ''), so that no walk up
    from it goes round a cycle; its joint is checked as written."""
    assert isinstance(body.attach, ast.AttachJoint)
    nowhere = ast.Ident("", body.attach.parent.span)
    return replace(body, attach=replace(body.attach, parent=nowhere))


def _rooted(body: ast.BodyDecl) -> ast.BodyDecl:
    """A second root checked as welded to the world: free, it would declare the root's
    coordinates (x, z, pitch) a second time. Its initial state went with its freedom."""
    if not isinstance(body.attach, ast.AttachFree):
        return body
    props = tuple(p for p in body.props if p.key.name not in ("initial", "velocity"))
    return replace(body, attach=ast.AttachFixed(None, body.attach.span), props=props)


def _self_parent(child: str, bodies: dict[str, ast.BodyDecl]) -> str:
    """A body written as its own parent, and the way out."""
    others = [name for name in bodies if name != child]
    head = f"body '{child}' cannot hang from itself"
    if not others:
        return head + f"; make it the root with 'body {child} free' (or 'fixed')"
    shown = ", ".join(others[:6]) + (", ..." if len(others) > 6 else "")
    return head + f"; hang it from another of this creature's bodies ({shown})"


def _unknown_parent(parent: str, child: str, bodies: dict[str, ast.BodyDecl]) -> str:
    head = f"unknown parent body '{parent}'"
    hint = did_you_mean(parent, bodies)
    if hint:
        return head + hint
    others = [name for name in bodies if name != child]
    if parent in ("ground", "world"):
        return head + f"; to weld body '{child}' to the world, write 'body {child} fixed'"
    if not others:
        return head + "; declare the parent body in this creature first"
    shown = ", ".join(others[:6]) + (", ..." if len(others) > 6 else "")
    return head + f"; hang '{child}' from one of this creature's bodies ({shown})"
