"""A creature's declaration whose keyword is misspelt ('boddy thigh on trunk via revolute hip
{ ... }', 'contakt toe on shank at tip', 'Body', 'bodies'). The parser reads it as the
creature's properties ('boddy thigh', 'on trunk', 'via revolute') and a block ('hip { ... }'),
so the checker would tell each of those, then every name the declaration declared as unknown
(its body, its joint, its contact). It is told once, at the keyword, as a misspelt keyword
that stops the parse is ('actuater hs on hip servo(...)').
"""

from __future__ import annotations

import difflib
from collections.abc import Sequence

from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic

# the declarations of a creature that read as properties when their keyword is misspelt
_DECLARATIONS = ("body", "contact", "actuator")
# what follows a declaration's name: 'on PARENT', or a body's 'free { ... }', 'fixed { ... }'
_AFTER_NAME = ("on", "free", "fixed")


def misspelt_keyword_message(word: str, right: str) -> str:
    """The sentence for ``word`` written where the keyword ``right`` was meant."""
    case = " (legdsl's words are lower-case)" if word.lower() == right else ""
    return f"'{word}' is not a word of legdsl; did you mean '{right}'?{case}"


def stem(word: str) -> str:
    """``word`` in lower case and, written as a plural, singular: 'Bodies' as 'body'."""
    lower = word.lower()
    if lower.endswith("ies"):
        return lower[:-3] + "y"
    return lower[:-1] if lower.endswith("s") and not lower.endswith("ss") else lower


def misspelt_declaration(file: str, tree: ast.SourceFile) -> Diagnostic | None:
    """The first declaration in ``tree`` whose keyword is misspelt: a property 'WORD NAME'
    followed on its line by 'on ...' (or 'free', 'fixed'), WORD close to a declaration's
    keyword."""
    for creature in tree.creatures:
        items = creature.items
        for item, after in zip(items, items[1:], strict=False):
            if not isinstance(item, ast.Prop) or not _names_one(item):
                continue
            line = [i for i in items if i.span.line == item.span.line]
            if _key(after) not in _AFTER_NAME or after.span.line != item.span.line:
                continue
            right = _meant(item.key.name, {k for i in line if (k := _key(i))}, line)
            if right is not None:
                return Diagnostic(item.key.span, misspelt_keyword_message(item.key.name, right))
    return None


def _key(item: object) -> str | None:
    if isinstance(item, ast.Prop):
        return item.key.name
    if isinstance(item, ast.BlockDecl):
        return item.name.name
    return None


def _names_one(prop: ast.Prop) -> bool:
    """Whether the property's value is a name alone: a declaration's name."""
    return isinstance(prop.value, ast.One) and isinstance(prop.value.value, ast.NameValue)


def _meant(word: str, keys: set[str], line: Sequence[object]) -> str | None:
    """The declaration's keyword ``word`` stands for, judged by its spelling and by what
    follows it on its line (``keys``: the properties' and blocks' keys read there)."""
    close = difflib.get_close_matches(stem(word), _DECLARATIONS, n=3, cutoff=0.6)
    if not close:
        return None
    has_block = any(isinstance(i, ast.BlockDecl) for i in line)
    shaped = (
        "body"
        if "via" in keys or "free" in keys or "fixed" in keys or has_block
        else "contact"
        if "at" in keys
        else None
    )
    return shaped if shaped in close else close[0]
