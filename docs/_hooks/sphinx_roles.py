"""A griffe extension for the API reference (``mkdocs.yml``: mkdocstrings' ``extensions``): the docstrings' Sphinx
roles, ``:func:`~mol_shell.runs.simulate.simulate``` and the like, rendered as cross-references.

mkdocstrings renders Markdown, in which a role stayed as its text (``:func:`` then a code span, ~1,160 of them, none
a link). Each role becomes an *optional* autorefs reference to the object's full path: a link where that object is
rendered on a page of the site, else its title as code, with no warning in ``mkdocs build --strict`` (autorefs drops
an optional reference it cannot resolve to its title). A name the object's scope does not resolve (griffe's
:meth:`griffe.Object.resolve`: a member, an import, a parent's) is left as code. ``~`` shows the last part of the
name, ``title <target>`` the title, as in Sphinx.
"""

from __future__ import annotations

import html
import re

import griffe

#: a Sphinx role of a Python object: ``:func:`name```, ``:py:meth:`~a.b```, ``:class:`title <a.b.C>```
ROLE = re.compile(r"(?<![\w`:]):(?:py:)?(?:func|meth|class|attr|data|mod|obj|exc|const|type):`(?P<body>[^`]+)`")
TARGET = re.compile(r"^(?P<title>.*?)\s*<(?P<target>[^<>]+)>$", flags=re.DOTALL)


def rewrite(text, resolve):
    """``text`` with its roles as optional autorefs references (``resolve(name)``: the full path of ``name``, or
    ``None`` where it names nothing known: then a code span)."""

    def one(match):
        titled = TARGET.match(match["body"])
        body = "".join(match["body"].split())  # a role broken over lines (a name has no spaces, a title single ones)
        target = "".join(titled["target"].split()) if titled else body
        short = target.startswith("~")
        target = target.lstrip("~").removesuffix("()")
        title = " ".join(titled["title"].split()) if titled else target.rsplit(".", 1)[-1] if short else target
        title += "()" if not titled and body.endswith("()") and not title.endswith("()") else ""
        path = resolve(target)
        code = f"`{title}`" if "`" not in title else title
        if path is None:
            return code
        return f'<autoref identifier="{html.escape(path)}" optional>{code}</autoref>'

    return ROLE.sub(one, text)


def resolver(obj, package):
    """``resolve(name)`` of :func:`rewrite` for the docstring of ``obj``: a full path of ``package`` if it is one of
    its objects, else the name in ``obj``'s scope (its first part resolved, the rest appended)."""

    def resolve(name):
        if name == package.path or name.startswith(package.path + "."):
            try:
                package[name[len(package.path) + 1:]] if name != package.path else package
            except (KeyError, griffe.AliasResolutionError, griffe.CyclicAliasError):
                return None
            return name
        head, _, rest = name.partition(".")
        try:
            found = obj.resolve(head)
        except (griffe.NameResolutionError, griffe.AliasResolutionError, griffe.CyclicAliasError):
            return None
        return f"{found}.{rest}" if rest else found

    return resolve


def _objects(obj):
    """``obj`` and every object it holds (not its aliases: their docstrings are their targets')."""
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _objects(member)


class SphinxRoles(griffe.Extension):
    """Rewrites the roles of every docstring of a package once it is loaded (:func:`rewrite`)."""

    def on_package(self, *, pkg, **kwargs):
        for obj in _objects(pkg):
            if obj.docstring is not None and ":" in obj.docstring.value:
                obj.docstring.value = rewrite(obj.docstring.value, resolver(obj, pkg))
