"""Print sympy expressions as C99 that computes, operation for operation, what the Python print does.

This printer *is* the Python printer (``legdsl.codegen.python.printer.LegPrinter``) with three
changes of spelling, so that both targets share one lowering and one choice of evaluation order:

* a division ``a/b`` becomes ``leg_div(a, b)``: Python raises ``ZeroDivisionError`` for a zero
  divisor where C gives an infinity, and the C runtime must stop where Python does (the helper
  flags the error in ``*err`` and divides as C does);
* ``math.sqrt``, ``math.sin``, ``math.cos`` become ``leg_sqrt``, ``leg_sin``, ``leg_cos`` (libm's
  function, flagging Python's "math domain error" where Python raises it);
* ``x**y`` becomes ``leg_pow(x, y)`` (libm ``pow``, which CPython's float power calls too).

Everything else is printed by the same code as the Python target: numbers as ``repr(float)``
(the shortest text that reads back to the same double, which a C compiler reads back exactly),
small integer powers unrolled into the same products, sums and products in the same order with
the same parentheses. C and Python give ``*``, ``/``, ``+``, ``-`` and unary minus the same
precedence and left-to-right grouping, so the same text is the same sequence of IEEE operations
once the compiler is kept from contracting or reassociating (``-ffp-contract=off``, no
``-ffast-math``: ``legdsl.codegen.c.build``).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

from sympy import Expr, Mul, Pow, S, Symbol
from sympy.core.mul import _keep_coeff
from sympy.printing.precedence import PRECEDENCE, precedence

from legdsl.codegen.python.printer import LegPrinter, _is_half
from legdsl.lower.straightline import Assign, Unpack, is_unrolled_power
from legdsl.lower.symbolic import Function, Nested

# The functions of Python's math module the C runtime has a checked twin of (legdsl_math.h).
C_MATH = {
    "math.sin": "leg_sin",
    "math.cos": "leg_cos",
    "math.tan": "leg_tan",
    "math.sqrt": "leg_sqrt",
    "math.asin": "leg_asin",
    "math.acos": "leg_acos",
    "math.atan": "atan",  # never raises
    "math.atan2": "atan2",  # never raises (CPython's special cases are C99's)
    "math.exp": "leg_exp",
    "math.log": "leg_log",
    "abs": "fabs",
}

_RESERVED = """auto break case char const continue default do double else enum extern float for
goto if inline int long register restrict return short signed sizeof static struct switch typedef
union unsigned void volatile while err out"""
C_KEYWORDS = frozenset(_RESERVED.split())
# Names a local of a generated function must not take in C though Python allows them: later C
# keywords, the macros of the headers it includes (NAN would expand), and the functions and
# macros it calls (a local leg_min hides leg_min()); legdsl_math.h's names are in the test.
_TAKEN_IN_C = """_Bool _Complex _Imaginary _Alignas _Alignof _Atomic _Generic _Noreturn
_Static_assert _Thread_local bool true false alignas alignof static_assert thread_local nullptr
constexpr typeof typeof_unqual asm NULL offsetof errno EDOM ERANGE EILSEQ
NAN INFINITY HUGE_VAL HUGE_VALF HUGE_VALL math_errhandling fpclassify isfinite isinf isnan
isnormal signbit isgreater isgreaterequal isless islessequal islessgreater isunordered
sin cos tan asin acos atan atan2 sqrt exp log pow fabs floor copysign sincos fmin fmax memcpy
leg_acos leg_acos_e leg_asin leg_asin_e leg_cos leg_cos_e leg_cos_t leg_div leg_div_e leg_exp
leg_exp_e leg_flag leg_log leg_log_e leg_math1 leg_max leg_min leg_pow leg_pow_e leg_sin
leg_sin_e leg_sin_t leg_sqrt leg_sqrt_e leg_tan leg_tan_e leg_trig_entry leg_trig_fill
leg_trig_find leg_trig_here leg_trig_table leg_whole_turn_pitch"""
C_TAKEN = C_KEYWORDS | frozenset(_TAKEN_IN_C.split())
# Reserved to the implementation (_X, __x) and the macro families of math.h and stdint.h.
_C_MACRO_LIKE = re.compile(
    r"_[A-Z_].*|(?:LEG|FP|M|MATH)_[A-Z0-9_]*"
    r"|U?INT(?:_LEAST|_FAST)?(?:8|16|32|64|MAX|PTR)_(?:MAX|MIN|WIDTH)|U?INT(?:8|16|32|64|MAX)_C"
    r"|(?:PTRDIFF|SIZE|SIG_ATOMIC|WCHAR|WINT)_(?:MAX|MIN|WIDTH)"
)


def taken_in_c(name: str) -> bool:
    """Whether a Python identifier cannot be a local of the same name in the generated C."""
    return name in C_TAKEN or _C_MACRO_LIKE.fullmatch(name) is not None


class UnsupportedInC(Exception):
    """An expression the C printer has no exact twin for (a compiler bug, never a user's)."""


class CPrinter(LegPrinter):
    """The Python printer, spelling divisions, math functions and powers as checked C calls."""

    def __init__(
        self,
        names: Mapping[Symbol, str] | None = None,
        bases: Mapping[Expr, Symbol] | None = None,
        local_names: Iterable[str] = (),
    ):
        super().__init__(names, bases)
        self._spelling = c_spellings(local_names)

    @classmethod
    def for_function(cls, function: Function) -> CPrinter:
        """A printer for ``function``'s body, spelling its locals as C identifiers."""
        return cls(function.names, function.bases, local_names(function))

    def c_name(self, name: str) -> str:
        """The C spelling of the Python name ``name`` in this printer's function."""
        return self._spelling.get(name, name)

    def _print_Symbol(self, expr: Symbol) -> str:
        return self.c_name(super()._print_Symbol(expr))

    def _module_format(self, fqn: str, register: bool = True) -> str:
        if fqn in C_MATH:
            return C_MATH[fqn]
        raise UnsupportedInC(f"no C twin of {fqn} (add one to legdsl_math.h and C_MATH)")

    def _print_Pow(self, expr: Pow, rational: bool = False) -> str:
        base, exp = expr.as_base_exp()
        if is_unrolled_power(expr):  # as the Python print unrolls it
            named = self._bases.get(expr.base)
            if named is not None:
                factor = self._print(named)
            elif expr.base.is_Atom:
                factor = self.parenthesize(expr.base, PRECEDENCE["Mul"], strict=True)
            else:
                factor = ""
            if factor:
                product = "*".join([factor] * abs(int(expr.exp)))
                return product if expr.exp > 0 else f"leg_div(1.0, {product})"
        if exp == -1:
            return f"leg_div(1.0, {self._print(base)})"
        if _is_half(exp):
            return f"leg_sqrt({self._print(base)})"
        return f"leg_pow({self._print(base)}, {self._print(exp)})"

    def _print_Mul(self, expr: Mul) -> str:
        # sympy's CodePrinter._print_Mul (the Python target's), with its final "a/b" as leg_div
        prec = precedence(expr)
        c, e = expr.as_coeff_Mul()
        sign = ""
        if c < 0:
            expr = _keep_coeff(-c, e)
            sign = "-"
        numer: list[Expr] = []
        denom: list[Expr] = []
        pow_paren = []
        args = (
            expr.as_ordered_factors() if self.order not in ("old", "none") else Mul.make_args(expr)
        )
        for item in args:
            if (
                item.is_commutative
                and item.is_Pow
                and item.exp.is_Rational
                and item.exp.is_negative
            ):
                if item.exp != -1:
                    denom.append(Pow(item.base, -item.exp, evaluate=False))
                else:
                    if len(item.args[0].args) != 1 and isinstance(item.base, Mul):
                        pow_paren.append(item)
                    denom.append(Pow(item.base, -item.exp))
            else:
                numer.append(item)
        numer = numer or [S.One]
        if len(numer) == 1 and sign == "-":
            a_str = [self.parenthesize(numer[0], 0.5 * (PRECEDENCE["Pow"] + PRECEDENCE["Mul"]))]
        else:
            a_str = [self.parenthesize(x, prec) for x in numer]
        b_str = [self.parenthesize(x, prec) for x in denom]
        for item in pow_paren:
            if item.base in denom:
                b_str[denom.index(item.base)] = f"({b_str[denom.index(item.base)]})"
        top = sign + "*".join(a_str)
        if not denom:
            return top
        return f"leg_div({top}, {'*'.join(b_str)})"

    # ---------------------------------------------------------------- control expressions
    def _print_Min(self, expr: Expr) -> str:
        return _fold("leg_min", [self._print(a) for a in expr.args])

    def _print_Max(self, expr: Expr) -> str:
        return _fold("leg_max", [self._print(a) for a in expr.args])

    def _print_re(self, expr: Expr) -> str:
        return f"({self._print(expr.args[0])})"  # of a real value (the Python print's note)

    def _print_im(self, expr: Expr) -> str:
        return "0.0"  # of a real value (the Python print's note)

    def _print_sign(self, expr: Expr) -> str:
        x = self._print(expr.args[0])
        # sign(NaN) is NaN, as in the Python print (the state machine then faults)
        return f"(({x}) == 0 ? 0.0 : ({x}) == ({x}) ? copysign(1.0, {x}) : NAN)"

    def _print_Piecewise(self, expr: Expr) -> str:
        *pieces, last = expr.args
        if last.cond != True:  # noqa: E712 (sympy's true): Python would give None
            raise UnsupportedInC("a select without a last 'otherwise' branch")
        text = f"({self._print(last.expr)})"
        for piece in reversed(pieces):
            text = f"(({self._print(piece.cond)}) ? ({self._print(piece.expr)}) : {text})"
        return text

    def _print_Relational(self, expr: Expr) -> str:
        if expr.rel_op not in ("==", "!=", "<", "<=", ">", ">="):
            raise UnsupportedInC(f"the relation {expr.rel_op}")
        return f"({self._print(expr.lhs)} {expr.rel_op} {self._print(expr.rhs)})"

    def _print_And(self, expr: Expr) -> str:
        return self._logic(expr, "&&")

    def _print_Or(self, expr: Expr) -> str:
        return self._logic(expr, "||")

    def _logic(self, expr: Expr, op: str) -> str:
        # the Python print's order (default_sort_key), which is also its short-circuit order
        from sympy import default_sort_key

        args = sorted(expr.args, key=default_sort_key)
        return "(" + f" {op} ".join(f"({self._print(a)})" for a in args) + ")"

    def _print_Not(self, expr: Expr) -> str:
        return f"(!({self._print(expr.args[0])}))"

    def _print_BooleanTrue(self, expr: Expr) -> str:
        return "1"

    def _print_BooleanFalse(self, expr: Expr) -> str:
        return "0"


def _fold(name: str, args: list[str]) -> str:
    """Python's min(a, b, c) as leg_min(leg_min(a, b), c): the same comparisons in order."""
    text = args[0]
    for arg in args[1:]:
        text = f"{name}({text}, {arg})"
    return text


def local_names(function: Function) -> list[str]:
    """The Python names of ``function``'s locals, in order."""
    return [
        st.target.name if isinstance(st, Unpack) else function.name_of(st.target)
        for st in function.statements
        if isinstance(st, Unpack | Assign)
    ]


def c_spellings(names: Iterable[str]) -> dict[str, str]:
    """Each of a function's Python locals that C cannot spell as it is, as a C identifier:
    ``int`` -> ``int_``, or ``int_2`` when the function has an ``int_`` as well; ``_Bool`` ->
    ``u_Bool``, ``M_PI`` -> ``uM_PI``."""
    names = list(dict.fromkeys(names))
    used = {n for n in names if not taken_in_c(n)}
    spelling = {}
    for name in names:
        if name in used:
            continue
        base = f"{name}_"
        if taken_in_c(base):  # the implementation's (_Bool) or a macro family's (M_PI): no
            base = f"u{name}"  # suffix frees it, and no taken name starts with a lowercase u
        spelled, n = base, 1
        while spelled in used:
            n += 1
            spelled = f"{base}{n}"
        used.add(spelled)
        spelling[name] = spelled
    return spelling


INDENT = "    "  # one level of the generated C


def flatten(value: Nested) -> list[Nested]:
    """The leaves of a returned value, in the order the Python function nests them (the order
    a C function writes them into ``out``)."""
    if isinstance(value, list | tuple):
        return [leaf for item in value for leaf in flatten(item)]
    return [value]
