"""A griffe extension: redik's docstrings keep reST markup, the site renders it as Markdown.

The docstrings are Google style with two pieces of reST that Python tools and readers of the
source know: roles (``:func:`redik.solve_pose```) and ``.. math::`` blocks. The reference pages
turn each role into a link to the named object when the site documents it (an optional
cross-reference: plain code when it does not, never a broken link) and each math block into a
display equation that MathJax typesets. ``:math:`x``` becomes inline math.
"""

from __future__ import annotations

import re
import textwrap
from typing import Any

import griffe

ROLE = re.compile(r":(?:py:)?(func|class|meth|mod|attr|data|exc|obj|const):`~?\.?([^`<>]+?)`")
INLINE_MATH = re.compile(r":math:`([^`]+)`")
MATH_BLOCK = re.compile(
    r"^(?P<indent>[ \t]*)\.\. math::[ \t]*\n((?:(?P=indent)[ \t]*\n)*)"
    r"(?P<body>(?:(?P=indent)[ \t]+\S.*\n|[ \t]*\n)+)",
    re.MULTILINE,
)


def _resolve(name: str, obj: griffe.Object, collection: griffe.ModulesCollection) -> str | None:
    """The full path ``name`` denotes where ``obj``'s docstring uses it, or None."""
    scopes = [obj.path]
    parent = obj.parent
    while parent is not None:
        scopes.append(parent.path)
        parent = parent.parent
    candidates = [name] + [f"{scope}.{name}" for scope in scopes] + [f"redik.{name}"]
    for candidate in candidates:
        try:
            collection.get_member(candidate)
        except (KeyError, ValueError, griffe.AliasResolutionError, griffe.CyclicAliasError):
            continue
        return candidate
    return None


def _math_block(match: re.Match) -> str:
    body = textwrap.dedent(match.group("body")).strip("\n")
    indent = match.group("indent")
    return f"{indent}$$\n{textwrap.indent(body, indent)}\n{indent}$$\n\n"


def convert(text: str, obj: griffe.Object, collection: griffe.ModulesCollection) -> str:
    """``text`` with its roles as cross-references and its math as MathJax input."""

    def role(match: re.Match) -> str:
        name = match.group(2).strip()
        shown = name.removesuffix("()")
        if match.group(0).startswith((":func:`~", ":class:`~", ":meth:`~", ":attr:`~")):
            shown = shown.rsplit(".", 1)[-1]
        target = _resolve(name.removesuffix("()"), obj, collection)
        if target is None:
            return f"`{shown}`"
        return f'<autoref optional identifier="{target}"><code>{shown}</code></autoref>'

    text = MATH_BLOCK.sub(_math_block, text if text.endswith("\n") else text + "\n")
    text = INLINE_MATH.sub(lambda m: f"${m.group(1)}$", text)
    return ROLE.sub(role, text)


class SphinxMarkup(griffe.Extension):
    """Rewrites every docstring once the whole package is loaded (names resolve then)."""

    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs: Any) -> None:
        """Convert the docstrings of ``pkg`` and everything in it."""
        collection = loader.modules_collection
        stack: list[griffe.Object] = [pkg]
        while stack:
            obj = stack.pop()
            if obj.docstring is not None:
                obj.docstring.value = convert(obj.docstring.value, obj, collection)
            stack.extend(m for m in obj.members.values() if not m.is_alias)
