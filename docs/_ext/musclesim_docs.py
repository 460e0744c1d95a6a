"""Sphinx directives of the musclesim docs: tables derived from the code, so that the docs show
what the code declares and cannot drift from it.

    ```{fmu-variables} CrawlerBody
    ```

a component's FMU variables (parameters, inputs, outputs: name, unit, or type if not Real,
default or start, description and source, and a parameter's role for the diagnosis), as the
component declares them (`musclesim.components.declarations`, what `musclesim build` writes into
the FMU's modelDescription.xml);

    ```{effect-library}
    ```

the diagnosis's effects and calibration parameters (`musclesim.diagnosis.effects`);

    ```{cli-help} run
    ```

what ``musclesim run --help`` prints (no argument: ``musclesim --help``).
A ``§label`` in a table's text becomes a link to that section of the docs.
"""
import re

from docutils import nodes
from sphinx import addnodes
from sphinx.util.docutils import SphinxDirective

CITATION = re.compile(r"§([a-z][a-z0-9-]*[a-z0-9])")


def _linked(text, docname):
    """`text` as nodes, each ``§label`` citation a link to its section of the docs."""
    out, at = [], 0
    for m in CITATION.finditer(text):
        out.append(nodes.Text(text[at:m.start()]))
        ref = addnodes.pending_xref("", refdomain="std", reftype="ref", reftarget=m.group(1),
                                    refexplicit=True, refwarn=True, refdoc=docname)
        ref += nodes.inline(text=m.group(0))
        out.append(ref)
        at = m.end()
    out.append(nodes.Text(text[at:]))
    return out


def _cell(text, docname, literal=False):
    entry = nodes.entry()
    para = nodes.paragraph()
    if literal:
        para += nodes.literal(text=text)
    else:
        para.extend(_linked(text, docname))
    entry += para
    return entry


def _table(title, header, rows, docname, widths=None):
    table = nodes.table(classes=["musclesim-table"])
    table += nodes.title(text=title)
    group = nodes.tgroup(cols=len(header))
    table += group
    for width in widths or ((22, 8, 10, 60) if len(header) == 4 else (22, 8, 70)):
        group += nodes.colspec(colwidth=width)
    head, body = nodes.thead(), nodes.tbody()
    group += head
    group += body
    for cells, parent in [(header, head)] + [(r, body) for r in rows]:
        row = nodes.row()
        for i, text in enumerate(cells):
            row += _cell(text, docname, literal=(i == 0 and parent is body))
        parent += row
    return table


def _bounds(lo, hi, relative):
    return f"{lo:g}x to {hi:g}x" if relative else f"{lo:+g} to {hi:+g}"


def _role(d):
    """A parameter's role for the diagnosis, in words ("" for none)."""
    if d.effect:
        return f"effect, off at the default; fitted within {d.effect[0]:g} to {d.effect[1]:g}"
    c = d.calibrate
    if c:
        return (f"calibrated within {_bounds(c.lower, c.upper, c.relative)}"
                + (f", period {c.period:g}" if c.period else "") + f": {c.why}")
    return ""


class FmuVariables(SphinxDirective):
    """The parameters, inputs and outputs of the component named in the argument."""

    required_arguments = 1

    def run(self):
        from musclesim.components import CATALOGUE, declarations

        name = self.arguments[0]
        if name not in CATALOGUE:
            raise self.error(f"fmu-variables: no component {name!r} in the catalogue")
        out = []
        for causality, title, column in (("parameter", "parameters", "default"),
                                         ("input", "inputs", "start"), ("output", "outputs", None)):
            rows = []
            for d in declarations(name).values():
                if d.causality != causality:
                    continue
                text = " ".join(t for t in (d.description, d.source and f"({d.source})",
                                            _role(d) and f"Diagnosis: {_role(d)}.") if t)
                # an Integer or Boolean variable has no unit but its type
                unit = d.unit if d.type == "Real" else d.type
                default = f"{d.default:.6g}" if d.type != "Boolean" else \
                    ("true" if d.default else "false")
                rows.append((d.name, unit, default, text) if column else (d.name, unit, text))
            if rows:
                header = ("name", "unit or type", column, "description") if column else \
                    ("name", "unit or type", "description")
                out.append(_table(f"{name}: {title}", header, rows, self.env.docname))
        return out


class EffectLibrary(SphinxDirective):
    """The effects the diagnosis can add, and the calibration parameters it fits first."""

    def run(self):
        from musclesim.diagnosis import REGIMES
        from musclesim.diagnosis.effects import CALIBRATION, EFFECTS

        doc = self.env.docname
        effects = [(e.name, e.component, ", ".join(
            f"{p.name} (off {p.off:g}; {p.lower:g} to {p.upper:g})" for p in e.parameters)
            + (" per instance" if e.per_instance else ""),
            f"{e.description}; shows where {REGIMES[e.regime]} ({e.reference})")
            for e in EFFECTS]
        calibrated = [(f"{c.component}.{c.name}", _bounds(c.lower, c.upper, c.relative)
                       + (f", period {c.period:g}" if c.period else ""), f"{c.why} ({c.reference})")
                      for c in CALIBRATION]
        return [_table("Effects", ("effect", "component", "parameters", "what and where"),
                       effects, doc, widths=(18, 14, 28, 40)),
                _table("Calibration parameters", ("component.parameter", "bounds", "why"),
                       calibrated, doc, widths=(26, 20, 54))]


class CliHelp(SphinxDirective):
    """The command line's own help of one command, as a literal block."""

    optional_arguments = 2  # a command, and its action (dataset check)

    def run(self):
        import contextlib
        import io
        import os

        from musclesim import cli

        text = io.StringIO()
        os.environ["COLUMNS"] = "100"  # argparse wraps to the terminal's width
        with contextlib.redirect_stdout(text), contextlib.suppress(SystemExit):
            cli.main([*self.arguments, "--help"])
        block = nodes.literal_block(text.getvalue(), text.getvalue())
        block["language"] = "text"
        return [block]


def setup(app):
    app.add_directive("fmu-variables", FmuVariables)
    app.add_directive("effect-library", EffectLibrary)
    app.add_directive("cli-help", CliHelp)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
